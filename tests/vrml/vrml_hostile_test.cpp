// Hostile and broken input: every case must end in a VrmlError naming the
// file and line, never a crash, a hang or an unbounded allocation.
#include <chrono>
#include <functional>

#include <pthread.h>

#include <doctest/doctest.h>

#include "vrml_test_support.h"

namespace MBX_UNITY_ID {

using mbx_files::read_vrml;
using mbx_files::read_vrml_text;
using mbx_files::VrmlError;
using mbx_files::VrmlLimits;
using vrml_test::check_error;
using vrml_test::read_written;
using vrml_test::TempDir;
using vrml_test::vrml;

namespace {

// Hostile inputs are written to h.wrl in a scratch directory and read from there.
const std::string file = "h.wrl";

void check_text_error(const std::string& text, int line, const std::string& fragment, const VrmlLimits& limits = {}) {
    check_error([&] { read_written(text, file, limits); }, file, line, fragment);
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string nested_groups(size_t depth) {
    std::string s = "#VRML V2.0 utf8\n";
    s.reserve(s.size() + depth * 20);
    for (size_t i = 0; i < depth; ++i) s += "Group { children [\n";
    return s;
}

}  // namespace

TEST_CASE("nesting a million levels deep stops at max_depth, without deep recursion") {
    // Group k sits on line k + 2; the one at depth 256 is the first too deep.
    check_text_error(nested_groups(1000000), 258, "nodes nested deeper than max_depth (256)");
    VrmlLimits shallow;
    shallow.max_depth = 3;
    check_text_error(nested_groups(10), 5, "nested deeper than max_depth (3)", shallow);
}

TEST_CASE("whatever max_depth allows, the stack left bounds the recursion") {
    VrmlLimits unbounded;
    unbounded.max_depth = size_t(1) << 40;
    auto check_stack_error = [](const std::function<void()>& read) {
        try {
            read();
            FAIL("no VrmlError");
        } catch (const VrmlError& e) {
            INFO(std::string(e.what()));
            CHECK(ends_with(e.file(), "/" + file));
            CHECK(e.line() > 258);
            CHECK(std::string(e.what()).find("nested too deeply for the stack left to the reader") !=
                  std::string::npos);
        }
    };
    // While parsing: a million nested Groups.
    check_stack_error([&] { read_written(nested_groups(1000000), file, unbounded); });
    // While building: 20000 PROTOs, each one Group deeper than the last,
    // parse shallow but expand 40000 levels deep.
    std::string text = vrml("PROTO P0 [ ] { Group { } }\n");
    for (int k = 1; k < 20000; ++k)
        text += "PROTO P" + std::to_string(k) + " [ ] { Group { children P" + std::to_string(k - 1) + " { } } }\n";
    text += "P19999 { }\n";
    check_stack_error([&] { read_written(text, file, unbounded); });
}

namespace {

struct ThreadRead {
    std::string text;
    VrmlLimits limits;
    std::string error;
};

void* read_on_thread(void* arg) {
    auto* job = static_cast<ThreadRead*>(arg);
    try {
        read_vrml_text(job->text, file, job->limits);  // no test assertions off the main thread
    } catch (const VrmlError& e) {
        job->error = e.what();
    }
    return nullptr;
}

}  // namespace

TEST_CASE("a thread with a small stack gets an error, not an overflow") {
    ThreadRead job{nested_groups(100000), {}, {}};
    job.limits.max_depth = size_t(1) << 40;
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, 1024 * 1024);
    pthread_t thread;
    REQUIRE(pthread_create(&thread, &attr, read_on_thread, &job) == 0);
    pthread_join(thread, nullptr);
    pthread_attr_destroy(&attr);
    INFO(job.error);
    CHECK(job.error.find("nested too deeply for the stack left to the reader") != std::string::npos);
}

TEST_CASE("PROTO expansion counts towards max_depth") {
    // P_k (line k + 2) wraps an instance of P_(k-1); instantiating P299 nests
    // 300 levels. Depth d holds the P_(299-d) instance in the body of P_(300-d).
    std::string text = vrml("PROTO P0 [ ] { Group { } }\n");
    for (int k = 1; k < 300; ++k)
        text += "PROTO P" + std::to_string(k) + " [ ] { P" + std::to_string(k - 1) + " { } }\n";
    text += "P299 { }\n";
    check_text_error(text, 46, "nested deeper than max_depth (256), counting Inlines and PROTO expansion");
}

TEST_CASE("Inline cycles are found by canonical path") {
    const TempDir dir;
    const std::string a = dir.write("a.wrl", vrml("\nInline { url \"b.wrl\" }\n"));
    dir.write("b.wrl", vrml("\n\nTransform { children Inline { url \"sub/../a.wrl\" } }\n"));
    dir.write("sub/keep.txt", "");
    check_error([&] { read_vrml(a); }, "b.wrl", 4, "Inline cycle: a.wrl -> b.wrl -> a.wrl");

    const std::string self = dir.write("self.wrl", vrml("Group { children [\n  Inline { url \"./self.wrl\" } ] }\n"));
    check_error([&] { read_vrml(self); }, "self.wrl", 3, "Inline cycle: self.wrl -> self.wrl");
}

TEST_CASE("Inline chains deeper than max_inline_depth are refused") {
    const TempDir dir;
    for (int k = 0; k < 20; ++k)
        dir.write("f" + std::to_string(k) + ".wrl", vrml("Inline { url \"f" + std::to_string(k + 1) + ".wrl\" }\n"));
    check_error([&] { read_vrml(dir.path() + "/f0.wrl"); }, "f16.wrl", 2,
                "Inlines nested deeper than max_inline_depth (16)");
}

TEST_CASE("max_total_values and max_nodes bound what is read") {
    VrmlLimits few_values;
    few_values.max_total_values = 10;
    check_text_error(vrml("\nCoordinate { point [ 1 2 3\n 4 5 6\n 7 8 9\n 10 11 12 ] }\n"), 6,
                     "more than max_total_values (10) values", few_values);
    VrmlLimits few_nodes;
    few_nodes.max_nodes = 5;
    check_text_error(vrml("Group {}\nGroup {}\nGroup {}\nGroup {}\nGroup {}\nGroup {}\n"), 7,
                     "more than max_nodes (5) nodes", few_nodes);
}

TEST_CASE("exponential USE expansion ends at max_nodes, quickly") {
    std::string text = vrml("DEF L0 Group { children Shape { geometry Box { } } }\n");
    for (int k = 1; k <= 60; ++k)
        text += "DEF L" + std::to_string(k) + " Group { children [ USE L" + std::to_string(k - 1) + " USE L" +
                std::to_string(k - 1) + " ] }\n";
    VrmlLimits limits;
    limits.max_nodes = 100000;
    const auto start = std::chrono::steady_clock::now();
    try {
        read_written(text, file, limits);
        FAIL("2^60 nodes were accepted");
    } catch (const VrmlError& e) {
        CHECK(std::string(e.what()).find("more than max_nodes (100000)") != std::string::npos);
        CHECK(ends_with(e.file(), "/" + file));
        CHECK(e.line() >= 2);
    }
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(10));

