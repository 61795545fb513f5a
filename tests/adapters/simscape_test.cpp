// The Simscape Multibody second-generation adapter (host_adapters/simscape):
// a mechanism written as an import file (nested sub-assemblies with relative
// transforms, a part shared by two instances, a joint of a sub-assembly, a
// rigid group, a grounded instance) is the same mechanism as the one served
// directly in world coordinates through the memory host: the same mass
// matrix and inverse dynamics at random states. The same file in inches and
// pounds is the same mechanism; joints act along their frames' z axes as in
// Simscape; bad files are findings or errors naming the line.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "host_adapters/common/file_error.h"
#include "host_adapters/inputs/input_formats.h"
#include "host_adapters/memory/memory_host.h"
#include "host_adapters/simscape/simscape_adapter.h"
#include "host_adapters/simscape/simscape_reader.h"
#include "samples/tools/simscape_document.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"
#include "mechanism_dynamics.h"
#include "translation_support.h"

namespace MBX_UNITY_ID {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using mbx_samples::SimscapeXmlDocument;
using mbx_samples::SimscapeXmlInstance;
using mbx_samples::SimscapeXmlJoint;
using mbx_samples::SimscapeXmlPart;

namespace {

Isometry3d placed(const Vector3d& axis, double angle, const Vector3d& at) {
    Isometry3d x = Isometry3d::Identity();
    x.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    x.translation() = at;
    return x;
}

Matrix3d inertia(double ixx, double iyy, double izz, double ixy, double ixz, double iyz) {
    Matrix3d I;
    I << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
    return I;
}

// A base on the ground, an arm sub-assembly (two instances of one link part
// and a tip in a rigid group with the second link) turned and offset from
// the root, a shoulder joint in the root assembly and an elbow joint in the
// arm's own definition; joint frames turned so that their z axes are the
// hinge axes.
struct Arm {
    SimscapeXmlDocument doc;
    Isometry3d arm_at = placed(Vector3d(0.3, -0.2, 1), 0.7, Vector3d(0.05, -0.02, 0.3));
    Isometry3d link1_at = placed(Vector3d(1, 0, 0), 0.2, Vector3d(0.01, 0.02, 0.0));
    Isometry3d link2_at = placed(Vector3d(0, 1, 0.2), -0.4, Vector3d(0.0, 0.0, 0.25));
    Isometry3d tip_at = placed(Vector3d(0, 0, 1), 0.3, Vector3d(0.02, 0.0, 0.45));
    // Hinge frames in the parts' frames: the shoulder turns about the link's
    // x axis at its foot, the elbow about its y axis at its far end.
    Isometry3d shoulder_in_link = placed(Vector3d(0, 1, 0), M_PI / 2, Vector3d(0, 0, 0.0));
    Isometry3d elbow_in_link = placed(Vector3d(1, 0, 0), -M_PI / 2, Vector3d(0, 0, 0.25));

    SimscapeXmlPart base, link, tip;

