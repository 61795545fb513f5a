// The table of input formats (host_adapters/inputs): a file's format is told
// by its XML root element before its extension, what no format takes is
// refused naming the formats there are, and the CLI and libmbx_files open
// files through it.
#include <cstdio>
#include <string>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "host_adapters/common/file_error.h"
#include "host_adapters/inputs/input_formats.h"
#include "tiny_pmxml.h"

namespace MBX_UNITY_ID {

using mbx_files::input_format_of;

namespace {

std::string run_cli(const std::string& args, int& status) {
    std::string out;
    FILE* p = popen((std::string(MBX_CLI_PATH) + " " + args + " 2>&1").c_str(), "r");
    REQUIRE(p != nullptr);
    char buffer[4096];
    for (size_t n; (n = fread(buffer, 1, sizeof buffer, p)) > 0;) out.append(buffer, n);
    status = pclose(p);
    return out;
}

}  // namespace

TEST_CASE("input formats: the root element names the format before the extension") {
    atest::TempDir dir("mbx_input_formats");
    const std::string pmxml = atest::tiny_pmxml();
    atest::write_file(dir.file("arm.xml"), pmxml);
    // The same export under a name that says nothing, after a byte order
    // mark, comments, a processing instruction and a DOCTYPE with a subset.
    const size_t root = pmxml.find("<PhysicalModelingXMLFile");
    REQUIRE(root != std::string::npos);
    atest::write_file(dir.file("export.dat"), "\xEF\xBB\xBF<?xml version=\"1.0\"?>\n<!-- exported -->\n<?app x?>\n"
                                              "<!DOCTYPE m [ <!ENTITY a \"b\"> ]>\n" + pmxml.substr(root));
    atest::write_file(dir.file("other.xml"), "<?xml version=\"1.0\"?><scene name=\"r\"/>");
    atest::write_file(dir.file("notes.txt"), "not a model");

    const mbx_files::InputFormat* f = input_format_of(dir.file("arm.xml"));
    REQUIRE(f != nullptr);
    CHECK(std::string(f->name) == "pmxml");
    const mbx_files::InputFormat* g = input_format_of(dir.file("export.dat"));
    REQUIRE(g != nullptr);
    CHECK(std::string(g->name) == "pmxml");
    // An XML root no format claims falls to the extension's format, whose
    // reader then says what is wrong with the file.
    const mbx_files::InputFormat* o = input_format_of(dir.file("other.xml"));
    REQUIRE(o != nullptr);
    CHECK(std::string(o->name) == "pmxml");
    CHECK_THROWS_AS(mbx_files::open_input(dir.file("other.xml")), mbx_files::FileError);
    // Neither a known root nor a known extension, or no file at all.
    CHECK(input_format_of(dir.file("notes.txt")) == nullptr);
    CHECK(input_format_of("fourbar") == nullptr);
    try {
        mbx_files::open_input(dir.file("notes.txt"));
        FAIL("a text file was opened as a model");
    } catch (const mbx_files::FileError& e) {
        CHECK(e.file() == dir.file("notes.txt"));
        CHECK(e.message().find("*.xml") != std::string::npos);
    }

    // Opened through the table, the renamed export serves the same model.
    const auto a = mbx_files::open_input(dir.file("arm.xml"));
    const auto b = mbx_files::open_input(dir.file("export.dat"));
    REQUIRE(a->table() != nullptr);
    REQUIRE(b->table() != nullptr);
    CHECK(a->table()->struct_size == b->table()->struct_size);
}

TEST_CASE("input formats: every entry is complete and the CLI lists it") {
    REQUIRE(!mbx_files::input_formats().empty());
    int status = -1;
    const std::string listed = run_cli("formats", status);
    CHECK(status == 0);
    for (const mbx_files::InputFormat& f : mbx_files::input_formats()) {
        CHECK(bool(f.open));
        CHECK(!f.extensions.empty());
        for (const std::string& e : f.extensions) CHECK((e.size() > 1 && e[0] == '.'));
        CHECK(listed.find(std::string(f.name)) != std::string::npos);
        CHECK(listed.find(f.description) != std::string::npos);
    }
    // A file the table does not take is refused by the CLI with the way to
    // see what it takes.
    atest::TempDir dir("mbx_input_formats_cli");
    atest::write_file(dir.file("notes.txt"), "not a model");
    const std::string refused = run_cli("translate " + dir.file("notes.txt") + " -o " + dir.file("out"), status);
    CHECK(status != 0);
    CHECK(refused.find("mbx formats") != std::string::npos);
}
}  // namespace MBX_UNITY_ID
