// The PMXML reader on the hand-written model: layout conventions, ids,
// subsystems, units, and every error path with its line number.
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "host_adapters/pmxml_vrml/pmxml_assembly.h"
#include "host_adapters/pmxml_vrml/pmxml_reader.h"
#include "tiny_pmxml.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx_files;
using atest::line_of;
using atest::replace_once;

namespace {

const PmxmlBody& body_named(const PmxmlModel& m, const std::string& id) {
    for (const PmxmlBody& b : m.bodies)
        if (b.id == id) return b;
    FAIL("no body " << id);
    return m.bodies.front();
}

Eigen::Matrix3d row_major(const double* r) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m(i, j) = r[3 * i + j];
    return m;
}

// The FileError parse_pmxml throws for `text` (fails the test if none).
FileError error_of(const std::string& text) {
    try {
        parse_pmxml(text, "tiny.xml");
    } catch (const FileError& e) {
        return e;
    }
    FAIL("no FileError");
    return FileError("", 0, "");
}

}  // namespace

TEST_CASE("pmxml: the tiny model reads with ids, flags, subsystems and global refs") {
    const PmxmlModel m = parse_pmxml(atest::tiny_pmxml(), "tiny.xml");
    CHECK(m.name == "TINY");
    CHECK(m.container == "SimMechanics");
    CHECK(m.created_using == "SimMechanics Link Version 4.0");
    REQUIRE(m.bodies.size() == 5);
    CHECK(m.bodies[0].id == "TINY/RootPart");
    CHECK(m.bodies[0].flags == MBX_BODY_HELPER);
    CHECK(m.bodies[1].id == "12");
    CHECK(m.bodies[1].flags == 0u);
    CHECK(m.bodies[2].id == "RootGround");
    CHECK(m.bodies[2].flags == (MBX_BODY_GROUND | MBX_BODY_HELPER));  // RootGround: a world datum
    CHECK(m.bodies[3].id == "TINY/SUB/RootPart");
    CHECK(m.bodies[3].flags == MBX_BODY_HELPER);
    CHECK(m.bodies[4].id == "SUB/31");
    CHECK(m.bodies[4].subsystem_path == std::vector<std::string>{"SUB"});
    CHECK(m.bodies[1].subsystem_path.empty());
    CHECK(m.max_subsystem_depth() == 1);
    CHECK(m.bodies[1].geometry_file == "ARM.stl");
    CHECK(m.bodies[1].geometry_line == line_of(atest::tiny_pmxml(), "\"ARM.stl\""));

    REQUIRE(m.joints.size() == 4);
    const PmxmlJoint& cross = m.joints[2];
    CHECK(cross.name == "ARM--LINK");
    CHECK(cross.id == "12:-:SUB/31");
    CHECK(m.frames[size_t(cross.base_frame)].id == "12::CS3");
    CHECK(m.frames[size_t(cross.follower_frame)].id == "SUB/31::CS2");
    CHECK(m.frames[size_t(cross.follower_frame)].ref == "16000");
    CHECK(cross.status == "Could not solve for constraint");
    CHECK(cross.primitives.size() == 1);
    CHECK(cross.primitives[0].type == MBX_PRIMITIVE_REVOLUTE);
    CHECK(cross.primitives[0].axis.y() == 1.5e-6);
    CHECK(m.joints[3].subsystem_path == std::vector<std::string>{"SUB"});

    // Units per quantity: LINK is in lbm and lbm*in^2 while lengths are mm.
    const PmxmlBody& link = body_named(m, "SUB/31");
    CHECK(link.mass_to_kg == mbx_test::relative(0.45359237, 1e-6));
    CHECK(link.inertia_to_kg_m2 == mbx_test::relative(0.45359237 * 0.0254 * 0.0254, 1e-6));
    CHECK(m.frames[size_t(link.cs1)].length_to_m == mbx_test::relative(0.001, 1e-6));
    CHECK(link.com.isApprox(Eigen::Vector3d(50, 0, 0)));
}