    Arm() {
        doc.root_name = "arm_on_base";
        doc.root_uid = "R00t";
        base = {"P-base", "base", true, 3.0, Vector3d(0, 0, -0.05), inertia(0.02, 0.03, 0.04, 0, 0, 0), "", {}};
        link = {"P-link", "link", true, 0.8, Vector3d(0.004, -0.003, 0.12),
                inertia(0.0042, 0.0045, 0.0006, 0.0001, -0.0002, 0.00015), "", {}};
        tip = {"P-tip", "tip", true, 0.25, Vector3d(0.01, 0.0, 0.02), inertia(0.0003, 0.0002, 0.0004, 0.00002, 0, 0),
               "", {}};
        doc.parts = {base, link, tip};
        SimscapeXmlInstance base_i{"Mbase1", "base <1>", "P-base", Isometry3d::Identity(), true, false, "", {}};
        SimscapeXmlInstance arm_i{"Marm1", "arm <1>", "A-arm", arm_at, false, false, "", {}};
        arm_i.children = {{"L1", "link <1>", "P-link", link1_at, false, false, "", {}},
                          {"L2", "link <2>", "P-link", link2_at, false, false, "hand", {}},
                          {"T1", "tip <1>", "P-tip", tip_at, false, false, "hand", {}}};
        doc.instances = {base_i, arm_i};
        // The shoulder's base frame on the base: where the link's foot is.
        const Isometry3d shoulder_world = arm_at * link1_at * shoulder_in_link;
        SimscapeXmlJoint shoulder{"Revolute", "shoulder", {{"Mbase1"}, shoulder_world}, {{"Marm1", "L1"}, shoulder_in_link}};
        doc.joints = {shoulder};
        // The elbow in the arm's own definition: paths from the arm's instances.
        const Isometry3d elbow_in_link2 = link2_at.inverse() * link1_at * elbow_in_link;
        SimscapeXmlJoint elbow{"Revolute", "elbow", {{"L1"}, elbow_in_link}, {{"L2"}, elbow_in_link2}};
        doc.assemblies = {{"A-arm", "arm", {elbow}}};
    }

    // The same mechanism as a CAD host would serve it: world poses, SI.
    mbx_memory::Assembly direct() const {
        mbx_memory::Assembly a;
        a.name = "arm_on_base";
        auto body = [&](const std::string& id, const SimscapeXmlPart& p, const Isometry3d& world, uint32_t flags) {
            mbx_memory::Body b;
            b.id = id;
            b.name = id;
            b.flags = flags;
            b.mass = p.mass;
            for (int k = 0; k < 3; ++k) b.com[k] = p.com[k];
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) b.inertia[3 * r + c] = p.inertia(r, c);
            b.pose = pose(world);
            a.bodies.push_back(b);
        };
        body("base", base, Isometry3d::Identity(), MBX_BODY_GROUND);
        body("link1", link, arm_at * link1_at, 0);
        body("link2", link, arm_at * link2_at, 0);
        body("tip", tip, arm_at * tip_at, 0);
        auto joint = [&](const std::string& id, const std::string& b0, const std::string& b1, const Isometry3d& at,
                         mbx_primitive_type type) {
            a.frames.push_back({id + "/b", id + "/b", b0, MBX_FRAME_IN_WORLD, {1, 1, 0}, pose(at)});
            a.frames.push_back({id + "/f", id + "/f", b1, MBX_FRAME_IN_WORLD, {1, 1, 0}, pose(at)});
            mbx_memory::Constraint c;
            c.id = c.name = id;
            c.base_frame_id = id + "/b";
            c.follower_frame_id = id + "/f";
            mbx_memory::Primitive p{};
            p.type = type;
            p.axis_reference = MBX_AXIS_IN_WORLD;
            const Vector3d z = at.linear().col(2);
            for (int k = 0; k < 3; ++k) p.axis[k] = z[k];
            c.chain.push_back(p);
            a.constraints.push_back(c);
        };
        joint("shoulder", "base", "link1", arm_at * link1_at * shoulder_in_link, MBX_PRIMITIVE_REVOLUTE);
        joint("elbow", "link1", "link2", arm_at * link1_at * elbow_in_link, MBX_PRIMITIVE_REVOLUTE);
        joint("hand", "link2", "tip", arm_at * link2_at, MBX_PRIMITIVE_WELD);
        return a;
    }

    static mbx_pose pose(const Isometry3d& x) {
        mbx_pose p{};
        for (int i = 0; i < 3; ++i) {
            p.position[i] = x.translation()[i];
            for (int j = 0; j < 3; ++j) p.rotation[3 * i + j] = x.linear()(i, j);
        }
        return p;
    }
};

using atest::check_same;
using atest::dynamics;

std::string write(atest::TempDir& dir, const std::string& name, const std::string& text) {
    const std::string path = dir.file(name);
    atest::write_file(path, text);
    return path;
}

const atest::FindingCopy* finding(const std::vector<atest::FindingCopy>& all, const std::string& code) {
    for (const atest::FindingCopy& f : all)
        if (f.code_name == code) return &f;
    return nullptr;
}

}  // namespace

