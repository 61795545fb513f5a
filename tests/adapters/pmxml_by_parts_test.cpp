// Reading a PMXML file by parts (an outline, then each part on its own) must
// give exactly what reading it as one pugixml DOM gives: the same model field
// for field, the same diagnostics, the same error at the same line. Real
// exports, the samples and generated assemblies take the fast way; what the
// outline does not take (references, comments, CDATA, carriage returns in
// text, other encodings, anything malformed) goes to the DOM.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "samples/tools/generate_pmxml.h"
#include "host_adapters/pmxml_vrml/pmxml_outline.h"
#include "host_adapters/pmxml_vrml/pmxml_reader.h"
#include "tiny_pmxml.h"

namespace MBX_UNITY_ID {

using namespace mbx_files;

namespace {

using mbx_test::read_file;

// What reading `text` gives: the model, or the error's text.
struct Outcome {
    bool ok = false;
    PmxmlModel model;
    std::string error;
    PmxmlParse used = PmxmlParse::automatic;
};

Outcome read_as(const std::string& text, PmxmlParse how) {
    Outcome o;
    try {
        o.model = parse_pmxml(text, "t.xml", how, &o.used);
        o.ok = true;
    } catch (const FileError& e) {
        o.error = e.what();
    }
    return o;
}

// Both ways agree on `text`; returns the way the automatic read took.
PmxmlParse same_both_ways(const std::string& text) {
    const Outcome fast = read_as(text, PmxmlParse::automatic);
    const Outcome dom = read_as(text, PmxmlParse::whole_dom);
    REQUIRE(dom.used == PmxmlParse::whole_dom);
    REQUIRE_MESSAGE(fast.ok == dom.ok, (fast.ok ? "by parts read it, the DOM refused: " + dom.error
                                                : "the DOM read it, by parts refused: " + fast.error));
    if (dom.ok) {
        const std::string difference = first_difference(fast.model, dom.model);
        REQUIRE_MESSAGE(difference.empty(), "differs in " << difference);
    } else {
        REQUIRE(fast.error == dom.error);
        REQUIRE(fast.used == PmxmlParse::whole_dom);  // errors always come from the DOM
    }
    return fast.used;
}

std::string replace_first(std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    REQUIRE_MESSAGE(at != std::string::npos, "'" << from << "' not in the text");
    return text.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("pmxml by parts: first_difference names the field that differs") {
    const PmxmlModel a = parse_pmxml(atest::tiny_pmxml(), "tiny.xml");
    PmxmlModel b = a;
    CHECK(first_difference(a, b).empty());
    b.frames[3].position.y() = std::nextafter(b.frames[3].position.y(), 1e9);
    CHECK(first_difference(a, b) == "frames[3].position");
    b = a;
    b.joints[1].primitives[0].line += 1;
    CHECK(first_difference(a, b) == "joints[1].primitives[0].line");
    b = a;
    b.diagnostics.push_back({});
    CHECK(first_difference(a, b).rfind("diagnostics count", 0) == 0);
}

TEST_CASE("pmxml by parts: the real exports, the samples and a generated assembly are read by parts, as the DOM reads them") {
    std::vector<std::string> files;
    if (const std::string dir = atest::pmxml_data_dir(); !dir.empty())
        for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
            if (e.path().extension() == ".xml") files.push_back(e.path().string());
    for (const char* sample : {"emps_axis/emps_axis.xml", "fourbar_imperial/fourbar.xml", "five_axis_arm/five_axis_arm.xml",
                               "joints_showcase/joints_showcase.xml", "double_cardan/double_cardan.xml"})
        files.push_back(std::string(MBX_SAMPLES_DIR) + "/" + sample);
    atest::TempDir dir;
    mbx_samples::GeneratorOptions options;
    options.parts = 1500;
    options.digits = 6;
    files.push_back(mbx_samples::generate_pmxml(dir.path.string(), "generated", options).xml_path);
    CHECK(files.size() >= 6);
    for (const std::string& f : files) {
        CAPTURE(f);
        CHECK(same_both_ways(read_file(f)) == PmxmlParse::by_parts);
        // read_pmxml maps the file rather than reading it: the same model.
        PmxmlParse used = PmxmlParse::automatic;
        const PmxmlModel mapped = read_pmxml(f, PmxmlParse::automatic, &used);
        CHECK(used == PmxmlParse::by_parts);
        CHECK(first_difference(mapped, read_pmxml(f, PmxmlParse::whole_dom)).empty());
    }
}

TEST_CASE("pmxml by parts: what the outline does not take is read by the DOM, with the same result") {
    const std::string tiny = atest::tiny_pmxml();
    REQUIRE(same_both_ways(tiny) == PmxmlParse::by_parts);
    const size_t first_name = tiny.find("<name>");
    REQUIRE(first_name != std::string::npos);
    struct Case {
        const char* what;
        std::string text;
    };
    std::string crlf;
    for (char c : tiny) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    const std::vector<Case> cases = {
        {"a character reference in a name", replace_first(tiny, "\"ARM\"", "\"A&#82;M\"")},
        {"a comment", std::string(tiny).insert(first_name, "<!-- exported -->")},
        {"a processing instruction", std::string(tiny).insert(first_name, "<?app data?>")},
        {"a byte-order mark", "\xEF\xBB\xBF" + tiny},
        {"a Latin-1 declaration", replace_first(tiny, "encoding=\"UTF-8\"", "encoding=\"ISO-8859-1\"")},
        {"a tab in a ref", replace_first(tiny, " ref=\"", " ref=\"\t")},
    };
    for (const Case& c : cases) {
        CAPTURE(std::string(c.what));
        CHECK(same_both_ways(c.text) == PmxmlParse::whole_dom);
    }
    // Windows line ends only between tags: pugixml drops that blank text, so
    // such a file is still read by parts.
    CHECK(same_both_ways(crlf) == PmxmlParse::by_parts);
    // A line end inside a value is converted by pugixml: the DOM reads it.
    CHECK(same_both_ways(replace_first(crlf, "\"ARM\"", "\"A\r\nRM\"")) == PmxmlParse::whole_dom);
}

TEST_CASE("pmxml by parts: mutants of the tiny model and a real export agree both ways") {
    std::vector<std::string> originals = {atest::tiny_pmxml()};
    if (const std::string dir = atest::pmxml_data_dir(); !dir.empty())
        originals.push_back(read_file(dir + "/legs_mechanism_2014/LEGS_MECHANISM.xml"));
    atest::Mutator mutator(0x2545f4914f6cdd1dull);
    // Tokens that move a file between the two ways or into its corners.
    const char* tokens[] = {"<", ">", "/", "\"", "'", "=", " ", "\n", "\r", "\t", "&amp;", "&lt;", "<!-- c -->",
                            "<![CDATA[x]]>", "<?pi x?>", "<Body>", "</Body>", "<Frame ref=\"7\"/>", "</bodies>",
                            "<name>\"n\"</name>", "</SimpleJoint >", "<x a='1' b=\"2\"/>", "\xC3\xA9", "WORLD"};
    int by_parts = 0, dom = 0;
    for (int round = 0; round < 1500; ++round) {
        // The caller's edit: duplicate a stretch (a part or half of one) elsewhere.
        const std::string text = mutator.mutate(originals[size_t(round) % originals.size()], tokens, 3, 30,
                                                [&](std::string& t, size_t at) {
                                                    const size_t n = std::min<size_t>(t.size() - at, 1 + mutator.next() % 400);
                                                    t.insert(size_t(mutator.next() % t.size()), t.substr(at, n));
                                                });
        CAPTURE(round);
        (same_both_ways(text) == PmxmlParse::by_parts ? by_parts : dom) += 1;
    }
    MESSAGE(by_parts << " mutants read by parts, " << dom << " by the DOM");
    CHECK(by_parts > 100);
    CHECK(dom > 100);
}

TEST_CASE("pmxml outline: the elements around the parts, and parts as whole spans") {
    const std::string text =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<R a=\"1\"><M><name>\"m\"</name><bodies>\n"
        "<Body x='y'><name>\"b\"</name><q><Body/></q></Body>\n</bodies><joints><SimpleJoint/></joints></M></R>\n";
    PmxmlOutline o;
    REQUIRE(outline_pmxml(text, o));
    const int m = o.child(o.root, "M");
    REQUIRE(m >= 0);
    CHECK(o.elements[size_t(o.child(m, "name"))].text == "\"m\"");
    const OutlineElement& body = o.elements[size_t(o.elements[size_t(o.child(m, "bodies"))].first_child)];
    CHECK(body.is_part());
    CHECK(text.substr(body.part_begin, body.part_end - body.part_begin) ==
          "<Body x='y'><name>\"b\"</name><q><Body/></q></Body>");
    CHECK(body.offset == text.find("Body x="));
    const OutlineElement& joint = o.elements[size_t(o.elements[size_t(o.child(m, "joints"))].first_child)];
    CHECK(text.substr(joint.part_begin, joint.part_end - joint.part_begin) == "<SimpleJoint/>");
    // Not taken: a second root, text outside the root, a mismatched end tag.
    CHECK_FALSE(outline_pmxml(text + "<R/>", o));
    CHECK_FALSE(outline_pmxml("x" + text.substr(text.find("<R")), o));
    CHECK_FALSE(outline_pmxml(atest::replace_once(text, "</M>", "</N>"), o));
}
}  // namespace MBX_UNITY_ID