    // The same with one big mesh used many times is bounded by the values it emits.
    std::string big = vrml("DEF S Shape { geometry Sphere { } }\n");
    for (int k = 0; k < 2000; ++k) big += "Transform { children USE S }\n";
    VrmlLimits mesh_values;
    mesh_values.max_total_values = 100000;
    check_error([&] { read_written(big, file, mesh_values); }, file, 2,
                "more than max_total_values (100000) values, counting the meshes built");
}

TEST_CASE("coordIndex must name existing vertices") {
    const std::string head =
        "\nGroup { children Shape { geometry IndexedFaceSet {\n"
        "  coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] }\n"
        "  coordIndex [ 0 1 2 -1\n";
    check_text_error(vrml(head + "   0 1 3 -1 ] } } }\n"), 6,
                     "coordIndex 3 refers to a vertex that does not exist (the Coordinate has 3 points)");
    check_text_error(vrml(head + "   0 -2 1 ] } } }\n"), 6, "coordIndex -2 is not a vertex index");
    check_text_error(vrml(head + "   0 1.5 1 ] } } }\n"), 6, "coordIndex 1.5 is not an integer");
    check_text_error(vrml(head + "   0 99999999999 1 ] } } }\n"), 6, "coordIndex 99999999999 refers to a vertex");
    check_text_error(
        vrml("\nShape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0 1 ] } coordIndex [ 0 0 0 ] } }\n"),
        3, "Coordinate.point: 4 numbers are not whole 3D points");
}