TEST_CASE("simscape: nested instances, a shared part, a sub-assembly's joint and a rigid group are the mechanism a host serves in world coordinates") {
    const Arm arm;
    atest::TempDir dir("mbx_simscape");
    const std::string path = write(dir, "arm.xml", mbx_samples::simscape_xml(arm.doc));
    const auto adapter = mbx_files::SimscapeAdapter::open(path);
    const mbx_memory::Assembly& a = adapter->assembly();
    // One body per part instance, named by its path of uids; the grounded base fixed.
    REQUIRE(a.bodies.size() == 4);
    CHECK(a.bodies[0].id == "Mbase1");
    CHECK((a.bodies[0].flags & MBX_BODY_GROUND) != 0);
    CHECK(a.bodies[1].id == "Marm1/L1");
    CHECK(a.bodies[2].id == "Marm1/L2");
    CHECK(a.bodies[3].id == "Marm1/T1");
    CHECK(a.bodies[2].name == "arm <1>/link <2>");
    // The nested instance's pose is its parent's composed with its own.
    const Isometry3d expected = arm.arm_at * arm.link2_at;
    for (int i = 0; i < 3; ++i) {
        CHECK(a.bodies[2].pose.position[i] == mbx_test::within(expected.translation()[i], 1e-15, "rounding"));
        for (int j = 0; j < 3; ++j)
            CHECK(a.bodies[2].pose.rotation[3 * i + j] == mbx_test::within(expected.linear()(i, j), 1e-15, "rounding"));
    }
    // The root's shoulder, the arm's elbow (its id under the arm instance) and the hand's weld.
    REQUIRE(a.constraints.size() == 3);
    CHECK(a.constraints[0].id == "Marm1/rigidGroup:hand#1");
    CHECK(a.constraints[1].id == "shoulder");
    CHECK(a.constraints[2].id == "Marm1/elbow");
    // Mass matrix and inverse dynamics equal the directly served mechanism's.
    const mbx_memory::Host direct(arm.direct());
    check_same(dynamics(adapter->table(), 2), dynamics(direct.table(), 2), 1e-12);
}

TEST_CASE("simscape: the same file in inches and pounds, and without DataUnits in SI, is the same mechanism") {
    const Arm arm;
    atest::TempDir dir("mbx_simscape_units");
    const auto si = mbx_files::SimscapeAdapter::open(write(dir, "si.xml", mbx_samples::simscape_xml(arm.doc)));
    SimscapeXmlDocument imperial = arm.doc;
    imperial.length_unit = "inch";
    imperial.mass_unit = "lbm";
    imperial.per_metre = 1 / 0.0254;
    imperial.per_kilogram = 1 / 0.45359237;
    const std::string imperial_text = mbx_samples::simscape_xml(imperial);
    CHECK(imperial_text.find("<DataUnits length=\"inch\" mass=\"lbm\"/>") != std::string::npos);
    const auto in = mbx_files::SimscapeAdapter::open(write(dir, "in.xml", imperial_text));
    CHECK(in->model().length_to_m == 0.0254);
    CHECK(in->model().mass_to_kg == 0.45359237);
    check_same(dynamics(in->table(), 2), dynamics(si->table(), 2), 1e-12);
    // An older exporter's file without DataUnits is read as SI, and says so.
    SimscapeXmlDocument bare = arm.doc;
    bare.write_data_units = false;
    const auto old = mbx_files::SimscapeAdapter::open(write(dir, "old.xml", mbx_samples::simscape_xml(bare)));
    check_same(dynamics(old->table(), 2), dynamics(si->table(), 2), 0);
    atest::Translation t(old->table(), 0);
    const std::vector<atest::FindingCopy> all = t.findings();
    const atest::FindingCopy* f = finding(all, "simscape_no_data_units");
    REQUIRE(f != nullptr);
    CHECK(f->line == 2);
    CHECK(f->message.find("metres and kilograms") != std::string::npos);
}