TEST_CASE("pmxml: orientation matrices are read column-major") {
    const PmxmlModel m = parse_pmxml(atest::tiny_pmxml(), "tiny.xml");
    const Eigen::Matrix3d r = atest::tiny_arm_rotation();
    REQUIRE_FALSE(r.isApprox(r.transpose(), 1e-3));  // the test means nothing for a symmetric matrix
    const PmxmlBody& arm = body_named(m, "12");
    const Eigen::Matrix3d read = m.frames[size_t(arm.cs1)].rotation;
    CHECK(read.isApprox(r, 1e-12));
    CHECK_FALSE(read.isApprox(r.transpose(), 1e-3));

    // The same through the host: mbx.h poses are row-major.
    const mbx_memory::Assembly a = to_assembly(m);
    const Eigen::Matrix3d served = row_major(a.bodies[1].pose.rotation);
    CHECK(served.isApprox(r, 1e-12));
    CHECK_FALSE(served.isApprox(r.transpose(), 1e-3));
    CHECK(a.bodies[1].pose.position[0] == 100);

    // Centre of mass in the CS1 frame: R^T (p_CG - p_CS1).
    const Eigen::Vector3d expected = r.transpose() * Eigen::Vector3d(50, 20, 10);
    CHECK(arm.com.isApprox(expected, 1e-12));
}

TEST_CASE("pmxml: inertia given in CG axes is turned into CS1 axes") {
    // Give the CG frame of ARM world axes while CS1 stays rotated.
    const std::string r_text = atest::orientation_text(atest::tiny_arm_rotation());
    const std::string text = replace_once(atest::tiny_pmxml(), "<position>150,20,10</position>",
                                          "<position>150,20,10</position><!-- CG -->");
    std::string changed = text;
    const size_t cg = changed.find("<!-- CG -->");
    const size_t orient = changed.find("<orientation>" + r_text, cg);
    changed.replace(orient, 13 + r_text.size(), "<orientation>1,0,0,0,1,0,0,0,1");
    const PmxmlModel m = parse_pmxml(changed, "tiny.xml");
    const PmxmlBody& arm = body_named(m, "12");
    Eigen::Matrix3d in_cg;
    in_cg << 0.01, 0.001, 0.002, 0.001, 0.02, 0.003, 0.002, 0.003, 0.03;
    const Eigen::Matrix3d r = atest::tiny_arm_rotation();
    const Eigen::Matrix3d expected = r.transpose() * in_cg * r;  // CG axes = world, CS1 axes = r
    CHECK(arm.inertia.isApprox(expected, 1e-12));
    // Principal moments do not depend on the axes.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> a(arm.inertia), b(in_cg);
    CHECK(a.eigenvalues().isApprox(b.eigenvalues(), 1e-12));
}

TEST_CASE("pmxml: host view has world frames with their own units and WORLD axes") {
    const mbx_memory::Assembly a = to_assembly(parse_pmxml(atest::tiny_pmxml(), "tiny.xml"));
    CHECK(a.name == "TINY");
    CHECK(a.source == "tiny.xml");
    // Joint ends (8) plus the user-added SENSOR datum; CG and CS1 stay in the bodies.
    CHECK(a.frames.size() == 9);
    bool sensor = false;
    for (const mbx_memory::Frame& f : a.frames) {
        CHECK(f.reference == MBX_FRAME_IN_WORLD);
        CHECK(f.units.length_to_m == 0.001);
        if (f.id == "12::CS4") {
            sensor = true;
            CHECK(f.name == "CS4 (SENSOR)");
            CHECK(f.body_id == "12");
        }
    }
    CHECK(sensor);
    REQUIRE(a.constraints.size() == 4);
    CHECK(a.constraints[1].base_frame_id == "TINY/RootPart::CS3");
    CHECK(a.constraints[1].follower_frame_id == "12::CS2");
    CHECK(a.constraints[1].chain[0].axis_reference == MBX_AXIS_IN_WORLD);
    CHECK(a.constraints[2].host_status == "Could not solve for constraint");
    CHECK(a.bodies[4].units.mass_to_kg == mbx_test::relative(0.45359237, 1e-6));
    CHECK(a.bodies[4].units.length_to_m == 0.001);
}

TEST_CASE("pmxml: multi-primitive joints keep their order, spherical ignores its axis") {
    const std::string text = replace_once(
        atest::tiny_pmxml(),
        "<Primitive><name>\"revolute\"</name><nodeID>\"\"</nodeID><referenceFrame>\"WORLD\"</"
        "referenceFrame><axis>0,0,1</axis></Primitive>",
        "<Primitive><name>\"prismatic\"</name><referenceFrame>\"WORLD\"</referenceFrame><axis>0,0,2</axis></Primitive>"
        "<Primitive><name>\"revolute\"</name><referenceFrame>\"WORLD\"</referenceFrame><axis>0,0,1</axis></Primitive>"
        "<Primitive><name>\"spherical\"</name><referenceFrame>\"BASE\"</referenceFrame><axis>0,0,0</axis></Primitive>");
    const PmxmlModel m = parse_pmxml(text, "tiny.xml");
    const PmxmlJoint& j = m.joints[1];
    REQUIRE(j.primitives.size() == 3);
    CHECK(j.primitives[0].type == MBX_PRIMITIVE_PRISMATIC);
    CHECK(j.primitives[1].type == MBX_PRIMITIVE_REVOLUTE);
    CHECK(j.primitives[2].type == MBX_PRIMITIVE_SPHERICAL);
}