TEST_CASE("truncated files: end of file inside a node, a string, brackets, a PROTO") {
    check_text_error(vrml("\nGroup { children [ Transform {\n translation 1 2 3\n"), 5,
                     "unexpected end of file inside 'Transform' node opened at line 3");
    check_text_error(vrml("\nWorldInfo { title \"abc\n def\n"), 3, "unterminated string");
    check_text_error(vrml("\nGroup { children [ Shape { geometry IndexedFaceSet { coordIndex [ 0 1 2\n 3 4"), 4,
                     "unexpected end of file inside '[' opened at line 3");
    check_text_error(vrml("\nPROTO A [ field SFFloat x 1\n"), 4,
                     "unexpected end of file in the interface of PROTO 'A'");
    check_text_error(vrml("\nPROTO A [ ] { Group { }\n"), 4, "unexpected end of file inside the body of PROTO 'A'");
    check_text_error(vrml("\nDEF"), 3, "expected a name after DEF, found end of file");
    check_text_error(vrml("\nTransform { translation"), 3, "expected a field value, found end of file");
    check_text_error("", 1, "not a VRML97 file: the first line must be '#VRML V2.0 utf8'");
    check_text_error("#VRML V2", 1, "unsupported VRML version");
    check_text_error("VRML V2.0 utf8\n", 1, "not a VRML97 file");
}

TEST_CASE("binary junk, NaN and infinity") {
    check_text_error(vrml("\nGroup {\n\x01\x02\xff }\n"), 4, "unexpected byte 0x01 (binary data?)");
    check_text_error(vrml(std::string("Group { children [ \0 ] }", 24)), 2, "unexpected byte 0x00");
    check_text_error(vrml("\nGroup { children [ \xff\xfe\x80 ] }\n"), 3, "expected '{' after node type");
    check_text_error(vrml("\nTransform { translation 1 nan 3 }\n"), 3, "non-finite number 'nan'");
    check_text_error(vrml("\nTransform {\n translation 1 2 1e999 }\n"), 4, "number out of range '1e999'");
    check_text_error(vrml("\nTransform { translation 1 2 -inf }\n"), 3, "malformed number '-inf'");
    check_text_error(vrml("\nCoordinate { point [ 1 2 Infinity ] }\n"), 3, "non-finite number 'Infinity'");
    check_text_error(vrml("\nTransform { translation 1.2.3 0 0 }\n"), 3, "malformed number '1.2.3'");
    check_text_error(vrml("\nTransform { translation 0x 0 0 }\n"), 3, "malformed number '0x'");
    // Denormals and underflow are ordinary (tiny) numbers.
    CHECK_NOTHROW(read_written(vrml("Transform { translation 1e-400 4.9e-324 0 }\n"), file));
}

TEST_CASE("USE of an undefined DEF, including a node's own name inside itself") {
    check_text_error(vrml("\nGroup { children [\n USE NOPE ] }\n"), 4, "USE of undefined DEF 'NOPE'");
    check_text_error(vrml("\nDEF A Group { children [\n USE A ] }\n"), 4, "USE of undefined DEF 'A'");
    // DEF names inside a PROTO body are local to it.
    check_text_error(vrml("PROTO P [ ] { DEF INSIDE Group { } }\nP { }\nUSE INSIDE\n"), 4,
                     "USE of undefined DEF 'INSIDE'");
}

TEST_CASE("recursive PROTO instantiation") {
    check_text_error(vrml("\nPROTO R [ ] {\n Group { children R { } }\n}\n"), 4,
                     "PROTO 'R' is instantiated inside its own body (recursive PROTO)");
    check_text_error(vrml("PROTO A [ ] {\n PROTO B [ ] { A { } }\n B { }\n}\n"), 3,
                     "PROTO 'A' is instantiated inside its own body");
    check_text_error(vrml("PROTO A [ field SFFloat x 1 ] {\n Transform { translation IS y } }\n"), 3,
                     "IS refers to 'y', which PROTO 'A' does not declare");
    check_text_error(vrml("\nTransform { translation IS x }\n"), 3, "IS outside a PROTO body");
}

TEST_CASE("other VRML versions and encodings are refused by name") {
    check_text_error("#VRML V1.0 ascii\nSeparator { }\n", 1, "VRML V1.0 is not supported");
    check_text_error("#VRML V3.0 utf8\n", 1, "unsupported VRML version in header '#VRML V3.0 utf8'");
    check_text_error("#X3D V3.0 utf8\n", 1, "X3D classic encoding");
    check_text_error(std::string("\x1f\x8b\x08\x00", 4), 1, "gzip-compressed");
    CHECK_NOTHROW(read_written("\xEF\xBB\xBF#VRML V2.0 utf8\r\nGroup { }\r\n", file));
}