TEST_CASE("simscape: inertia is read as Ixx Iyy Izz Iyz Izx Ixy with the products as tensor entries") {
    // A part whose six numbers are all different: each lands where the order says.
    const std::string text =
        "<SimscapeMultibodyImportXML version=\"2.0\"><DataUnits length=\"meter\" mass=\"kilogram\"/>"
        "<RootAssembly name=\"r\" uid=\"R\"><InstanceTree><Instance entityUid=\"P\" name=\"p\" uid=\"I\">"
        "<Transform><Rotation>1 0 0 0 1 0 0 0 1</Rotation><Translation>0 0 0</Translation></Transform></Instance>"
        "</InstanceTree><Joints/></RootAssembly><Parts><Part name=\"p\" uid=\"P\"><MassProperties><Mass>2</Mass>"
        "<CenterOfMass>0.1 0.2 0.3</CenterOfMass><Inertia>11 22 33 -0.23 -0.31 -0.12</Inertia></MassProperties>"
        "</Part></Parts></SimscapeMultibodyImportXML>";
    const mbx_files::SimscapeModel m = mbx_files::parse_simscape(text, "inertia.xml");
    REQUIRE(m.parts.size() == 1);
    const Matrix3d& I = m.parts[0].inertia;
    CHECK(I(0, 0) == 11);
    CHECK(I(1, 1) == 22);
    CHECK(I(2, 2) == 33);
    CHECK(I(1, 2) == -0.23);
    CHECK(I(2, 1) == -0.23);
    CHECK(I(2, 0) == -0.31);
    CHECK(I(0, 2) == -0.31);
    CHECK(I(0, 1) == -0.12);
    CHECK(I(1, 0) == -0.12);
    CHECK(m.parts[0].com == Vector3d(0.1, 0.2, 0.3));
}