TEST_CASE("pmxml: repeated joint nodeIDs get a suffix, names stay") {
    const std::string text = replace_once(atest::tiny_pmxml(), "<nodeID>\"12:-:SUB/31\"</nodeID>",
                                          "<nodeID>\"TINY/RootPart:-:12\"</nodeID>");
    const PmxmlModel m = parse_pmxml(text, "tiny.xml");
    CHECK(m.joints[1].id == "TINY/RootPart:-:12");
    CHECK(m.joints[2].id == "TINY/RootPart:-:12~2");
    CHECK(m.joints[2].name == "ARM--LINK");
    REQUIRE(m.diagnostics.size() == 1);
    CHECK(m.diagnostics[0].code == "pmxml_duplicate_id");
    CHECK(m.diagnostics[0].line == line_of(text, "<SimpleJoint>\n        <name>\"ARM--LINK\""));
}

TEST_CASE("pmxml: a body without nodeID is named by its subsystem path") {
    const std::string text = replace_once(atest::tiny_pmxml(), "<nodeID>\"SUB/31\"</nodeID>", "");
    const PmxmlModel m = parse_pmxml(text, "tiny.xml");
    CHECK(m.bodies[4].id == "TINY/SUB/LINK");
    CHECK(m.frames[size_t(m.bodies[4].cs1)].id == "TINY/SUB/LINK::CS1");
}

namespace {

// A massless body with the given frames (CS1 first), as the exporter writes it.
std::string body_with_frames(const std::string& node_id, const std::vector<std::string>& frame_names) {
    std::string s = "<Body><name>\"P\"</name><nodeID>\"" + node_id + "\"</nodeID><mass>0</mass>"
                    "<inertia>0,0,0,0,0,0,0,0,0</inertia><frames>\n";
    for (const std::string& name : frame_names)
        s += atest::tiny_frame("  ", "", name, "", "0,0,0", "1,0,0,0,1,0,0,0,1");
    return s + "</frames></Body>\n";
}

std::string model_of(const std::string& bodies) {
    return "<PhysicalModelingXMLFile><SimMechanics><name>\"M\"</name><bodies>\n" + bodies +
           "</bodies></SimMechanics></PhysicalModelingXMLFile>\n";
}

std::vector<std::string> frame_ids(const PmxmlModel& m) {
    std::vector<std::string> ids;
    for (const PmxmlFrame& f : m.frames) ids.push_back(f.id);
    return ids;
}

}  // namespace

TEST_CASE("pmxml: frame ids are <body id>::<name>, unique in the file in file order") {
    using V = std::vector<std::string>;
    SUBCASE("repeated names in one body take ~2, ~3, skipping names already written that way") {
        const PmxmlModel m = parse_pmxml(
            model_of(body_with_frames("A", {"CS1", "CS2", "CS2", "CS2~2", "CS2"}) + body_with_frames("B", {"CS1", "CS2"})),
            "ids.xml");
        CHECK(frame_ids(m) == V{"A::CS1", "A::CS2", "A::CS2~2", "A::CS2~2~2", "A::CS2~3", "B::CS1", "B::CS2"});
    }
    SUBCASE("a body with many frames (past the few checked one by one)") {
        V names{"CS1"}, expected{"A::CS1"};
        for (int k = 0; k < 40; ++k) {
            names.push_back("CS" + std::to_string(k % 10 + 2));
            expected.push_back("A::CS" + std::to_string(k % 10 + 2) + (k < 10 ? "" : "~" + std::to_string(k / 10 + 1)));
        }
        CHECK(frame_ids(parse_pmxml(model_of(body_with_frames("A", names)), "ids.xml")) == expected);
    }
    SUBCASE("'::' in body ids and frame names: ids of different bodies can meet") {
        // "a::b" + "c" and "a" + "b::c" spell the same id; the later frame gets the suffix.
        const PmxmlModel m = parse_pmxml(
            model_of(body_with_frames("a::b", {"CS1", "c"}) + body_with_frames("a", {"CS1", "b::c", "b::CS1"})),
            "ids.xml");
        CHECK(frame_ids(m) == V{"a::b::CS1", "a::b::c", "a::CS1", "a::b::c~2", "a::b::CS1~2"});
    }
}