TEST_CASE("fields of the wrong type and syntax errors") {
    check_text_error(vrml("\nTransform { translation \"x\" }\n"), 3,
                     "Transform.translation: expected 3 numbers, found 1 string(s)");
    check_text_error(vrml("\nTransform {\n rotation 0 1 0 }\n"), 4, "Transform.rotation: expected 4 numbers");
    check_text_error(vrml("\nGroup { children 1 2 3 }\n"), 3, "Group.children: expected nodes, found 3 number(s)");
    check_text_error(vrml("\nGroup { children [ Group { } ] ] }\n"), 3,
                     "expected a field name or '}' in 'Group' node, found ']'");
    check_text_error(vrml("\nGroup { children [ 1 \"a\" ] }\n"), 3, "list mixes numbers and strings");
    check_text_error(vrml("\nGroup { children [ [ ] ] }\n"), 3, "unexpected '[' in list");
    check_text_error(vrml("\nGroup }\n"), 3, "expected '{' after node type 'Group', found '}'");
    check_text_error(vrml("\n}\n"), 3, "expected a node, found '}'");
    check_text_error(vrml("\nShape { geometry Box { size 1 -2 3 } }\nShape { geometry Cone { side \"yes\" } }\n"), 4,
                     "Cone.side: expected TRUE or FALSE");
    check_text_error(vrml("\nROUTE A.b B.c\n"), 3, "malformed ROUTE: expected TO");
    check_text_error(vrml("\nShape { geometry IndexedFaceSet { coord Group { } coordIndex [ 0 1 2 ] } }\n"), 3,
                     "IndexedFaceSet.coord must be a Coordinate node, found 'Group'");
}

TEST_CASE("unreadable and oversized files") {
    check_error([] { read_vrml("/nonexistent/missing.wrl"); }, "missing.wrl", 0, "no such file");
    const TempDir dir;
    VrmlLimits tiny;
    tiny.max_file_bytes = 60;
    const std::string big = dir.write("big.wrl", vrml(std::string(100, '\n')));
    check_error([&] { read_vrml(big, tiny); }, "big.wrl", 0, "more than max_file_bytes (60)");
    dir.write("part.wrl", vrml(std::string(100, '\n')));
    const std::string assembly = dir.write("asm.wrl", vrml("\nInline { url \"part.wrl\" }\n"));
    check_error([&] { read_vrml(assembly, tiny); }, "asm.wrl", 3, "cannot read Inline file");
    check_error([&] { read_vrml(dir.path()); }, dir.path(), 0, "not a regular file");
}

TEST_CASE("hostile sizes stay near-linear: many fields, a huge PROTO interface, many Inline urls") {
    const auto start = std::chrono::steady_clock::now();
    // One node with 200000 fields; of the repeated "children" the last wins.
    std::string fields = vrml("Group {\n children [ Group { } ]\n");
    for (int i = 0; i < 200000; ++i) fields += " f" + std::to_string(i) + " 1\n";
    fields += " children [ ]\n}\n";
    const auto one = read_written(fields, file);
    CHECK(one.nodes.size() == 1);

    // A PROTO with 50000 interface fields, all set by its instance.
    std::string proto = vrml("PROTO Big [\n");
    for (int i = 0; i < 50000; ++i) proto += " field SFFloat f" + std::to_string(i) + " 0\n";
    proto += " field SFVec3f pos 0 0 0\n] { Transform { translation IS pos } }\nBig {\n";
    for (int i = 0; i < 50000; ++i) proto += " f" + std::to_string(i) + " 1\n";
    proto += " pos 1 2 3\n}\n";
    const auto big = read_written(proto, file);
    REQUIRE(big.nodes.size() == 2);
    CHECK(big.nodes[1].world.translation().isApprox(Eigen::Vector3d(1, 2, 3)));

    // An Inline listing 100000 alternatives, and 5000 Inlines of missing files.
    std::string urls = vrml("Inline { url [\n");
    for (int i = 0; i < 100000; ++i) urls += " \"m" + std::to_string(i) + ".wrl\"\n";
    urls += "] }\n";
    for (int i = 0; i < 5000; ++i) urls += "Inline { url \"missing" + std::to_string(i) + ".wrl\" }\n";
    const auto missing = read_written(urls, file);
    CHECK(missing.nodes.empty());
    REQUIRE(missing.warnings.size() == 1001);  // capped, plus the count of the rest
    CHECK(missing.warnings[0].find("h.wrl:2: Inline has 100000 urls; only the first 16 are tried") !=
          std::string::npos);
    CHECK(missing.warnings.back() == "4002 more warnings not shown");

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    MESSAGE("hostile sizes read in " << seconds << " s");
    CHECK(seconds < 20);
}
}  // namespace MBX_UNITY_ID