TEST_CASE("simscape: each joint type moves along its frames' axes as Simscape's joint block does") {
    // Turned joint frames, so that a wrong axis gives another mass matrix.
    struct Case {
        const char* type;
        uint32_t nv;
        std::vector<std::pair<mbx_primitive_type, int>> chain;  // axis index in the joint frame
    };
    const std::vector<Case> cases = {
        {"Revolute", 1, {{MBX_PRIMITIVE_REVOLUTE, 2}}},
        {"Prismatic", 1, {{MBX_PRIMITIVE_PRISMATIC, 2}}},
        {"Cylindrical", 2, {{MBX_PRIMITIVE_PRISMATIC, 2}, {MBX_PRIMITIVE_REVOLUTE, 2}}},
        {"Spherical", 3, {{MBX_PRIMITIVE_SPHERICAL, 2}}},
        {"Planar", 3, {{MBX_PRIMITIVE_PRISMATIC, 0}, {MBX_PRIMITIVE_PRISMATIC, 1}, {MBX_PRIMITIVE_REVOLUTE, 2}}},
        {"PinSlot", 2, {{MBX_PRIMITIVE_PRISMATIC, 0}, {MBX_PRIMITIVE_REVOLUTE, 2}}},
        {"Universal", 2, {{MBX_PRIMITIVE_REVOLUTE, 0}, {MBX_PRIMITIVE_REVOLUTE, 1}}},
    };
    atest::TempDir dir("mbx_simscape_joints");
    const Isometry3d frame = placed(Vector3d(0.4, 1, -0.3), 1.1, Vector3d(0.1, 0.05, -0.2));
    const SimscapeXmlPart body{"P", "body", true, 1.5, Vector3d(0.2, -0.1, 0.05), inertia(0.03, 0.05, 0.04, 0.004, -0.002, 0.001), "", {}};
    for (const Case& c : cases) {
        CAPTURE(c.type);
        SimscapeXmlDocument doc;
        doc.root_name = "one_joint";
        doc.root_uid = "ROOT";
        doc.parts = {body};
        doc.instances = {{"B", "body <1>", "P", placed(Vector3d(1, 0, 0), 0.3, Vector3d(0.3, 0, 0.1)), false, false, "", {}}};
        // Base: the world (the root assembly's uid); follower: the body, its frame where the world's is.
        doc.joints = {{c.type, "j", {{"ROOT"}, frame}, {{"B"}, doc.instances[0].local.inverse() * frame}}};
        const auto adapter = mbx_files::SimscapeAdapter::open(write(dir, std::string(c.type) + ".xml", mbx_samples::simscape_xml(doc)));
        // The same joint served directly, its primitives along the world's view of the frame's axes.
        mbx_memory::Assembly a;
        a.name = "one_joint";
        mbx_memory::Body world;
        world.id = "world";
        world.flags = MBX_BODY_GROUND | MBX_BODY_HELPER;
        world.pose = Arm::pose(Isometry3d::Identity());
        mbx_memory::Body b;
        b.id = "body";
        b.mass = body.mass;
        for (int k = 0; k < 3; ++k) b.com[k] = body.com[k];
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k) b.inertia[3 * r + k] = body.inertia(r, k);
        b.pose = Arm::pose(doc.instances[0].local);
        a.bodies = {world, b};
        a.frames.push_back({"fb", "fb", "world", MBX_FRAME_IN_WORLD, {1, 1, 0}, Arm::pose(frame)});
        a.frames.push_back({"ff", "ff", "body", MBX_FRAME_IN_WORLD, {1, 1, 0}, Arm::pose(frame)});
        mbx_memory::Constraint joint;
        joint.id = joint.name = "j";
        joint.base_frame_id = "fb";
        joint.follower_frame_id = "ff";
        for (const auto& [type, axis] : c.chain) {
            mbx_memory::Primitive p{};
            p.type = type;
            p.axis_reference = MBX_AXIS_IN_WORLD;
            for (int k = 0; k < 3; ++k) p.axis[k] = frame.linear()(k, axis);
            joint.chain.push_back(p);
        }
        a.constraints = {joint};
        const mbx_memory::Host direct(a);
        check_same(dynamics(adapter->table(), c.nv), dynamics(direct.table(), c.nv), 1e-12);
    }
}

TEST_CASE("simscape: an unknown joint, a path to no instance and a missing part are findings naming the line") {
    Arm arm;
    arm.doc.joints.push_back({"Bushing", "odd", {{"Mbase1"}, Isometry3d::Identity()}, {{"Marm1", "L1"}, Isometry3d::Identity()}});
    arm.doc.joints.push_back({"Revolute", "lost", {{"Mbase1"}, Isometry3d::Identity()}, {{"Marm1", "nothing"}, Isometry3d::Identity()}});
    arm.doc.instances.push_back({"Mghost", "ghost <1>", "P-none", Isometry3d::Identity(), false, false, "", {}});
    const std::string text = mbx_samples::simscape_xml(arm.doc);
    atest::TempDir dir("mbx_simscape_bad");
    const auto adapter = mbx_files::SimscapeAdapter::open(write(dir, "bad.xml", text));
    atest::Translation t(adapter->table(), 0);
    const std::vector<atest::FindingCopy> all = t.findings();
    const atest::FindingCopy* unknown = finding(all, "simscape_unknown_joint");
    REQUIRE(unknown != nullptr);
    CHECK(unknown->line == atest::line_of(text, "<Bushing name=\"odd\">"));
    CHECK(unknown->message.find("Revolute, Prismatic") != std::string::npos);
    const atest::FindingCopy* lost = finding(all, "simscape_joint_unresolved");
    REQUIRE(lost != nullptr);
    CHECK(lost->subject_id == "lost");
    CHECK(lost->message.find("'nothing'") != std::string::npos);
    const atest::FindingCopy* ghost = finding(all, "simscape_missing_part");
    REQUIRE(ghost != nullptr);
    CHECK(ghost->line == atest::line_of(text, "uid=\"Mghost\""));
    // The rest still makes the arm.
    CHECK(t.status() == MBX_OK);
}