TEST_CASE("pmxml errors: malformed XML") {
    const std::string text = replace_once(atest::tiny_pmxml(), "<mass>2.5</mass>", "<mass>2.5</masss>");
    const FileError e = error_of(text);
    CHECK(e.file() == "tiny.xml");
    CHECK(e.line() == line_of(text, "</masss>"));
    CHECK(e.message().find("malformed XML") != std::string::npos);
    CHECK(std::string(e.what()).rfind("tiny.xml:" + std::to_string(e.line()) + ": ", 0) == 0);

    const FileError empty = error_of("");
    CHECK(empty.message().find("malformed XML") != std::string::npos);
    const FileError truncated = error_of(atest::tiny_pmxml().substr(0, 4000));
    CHECK(truncated.message().find("malformed XML") != std::string::npos);
    CHECK(truncated.line() > 1);
}

TEST_CASE("pmxml errors: not first-generation PMXML") {
    const FileError second = error_of(
        "<?xml version=\"1.0\"?>\n<SimscapeMultibodyImportXML version=\"2.0\" "
        "xmlns=\"urn:mathworks:SimscapeMultibody:import\"/>\n");
    CHECK(second.line() == 2);
    CHECK(second.message().find("second-generation") != std::string::npos);
    const FileError other = error_of("<robot name=\"r\"/>");
    CHECK(other.line() == 1);
    CHECK(other.message().find("<robot>") != std::string::npos);
    const FileError no_model = error_of("<PhysicalModelingXMLFile>\n</PhysicalModelingXMLFile>\n");
    CHECK(no_model.message().find("SimscapeMultibody") != std::string::npos);
}

TEST_CASE("pmxml errors: the SimscapeMultibody container reads like SimMechanics") {
    std::string text = atest::tiny_pmxml();
    text = replace_once(text, "  <SimMechanics>", "  <SimscapeMultibody>");
    text = replace_once(text, "  </SimMechanics>", "  </SimscapeMultibody>");
    const PmxmlModel m = parse_pmxml(text, "tiny.xml");
    CHECK(m.container == "SimscapeMultibody");
    CHECK(m.bodies.size() == 5);
}

TEST_CASE("pmxml errors: dangling ref names the joint and the line") {
    const std::string text =
        replace_once(atest::tiny_pmxml(), "<Frame ref=\"16000\"></Frame>", "<Frame ref=\"17000\"></Frame>");
    const FileError e = error_of(text);
    CHECK(e.line() == line_of(text, "<Frame ref=\"17000\">"));
    CHECK(e.message().find("'ARM--LINK'") != std::string::npos);
    CHECK(e.message().find("17000") != std::string::npos);
}

TEST_CASE("pmxml errors: a joint end without a ref") {
    const std::string text = replace_once(atest::tiny_pmxml(), "<Frame ref=\"16000\"></Frame>", "<Frame></Frame>");
    const FileError e = error_of(text);
    CHECK(e.message().find("'ARM--LINK'") != std::string::npos);
    CHECK(e.message().find("no ref") != std::string::npos);
}

TEST_CASE("pmxml errors: duplicate ref names both lines") {
    const std::string text = replace_once(atest::tiny_pmxml(), "<Frame ref=\"8\">\n", "<Frame ref=\"5\">\n");
    const FileError e = error_of(text);
    CHECK(e.line() == line_of(text, "<Frame ref=\"5\">\n                <name>\"CS3\""));
    CHECK(e.message().find("ref 5") != std::string::npos);
    CHECK(e.message().find("line " + std::to_string(line_of(text, "<Frame ref=\"5\">"))) != std::string::npos);
}

