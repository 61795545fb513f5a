// The Part 21 reader on synthetic text (every construct of ISO 10303-21 a
// geometry reader meets) and on real exports, whose instance and type counts
// are checked against an independent scan of the text.
#include <doctest/doctest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "host_adapters/step/part21.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx_step;

namespace {

std::string wrap(const std::string& data, const std::string& schema = "AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }") {
    return "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('a test','second'),'2;1');\n"
           "FILE_NAME('part.stp','2026-11-28T00:00:00',('me'),('mbx'),'pre','SolidWorks 2020','');\n"
           "FILE_SCHEMA(('" + schema + "'));\nENDSEC;\nDATA;\n" + data + "ENDSEC;\nEND-ISO-10303-21;\n";
}

const Record& only_record(const File& f, uint64_t id) {
    const Instance* in = f.find(id);
    REQUIRE(in != nullptr);
    REQUIRE(in->record_count == 1);
    return f.first_record(*in);
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// gzip -dc of a Debian-packaged test file (the library reads no gzip).
std::string gunzip(const std::string& path) {
    FILE* pipe = ::popen(("gzip -dc '" + path + "'").c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string out;
    char buffer[65536];
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
    REQUIRE(::pclose(pipe) == 0);
    return out;
}

std::string error_of(const std::string& text) {
    try {
        read_part21(text, "t.stp");
    } catch (const ReadError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("part 21: the header's description, name, system and schema") {
    const File f = read_part21(wrap("#1=CARTESIAN_POINT('',(0.,0.,0.));\n"), "t.stp");
    CHECK(f.header.description == std::vector<std::string>{"a test", "second"});
    CHECK(f.header.name == "part.stp");
    CHECK(f.header.originating_system == "SolidWorks 2020");
    REQUIRE(f.header.schemas.size() == 1);
    CHECK(f.header.schemas[0].rfind("AUTOMOTIVE_DESIGN", 0) == 0);
}

TEST_CASE("part 21: every kind of value, with its numbers exact") {
    const File f = read_part21(
        wrap("#1=THING('name',$,*,12,-3.5,1.E-3,+2.,.T.,#2,(1,2,(3,4)),LENGTH_MEASURE(2.5),\"0FF\",(),-7,1.5e+2);\n"
             "#2=OTHER(.unspecified.);\n"),
        "t.stp");
    const Record& r = only_record(f, 1);
    CHECK(f.type_name(r.type) == "THING");
    REQUIRE(r.count == 15);
    CHECK(f.attribute(r, 0).kind == Kind::String);
    CHECK(f.text(f.attribute(r, 0)) == "name");
    CHECK(f.attribute(r, 1).kind == Kind::Missing);
    CHECK(f.attribute(r, 2).kind == Kind::Derived);
    CHECK(f.attribute(r, 3).kind == Kind::Integer);
    CHECK(f.attribute(r, 3).integer == 12);
    CHECK(f.attribute(r, 4).kind == Kind::Real);
    CHECK(f.attribute(r, 4).real == -3.5);
    CHECK(f.attribute(r, 5).real == 1e-3);
    CHECK(f.attribute(r, 6).real == 2.0);
    CHECK(f.attribute(r, 7).kind == Kind::Enumeration);
    CHECK(f.text(f.attribute(r, 7)) == "T");
    const Value& ref = f.attribute(r, 8);
    CHECK(ref.kind == Kind::Reference);
    CHECK(ref.id == 2);
    REQUIRE(ref.a != kUnresolved);
    CHECK(f.instances[ref.a].id == 2);
    const Value& list = f.attribute(r, 9);
    REQUIRE(list.kind == Kind::List);
    REQUIRE(list.count == 3);
    CHECK(f.element(list, 0).integer == 1);
    CHECK(f.element(list, 1).integer == 2);
    const Value& inner = f.element(list, 2);
    REQUIRE(inner.kind == Kind::List);
    REQUIRE(inner.count == 2);
    CHECK(f.element(inner, 0).integer == 3);
    CHECK(f.element(inner, 1).integer == 4);
    const Value& typed = f.attribute(r, 10);
    REQUIRE(typed.kind == Kind::Typed);
    CHECK(f.type_name(uint32_t(typed.type)) == "LENGTH_MEASURE");
    CHECK(f.values[typed.a].real == 2.5);
    CHECK(f.attribute(r, 11).kind == Kind::Binary);
    CHECK(f.text(f.attribute(r, 11)) == "0FF");
    CHECK(f.attribute(r, 12).kind == Kind::List);
    CHECK(f.attribute(r, 12).count == 0);
    CHECK(f.attribute(r, 13).integer == -7);
    CHECK(f.attribute(r, 14).real == 150.0);
    // Enumerations upper-cased, as the schema spells them.
    CHECK(f.text(f.attribute(only_record(f, 2), 0)) == "UNSPECIFIED");
    CHECK(f.type_id("THING") == r.type);
    CHECK(f.type_id("NOWHERE") == File::kNoType);
}

TEST_CASE("part 21: a complex instance keeps one record per partial type") {
    const File f = read_part21(
        wrap("#7=( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#8)) "
             "REPRESENTATION_CONTEXT('ctx','3D') );\n#8=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\n"),
        "t.stp");
    const Instance* ctx = f.find(7);
    REQUIRE(ctx != nullptr);
    CHECK(ctx->record_count == 3);
    const Record* geometric = f.record(*ctx, f.type_id("GEOMETRIC_REPRESENTATION_CONTEXT"));
    REQUIRE(geometric != nullptr);
    CHECK(f.attribute(*geometric, 0).integer == 3);
    const Record* units = f.record(*ctx, f.type_id("GLOBAL_UNIT_ASSIGNED_CONTEXT"));
    REQUIRE(units != nullptr);
    const Value& unit = f.element(f.attribute(*units, 0), 0);
    REQUIRE(unit.kind == Kind::Reference);
    const Record* si = f.record(unit.a, f.type_id("SI_UNIT"));
    REQUIRE(si != nullptr);
    CHECK(f.text(f.attribute(*si, 0)) == "MILLI");
    CHECK(f.text(f.attribute(*si, 1)) == "METRE");
    CHECK(f.record(*ctx, f.type_id("SI_UNIT")) == nullptr);
    const Record* named = f.record(unit.a, f.type_id("NAMED_UNIT"));
    REQUIRE(named != nullptr);
    CHECK(f.attribute(*named, 0).kind == Kind::Derived);
}

TEST_CASE("part 21: strings with doubled quotes, backslashes and every encoding directive, as UTF-8") {
    const File f = read_part21(
        wrap("#1=N('it''s');\n#2=N('\\X\\E9t\\X\\E9');\n#3=N('\\X2\\00E9004C\\X0\\!');\n#4=N('\\S\\i');\n"
             "#5=N('a\\\\b');\n#6=N('\\X4\\0001F600\\X0\\');\n#7=N('\\X2\\D83DDE00\\X0\\');\n"
             "#8=N('split\nacross lines');\n#9=N('\\PA\\\\S\\i');\n"),
        "t.stp");
    auto name = [&](uint64_t id) { return std::string(f.text(f.attribute(only_record(f, id), 0))); };
    CHECK(name(1) == "it's");
    CHECK(name(2) == "\xC3\xA9t\xC3\xA9");        // été
    CHECK(name(3) == "\xC3\xA9L!");               // éL!
    CHECK(name(4) == "\xC3\xA9");                 // \S\i: 'i' (0x69) + 128 = é
    CHECK(name(5) == "a\\b");
    CHECK(name(6) == "\xF0\x9F\x98\x80");         // U+1F600
    CHECK(name(7) == "\xF0\x9F\x98\x80");         // the same as a UTF-16 surrogate pair
    CHECK(name(8) == "splitacross lines");        // a line break inside a string is not part of it
    CHECK(name(9) == "\xC3\xA9");
}

TEST_CASE("part 21: comments anywhere, CRLF line ends and lower-case keywords, lines counted through all of them") {
    const std::string text =
        "ISO-10303-21;\r\nHEADER;/* a comment\r\n over two lines */\r\nFILE_DESCRIPTION((''),'2;1');\r\n"
        "FILE_NAME('','',(''),(''),'','','');\r\nFILE_SCHEMA(('CONFIG_CONTROL_DESIGN'));\r\nENDSEC;\r\nDATA;\r\n"
        "#1 = cartesian_point ( 'p' , /* inside */ ( 1. , 2. , 3. ) ) ;\r\n"
        "#2=DIRECTION('',(0.,0.,1.));\r\n#3=AXIS2_PLACEMENT_3D('',#1,#2,#9);\r\nENDSEC;\r\nEND-ISO-10303-21;\r\n";
    const File f = read_part21(text, "t.stp");
    CHECK(f.header.schemas == std::vector<std::string>{"CONFIG_CONTROL_DESIGN"});
    const Instance* p = f.find(1);
    REQUIRE(p != nullptr);
    CHECK(p->line == 9);
    CHECK(f.type_name(f.first_record(*p).type) == "CARTESIAN_POINT");
    CHECK(f.find(3)->line == 11);
    // #9 is nowhere: a problem naming the instance, its line and the missing one.
    REQUIRE(f.problems.size() == 1);
    CHECK(f.problems[0].entity == 3);
    CHECK(f.problems[0].line == 11);
    CHECK(f.problems[0].message.find("#9") != std::string::npos);
    CHECK(f.attribute(only_record(f, 3), 3).a == kUnresolved);
}

TEST_CASE("part 21: a cycle of references is reported with its chain, and reading ends") {
    const File f = read_part21(wrap("#1=A(#2);\n#2=B((#3));\n#3=C(X(#1));\n#4=D(#4);\n#5=E(#1);\n"), "t.stp");
    REQUIRE(f.problems.size() == 2);
    CHECK(f.problems[0].message.find("a cycle of references") != std::string::npos);
    CHECK(f.problems[0].message.find("#1 -> #2 -> #3 -> #1") != std::string::npos);
    CHECK(f.problems[1].message.find("#4 -> #4") != std::string::npos);
}

TEST_CASE("part 21: malformed text is refused with its line and instance") {
    CHECK(error_of(wrap("#1=A(1);\n#1=B(2);\n")).find("t.stp:9: #1: instance number written twice (lines 8 and 9)") == 0);
    CHECK(error_of(wrap("#1=A(1,);\n")).find("t.stp:8: #1: expected a value") == 0);
    CHECK(error_of(wrap("#1=A(1 2);\n")).find("t.stp:8: #1: expected ',' or ')'") == 0);
    CHECK(error_of(wrap("#1=A(1)\n#2=B(2);\n")).find("t.stp:9: #1: expected ';'") == 0);
    CHECK(error_of(wrap("#1=A('never ends);\n")).find("t.stp:8: #1: a string that never ends") == 0);
    CHECK(error_of(wrap("#1=A(1.E);\n")).find("a real with an empty exponent") != std::string::npos);
    CHECK(error_of(wrap("#1=A(99999999999999999999);\n")).find("an integer out of range") != std::string::npos);
    CHECK(error_of(wrap("#1=A(1.E999);\n")).find("a real out of range") != std::string::npos);
    CHECK(error_of(wrap("#0=A(1);\n")).find("instance number 0") != std::string::npos);
    CHECK(error_of(wrap("#1=A(.T);\n")).find("enumeration") != std::string::npos);
    CHECK(error_of(wrap("#1=();\n")).find("a complex instance with no records") != std::string::npos);
    CHECK(error_of("ISO-10303-21;\nHEADER;\nENDSEC;\nEND-ISO-10303-21;\n").find("no DATA section") != std::string::npos);
    CHECK(error_of("solid ascii\nfacet normal 0 0 1\n").find("t.stp:1: expected ISO-10303-21") == 0);
    CHECK(error_of("ISO-10303-21;\nHEADER;\n/* open\n").find("t.stp:3: a comment that never ends") == 0);
    // Nesting beyond the limit is refused, not followed down the stack.
    std::string deep = "#1=A(";
    for (int k = 0; k < 200; ++k) deep += "(";
    for (int k = 0; k < 200; ++k) deep += ")";
    CHECK(error_of(wrap(deep + ");\n")).find("nested deeper than 64") != std::string::npos);
    std::string typed = "#1=A(";
    for (int k = 0; k < 200; ++k) typed += "T(";
    typed += "1";
    for (int k = 0; k < 200; ++k) typed += ")";
    CHECK(error_of(wrap(typed + ");\n")).find("nested deeper than 64") != std::string::npos);
}

TEST_CASE("part 21: every truncation of a real file is refused cleanly, none read as a whole file") {
    const std::string text = read_text(mbx_test::shared_data("step/dfki_double_pendulum/lever_200.STEP"));
    const File whole = read_part21(text, "lever_200.STEP");
    CHECK(whole.problems.empty());
    int refused = 0, cuts = 0;
    for (size_t n = 0; n < text.size(); n += 997) {
        ++cuts;
        try {
            read_part21(std::string_view(text).substr(0, n), "cut.stp");
        } catch (const ReadError& e) {
            ++refused;
            CHECK(e.line() >= 1);
        }
    }
    CHECK(refused == cuts);
}

TEST_CASE("part 21: real exports read whole, their instances and types counted as an independent scan counts them") {
    struct Sample {
        std::string path;
        const char* schema;
    };
    std::vector<Sample> samples = {
        {mbx_test::shared_data("step/dfki_double_pendulum/double_pendulum.STEP"), "AUTOMOTIVE_DESIGN"},
        {mbx_test::shared_data("step/dfki_double_pendulum/lever_200.STEP"), "AUTOMOTIVE_DESIGN"},
        {mbx_test::shared_data("step/dfki_double_pendulum/lever_300.STEP"), "AUTOMOTIVE_DESIGN"},
        {mbx_test::shared_data("step/dfki_double_pendulum/lever_400.STEP"), "AUTOMOTIVE_DESIGN"},
        {mbx_test::shared_data("step/nist_ctc_02/nist_ctc_02_asme1_ap242-1.stp"), "AP242_MANAGED_MODEL_BASED_3D_ENGINEERING"},
    };
    for (const char* packaged : {"/usr/share/opencascade/data/step/linkrods.step", "/usr/share/opencascade/data/step/screw.step",
                                 "/usr/share/doc/gmsh-doc/doc/gmsh/demos/api/as1-tu-203.stp.gz"}) {
        if (!std::ifstream(packaged)) MBX_SKIP("no " << packaged << " (occt-misc and gmsh-doc: bash .ci/install-deps)");
        samples.push_back({packaged, nullptr});
    }
    for (const Sample& s : samples) {
        CAPTURE(s.path);
        const bool gz = s.path.size() > 3 && s.path.compare(s.path.size() - 3, 3, ".gz") == 0;
        const std::string text = gz ? gunzip(s.path) : read_text(s.path);
        const File f = read_part21(text, s.path);
        CHECK(f.problems.empty());
        if (s.schema) {
            REQUIRE(!f.header.schemas.empty());
            CHECK(f.header.schemas[0].rfind(s.schema, 0) == 0);
        }
        // The independent scan: each instance starts a statement "#n=" at a
        // line's start in these writers' output; simple instances name their
        // type right after it.
        const std::regex start(R"(^#(\d+)\s*=\s*(\(|[A-Z0-9_]+))", std::regex::multiline);
        std::map<std::string, size_t> scanned;
        size_t instances = 0;
        for (auto it = std::sregex_iterator(text.begin(), text.end(), start); it != std::sregex_iterator(); ++it) {
            ++instances;
            ++scanned[(*it)[2]];
        }
        CHECK(f.instances.size() == instances);
        std::map<std::string, size_t> read;
        for (const Instance& in : f.instances)
            ++read[in.record_count == 1 ? f.type_name(f.first_record(in).type) : std::string("(")];
        CHECK(read == scanned);
        MESSAGE(s.path << ": " << f.instances.size() << " instances, " << f.type_count() << " type names, "
                       << read["ADVANCED_FACE"] << " advanced faces");
        if (s.path.find("nist_ctc_02") != std::string::npos) CHECK(read["ADVANCED_FACE"] == 487);
        if (s.path.find("double_pendulum.STEP") != std::string::npos)
            CHECK(read["NEXT_ASSEMBLY_USAGE_OCCURRENCE"] == 28);
    }
}

TEST_CASE("part 21: what is not a regular file, or too large, is refused before reading") {
    CHECK_THROWS_WITH_AS(read_part21_file("/nowhere/part.step"), doctest::Contains("cannot open"), ReadError);
    CHECK_THROWS_WITH_AS(read_part21_file("/dev/zero"), doctest::Contains("not a regular file"), ReadError);
    CHECK_THROWS_WITH_AS(read_part21_file("/tmp"), doctest::Contains("not a regular file"), ReadError);
    const std::string lever = mbx_test::shared_data("step/dfki_double_pendulum/lever_200.STEP");
    CHECK_THROWS_WITH_AS(read_part21_file(lever, 1000), doctest::Contains("larger than 1000 bytes"), ReadError);
    CHECK(read_part21_file(lever).instances.size() > 1000);
}

}  // namespace MBX_UNITY_ID