TEST_CASE("simscape: a rotation that is not one, a number that is not one and no root assembly are errors naming the line") {
    const Arm arm;
    const std::string good = mbx_samples::simscape_xml(arm.doc);
    auto error_of = [](const std::string& text) {
        try {
            mbx_files::parse_simscape(text, "bad.xml");
        } catch (const mbx_files::FileError& e) {
            return e;
        }
        FAIL("no error");
        return mbx_files::FileError("", 0, "");
    };
    const std::string rotation = "<Rotation>1 0 0 0 1 0 0 0 1 </Rotation>";
    REQUIRE(good.find(rotation) != std::string::npos);
    std::string skewed = good;
    skewed.replace(skewed.find(rotation), rotation.size(), "<Rotation>1 0 0 0 2 0 0 0 1</Rotation>");
    const mbx_files::FileError e1 = error_of(skewed);
    CHECK(e1.line() == atest::line_of(skewed, "<Rotation>1 0 0 0 2 0 0 0 1</Rotation>"));
    CHECK(e1.message().find("is not a rotation") != std::string::npos);
    std::string nan = good;
    nan.replace(nan.find("<Mass>"), 6, "<Mass>nan");
    const mbx_files::FileError e2 = error_of(nan);
    CHECK(e2.message().find("not a finite number") != std::string::npos);
    CHECK(e2.line() == atest::line_of(nan, "<Mass>nan"));
    const mbx_files::FileError e3 = error_of("<SimscapeMultibodyImportXML version=\"2.0\">\n<Parts/>\n</SimscapeMultibodyImportXML>");
    CHECK(e3.message().find("no <RootAssembly>") != std::string::npos);
    CHECK(e3.line() == 1);
    const mbx_files::FileError e4 = error_of(good.substr(0, good.size() / 2));
    CHECK(e4.message().find("not well-formed XML") != std::string::npos);
}

