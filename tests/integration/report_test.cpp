// Reports: written atomically (only the two final files remain, no
// temporaries), valid JSON with the documented sections, and byte-identical
// across runs so they can be diffed and cached.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/json_check.h"
#include "support/temp_dir.h"
#include "support/plugin_fixture.h"
#include "../common/file_text.h"

namespace MBX_UNITY_ID {

using namespace itest;
namespace fs = std::filesystem;

namespace {

using mbx_test::read_file;

std::vector<std::string> entries(const fs::path& dir) {
    std::vector<std::string> names;
    if (!fs::exists(dir)) return names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

mbx_status write_report(const std::string& name, const fs::path& dir) {
    const Run r = translate_builtin(name);
    REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
    const mbx_status status = api().mechanism_write_report(r.context.get(), r.get(), dir.string().c_str());
    if (status != MBX_OK) MESSAGE(std::string(api().context_last_error(r.context.get())));
    return status;
}

}  // namespace

TEST_CASE("report: valid JSON with the documented sections, only the final files left") {
    for (const auto& name : mbx_stub::builtin_names()) {
        INFO("builtin " << name);
        TempDir dir;
        const fs::path nested = dir.path / "created" / "on demand";
        REQUIRE(write_report(name, nested) == MBX_OK);
        CHECK(entries(nested) == std::vector<std::string>{"report.json", "report.txt"});

        const std::string json = read_file(nested / "report.json");
        const JsonCheck check = check_json(json);
        REQUIRE_MESSAGE(check.ok, check.error);
        for (const char* key : {"bodies", "joints", "loops", "findings"})
            CHECK_MESSAGE(check.top_keys.count(key) == 1, "missing top-level key " << key);
        CHECK(json.find(name) != std::string::npos);  // the model is named (describe_assembly)
        CHECK(!read_file(nested / "report.txt").empty());
    }
}

TEST_CASE("report: two runs give byte-identical files") {
    for (const auto& name : mbx_stub::builtin_names()) {
        INFO("builtin " << name);
        TempDir one, two;
        REQUIRE(write_report(name, one.path) == MBX_OK);
        REQUIRE(write_report(name, two.path) == MBX_OK);
        CHECK(read_file(one.path / "report.json") == read_file(two.path / "report.json"));
        CHECK(read_file(one.path / "report.txt") == read_file(two.path / "report.txt"));
        // Rewriting in place replaces the files whole.
        REQUIRE(write_report(name, one.path) == MBX_OK);
        CHECK(read_file(one.path / "report.json") == read_file(two.path / "report.json"));
        CHECK(entries(one.path) == std::vector<std::string>{"report.json", "report.txt"});
    }
}

TEST_CASE("report: an unwritable destination is MBX_ERROR_IO and leaves nothing behind") {
    TempDir dir;
    const fs::path blocker = dir.path / "not_a_directory";
    std::ofstream(blocker) << "a file where the report directory should be";
    CHECK(write_report("fourbar", blocker) == MBX_ERROR_IO);
    CHECK(write_report("fourbar", blocker / "below") == MBX_ERROR_IO);
    CHECK(entries(dir.path) == std::vector<std::string>{"not_a_directory"});
}
}  // namespace MBX_UNITY_ID