TEST_CASE("pmxml errors: frames relative to anything but WORLD") {
    for (const char* field : {"positionOrigin", "positionReferenceFrame", "orientationReferenceFrame"}) {
        CAPTURE(field);
        std::string text = atest::tiny_pmxml();
        const size_t frame = text.find("<nodeID>\"12::CS1(AUTOGEN)\"</nodeID>");
        const std::string from = std::string("<") + field + ">\"WORLD\"";
        const size_t at = text.find(from, frame);
        text.replace(at, from.size(), std::string("<") + field + ">\"ADJOINING\"");
        const FileError e = error_of(text);
        CHECK(e.line() == line_of(text, "\"ADJOINING\""));
        CHECK(e.message().find("frame 'CS1' of body 'ARM'") != std::string::npos);
        CHECK(e.message().find("'ADJOINING'") != std::string::npos);
    }
    std::string text = atest::tiny_pmxml();
    const size_t frame = text.find("<nodeID>\"SUB/31::CG(AUTOGEN)\"</nodeID>");
    const std::string from = "\"3x3 Transform\"";
    text.replace(text.find(from, frame), from.size(), "\"Quaternion\"");
    const FileError e = error_of(text);
    CHECK(e.line() == line_of(text, "\"Quaternion\""));
    CHECK(e.message().find("frame 'CG' of body 'LINK'") != std::string::npos);
}

TEST_CASE("pmxml errors: an axis not in WORLD names the joint") {
    std::string text = atest::tiny_pmxml();
    const size_t joint = text.find("<name>\"RootPart--ARM\"</name>");
    const std::string from = "<referenceFrame>\"WORLD\"</referenceFrame>";
    text.replace(text.find(from, joint), from.size(), "<referenceFrame>\"BASE\"</referenceFrame>");
    const FileError e = error_of(text);
    CHECK(e.line() == line_of(text, "\"BASE\""));
    CHECK(e.message().find("'RootPart--ARM'") != std::string::npos);
    CHECK(e.message().find("'BASE'") != std::string::npos);
}

TEST_CASE("pmxml errors: unknown primitive") {
    const std::string text = replace_once(
        atest::tiny_pmxml(),
        "<name>\"revolute\"</name><nodeID>\"\"</nodeID><referenceFrame>\"WORLD\"</referenceFrame><axis>0,0,1</axis>",
        "<name>\"cylindrical\"</name><nodeID>\"\"</nodeID><referenceFrame>\"WORLD\"</referenceFrame><axis>0,0,1</"
        "axis>");
    const FileError e = error_of(text);
    CHECK(e.line() == line_of(text, "\"cylindrical\""));
    CHECK(e.message().find("'RootPart--ARM'") != std::string::npos);
    CHECK(e.message().find("'cylindrical'") != std::string::npos);
}

TEST_CASE("pmxml errors: bad numbers") {
    {
        const std::string text = replace_once(atest::tiny_pmxml(), "<mass>2.5</mass>", "<mass>2,5</mass>");
        const FileError e = error_of(text);
        CHECK(e.line() == line_of(text, "<mass>2,5"));
        CHECK(e.message().find("body 'ARM'") != std::string::npos);
        CHECK(e.message().find("'2,5'") != std::string::npos);
    }
    {
        const std::string text =
            replace_once(atest::tiny_pmxml(), "<position>150,20,10</position>", "<position>150,20</position>");
        const FileError e = error_of(text);
        CHECK(e.line() == line_of(text, "<position>150,20<"));
        CHECK(e.message().find("frame 'CG' of body 'ARM'") != std::string::npos);
    }
    {
        const std::string text = replace_once(atest::tiny_pmxml(), "<inertia>20,0,0,0,30,0,0,0,40</inertia>",
                                              "<inertia>20,0,0,0,3O,0,0,0,40</inertia>");
        const FileError e = error_of(text);
        CHECK(e.line() == line_of(text, "3O"));
    }
    {
        const std::string text = replace_once(atest::tiny_pmxml(), "<axis>0,0,1</axis>", "<axis>0,0,0</axis>");
        const FileError e = error_of(text);
        CHECK(e.line() == line_of(text, "<axis>0,0,0</axis>"));
        CHECK(e.message().find("zero-length") != std::string::npos);
    }
}