TEST_CASE("simscape: the input table picks the adapter by the root element, whatever the extension") {
    const Arm arm;
    atest::TempDir dir("mbx_simscape_table");
    const std::string path = write(dir, "export.dat", mbx_samples::simscape_xml(arm.doc));
    const mbx_files::InputFormat* f = mbx_files::input_format_of(path);
    REQUIRE(f != nullptr);
    CHECK(std::string(f->name) == "simscape");
    const auto input = mbx_files::open_input(path);
    atest::Translation t(input->table(), 0);
    CHECK(t.status() == MBX_OK);
    // (the base is the ground; the second link and the tip are one rigid group)
    CHECK(t.summary().rigid_body_count == 2);
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("simscape sample: the DFKI double pendulum on its real STEP levers is the analytic double pendulum, its shapes match its mass properties") {
    const std::string steps = mbx_test::shared_data("step/dfki_double_pendulum");
    mbx_files::FileInputOptions options;
    options.mesh_dirs = {steps};
    const auto adapter =
        mbx_files::SimscapeAdapter::open(std::string(MBX_SAMPLES_DIR) + "/double_pendulum_simscape/double_pendulum.xml", options);
    const mbx_files::SimscapeModel& m = adapter->model();
    REQUIRE(m.parts.size() == 3);
    CHECK(adapter->geometry_files().size() == 2);
    // Both hinges along the world's y axis: a planar double pendulum. Only
    // each lever's inertia about its own hinge axis (the levers' z) and its
    // centre of mass in the swing plane enter its mass matrix.
    const mbx_files::SimscapePart& a = m.parts[1];
    const mbx_files::SimscapePart& b = m.parts[2];
    const Eigen::Vector2d c1 = a.com.head<2>(), c2 = b.com.head<2>(), l1(0.2, 0);
    const double I1 = a.inertia(2, 2) + a.mass * c1.squaredNorm(), I2 = b.inertia(2, 2) + b.mass * c2.squaredNorm();
    atest::Translation t(adapter->table(), MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES);
    REQUIRE(t.status() == MBX_OK);
    mbx_context* ctx = t.context();
    mbx_sim_model* model = nullptr;
    mbx_sim_data* data = nullptr;
    REQUIRE(mbx_sim_model_create(ctx, t.mechanism(), nullptr, &model) == MBX_OK);
    REQUIRE(mbx_sim_data_create(ctx, model, &data) == MBX_OK);
    uint32_t shoulder = 0, elbow = 0;
    REQUIRE(mbx_sim_model_find_joint(model, "shoulder", &shoulder) == MBX_OK);
    REQUIRE(mbx_sim_model_find_joint(model, "elbow", &elbow) == MBX_OK);
    for (double q2 : {0.0, 0.7, -2.1, 3.0}) {
        CAPTURE(q2);
        const double q[2] = {shoulder == 0 ? 0.4 : q2, shoulder == 0 ? q2 : 0.4}, v[2] = {0, 0};
        REQUIRE(mbx_sim_set_state(ctx, data, 0, q, v) == MBX_OK);
        double M[4];
        REQUIRE(mbx_sim_mass_matrix(ctx, data, M) == MBX_OK);
        const Eigen::Vector2d turned = Eigen::Rotation2Dd(q2) * c2;
        const double coupling = b.mass * l1.dot(turned);
        const double M11 = I1 + I2 + b.mass * l1.squaredNorm() + 2 * coupling, M12 = I2 + coupling, M22 = I2;
        CHECK(M[shoulder * 2 + shoulder] == mbx_test::relative(M11, 1e-12));
        CHECK(M[shoulder * 2 + elbow] == mbx_test::relative(M12, 1e-12));
        CHECK(M[elbow * 2 + elbow] == mbx_test::relative(M22, 1e-12));
    }
    mbx_sim_data_destroy(data);
    mbx_sim_model_destroy(model);
    // Each lever's STEP solid was read and its centroid agrees with the XML's centre of mass.
    CHECK(t.mesh_total() == 2);
    CHECK(t.count(MBX_FINDING_MASS_MISMATCH) == 0);
    CHECK(t.count(MBX_FINDING_HOST_DIAGNOSTIC) == 0);
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("simscape sample: the DFKI double pendulum given by mates only is the same mechanism as with typed joints") {
    const std::string dir = std::string(MBX_SAMPLES_DIR) + "/double_pendulum_simscape/";
    const auto typed = mbx_files::SimscapeAdapter::open(dir + "double_pendulum.xml");
    const auto mated = mbx_files::SimscapeAdapter::open(dir + "double_pendulum_mates.xml");
    // Each hinge's concentric bore and coincident face make one revolute joint, named by its mates.
    const mbx_memory::Assembly& a = mated->assembly();
    REQUIRE(a.constraints.size() == 2);
    CHECK(a.constraints[0].id == "mates:Mmount1~Mlever1");
    CHECK(a.constraints[0].name == "Revolute from mates Concentric1, Coincident1");
    CHECK(a.constraints[1].name == "Revolute from mates Concentric2, Coincident2");
    for (const mbx_memory::Constraint& c : a.constraints) {
        REQUIRE(c.chain.size() == 1);
        CHECK(c.chain[0].type == MBX_PRIMITIVE_REVOLUTE);
    }
    check_same(dynamics(mated->table(), 2), dynamics(typed->table(), 2), 1e-12);
    atest::Translation t(mated->table(), 0);
    for (const atest::FindingCopy& f : t.findings()) CHECK(f.code_name.rfind("simscape_", 0) != 0);
}

}  // namespace MBX_UNITY_ID