TEST_CASE("pmxml errors: missing mass, units, frames") {
    {
        const std::string text = replace_once(atest::tiny_pmxml(), "        <mass>2.5</mass>\n", "");
        const FileError e = error_of(text);
        CHECK(e.line() == line_of(text, "<Body>\n        <name>\"ARM\""));
        CHECK(e.message().find("body 'ARM' has no <mass>") != std::string::npos);
    }
    {
        const std::string text =
            replace_once(atest::tiny_pmxml(), "<massUnits>\"lbm\"</massUnits>", "<massUnits>\"stone\"</massUnits>");
        const FileError e = error_of(text);
        CHECK(e.line() == line_of(text, "\"stone\""));
        CHECK(e.message().find("'stone'") != std::string::npos);
    }
    {
        const std::string text = replace_once(atest::tiny_pmxml(), "<massUnits>\"lbm\"</massUnits>", "");
        const FileError e = error_of(text);
        CHECK(e.message().find("body 'LINK' has no <massUnits>") != std::string::npos);
    }
    {
        // A massless helper may omit its units.
        std::string text = atest::tiny_pmxml();
        text =
            replace_once(text,
                         "            <massUnits>\"kg\"</massUnits>\n            "
                         "<inertia>0,0,0,0,0,0,0,0,0</inertia>\n            <inertiaUnits>\"kg*m^2\"</inertiaUnits>\n",
                         "            <inertia>0,0,0,0,0,0,0,0,0</inertia>\n");
        CHECK_NOTHROW(parse_pmxml(text, "tiny.xml"));
    }
    {
        std::string text = atest::tiny_pmxml();
        const size_t frame = text.find("RootGround:-:TINY/RootPart::RootGround(AUTOGEN)");
        const std::string from = "<positionUnits>\"mm\"</positionUnits>";
        text.erase(text.find(from, frame), from.size());
        const FileError e = error_of(text);
        CHECK(e.message().find("frame 'CS1' of ground 'RootGround' has no <positionUnits>") != std::string::npos);
    }
    {
        std::string text = atest::tiny_pmxml();
        const size_t at = text.find("<name>\"CS1\"</name>", text.find("<name>\"LINK\"</name>"));
        text.replace(at, 18, "<name>\"CSX\"</name>");
        const FileError e = error_of(text);
        CHECK(e.message().find("body 'LINK' has no CS1 frame") != std::string::npos);
    }
    {
        std::string text = atest::tiny_pmxml();
        const size_t frame = text.find("<nodeID>\"12::CG(AUTOGEN)\"</nodeID>");
        const std::string r = atest::orientation_text(atest::tiny_arm_rotation());
        const size_t at = text.find(r, frame);
        text.replace(at, r.size(), "1,0,0,0,1,0,0,0,-1");  // a reflection
        const FileError e = error_of(text);
        CHECK(e.line() == line_of(text, "1,0,0,0,1,0,0,0,-1"));
        CHECK(e.message().find("not a rotation") != std::string::npos);
    }
}

TEST_CASE("pmxml errors: a missing file") {
    try {
        read_pmxml("/nonexistent/dir/model.xml");
        FAIL("no error");
    } catch (const FileError& e) {
        CHECK(e.file() == "/nonexistent/dir/model.xml");
        CHECK(e.line() == 0);
        CHECK(e.message().find("cannot open") != std::string::npos);
    }
    atest::TempDir dir;
    try {
        read_pmxml(dir.path.string());
        FAIL("no error");
    } catch (const FileError& e) {
        CHECK(e.message().find("directory") != std::string::npos);
    }
    atest::write_file(dir.file("tiny.xml"), atest::tiny_pmxml());
    CHECK(read_pmxml(dir.file("tiny.xml")).bodies.size() == 5);
}

TEST_CASE("pmxml fuzz: random mutations end in a model or a FileError with a line") {
    const std::string original = atest::tiny_pmxml();
    atest::Mutator mutator(0x9e3779b97f4a7c15ull);
    const char* tokens[] = {"\"", ",", "<", ">", "/", "e-006", "ref=\"1\"", "nan", "-", "0", "\n", "Frame", "WORLD"};
    size_t parsed = 0, errors = 0;
    for (int round = 0; round < 2000; ++round) {
        const std::string text =
            mutator.mutate(original, tokens, 4, 40, [](std::string& t, size_t at) { t = t.substr(0, at); });
        try {
            const PmxmlModel m = parse_pmxml(text, "fuzz.xml");
            ++parsed;
            for (const PmxmlJoint& j : m.joints) {
                REQUIRE(size_t(j.base_frame) < m.frames.size());
                REQUIRE(size_t(j.follower_frame) < m.frames.size());
            }
            to_assembly(m);
        } catch (const FileError& e) {
            ++errors;
            REQUIRE(e.file() == "fuzz.xml");
            REQUIRE(e.line() >= 0);
            REQUIRE_FALSE(e.message().empty());
        }
    }
    MESSAGE(parsed << " mutants parsed, " << errors << " refused");
    CHECK(errors > 0);
}
}  // namespace MBX_UNITY_ID
