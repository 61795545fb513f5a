// URDF structure: spherical joints split into three revolutes, floating
// roots, odd CAD names, the cut-joint sidecar of a loop checked against the
// parsed links and mbx's kinematics, the loop warning, and byte-identical
// re-export.
#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "apps/stub_host/assemblies/builder.h"
#include "urdf_consumer.h"

namespace MBX_UNITY_ID {

using namespace urdf_test;
using nlohmann::json;

namespace {

using mbx_stub::build::axis_angle;
using mbx_stub::build::box_inertia;
using mbx_stub::build::box_mesh;
using mbx_stub::build::Prim;
using mbx_stub::build::revolute;
using mbx_stub::build::rotation_z_to;

// ground (turned and offset, with mass and a mesh)
//   -spherical "ball joint"- arm "arm/1 <é>"
//   -revolute "j" (limits)- arm "arm/1 <é>" (same name)
//   -prismatic "j" (no limits)- "3rd link"
//   -universal "J" (two revolutes, node "J#0")- "" (empty name)
//   -prismatic "slot" (limits)- "J_0" (the node's sanitized name)
// and a floating pair "float" -revolute "hinge"- "world" (the root link's name).
mbx_memory::Assembly odd_assembly() {
    using namespace mbx_stub::build;
    mbx_memory::Assembly a;
    a.name = "odd";
    const mbx_units si{1, 1, 1};
    Builder b(a, "odd", si, si);
    const Mat3 I = Mat3::Identity();
    b.body("ground", "Base plate", MBX_BODY_GROUND, 5.0, axis_angle(Vec3(1, 2, 3).normalized(), 0.4), Vec3(0.1, -0.2, 0.05),
           Vec3(0.1, -0.2, 0.0), box_inertia(5, 0.4, 0.3, 0.1));
    b.mesh("ground", box_mesh("plate", Vec3(0.4, 0.3, 0.1), I, Vec3(0, 0, -0.05)));

    const Vec3 S(0.2, 0.1, 0.3);
    b.body("arm1", "arm/1 <\xc3\xa9>", 0, 1.5, axis_angle(Vec3(0.3, -1, 0.5).normalized(), 0.9), S + Vec3(0.05, 0, 0),
           S + Vec3(0.1, 0.02, -0.01), box_inertia(1.5, 0.2, 0.05, 0.04));
    b.mesh("arm1", box_mesh("bar", Vec3(0.2, 0.05, 0.04), I, Vec3(0.05, 0, 0)));
    b.joint("ball", "ground", "arm1", S, axis_angle(Vec3(0, 1, 1).normalized(), 0.7), {spherical()}, MBX_FRAME_IN_BODY,
            MBX_FRAME_IN_WORLD)
        .name = "ball joint";

    const Vec3 E = S + Vec3(0.25, 0.05, 0);
    b.body("arm2", "arm/1 <\xc3\xa9>", 0, 0.8, axis_angle(Vec3(1, 0, 1).normalized(), -0.5), E,
           E + Vec3(0.08, 0, 0.01), box_inertia(0.8, 0.16, 0.04, 0.03));
    b.mesh("arm2", box_mesh("bar", Vec3(0.16, 0.04, 0.03), I, Vec3(0.08, 0, 0)));
    const Vec3 elbow_axis = Vec3(0, 0.3, 1).normalized();
    b.joint("elbow", "arm1", "arm2", E, rotation_z_to(elbow_axis, 0.2),
            {revolute(elbow_axis, MBX_AXIS_IN_WORLD, -1.0, 1.2)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_BODY)
        .name = "j";

    Prim slide;
    slide.type = MBX_PRIMITIVE_PRISMATIC;
    slide.axis = Vec3(1, 0.2, -0.1).normalized();
    const Vec3 P = E + Vec3(0.15, 0, 0.02);
    b.body("slider", "3rd link", 0, 0.4, axis_angle(Vec3(0, 0, 1), 0.3), P, P + Vec3(0.01, 0.01, 0),
           box_inertia(0.4, 0.05, 0.05, 0.05));
    b.joint("slide", "arm2", "slider", P, rotation_z_to(slide.axis, 0.1), {slide}, MBX_FRAME_IN_BODY, MBX_FRAME_IN_BODY)
        .name = "j";

    const Vec3 U = P + Vec3(0.1, 0.05, 0);
    b.body("tip", "", 0, 0.3, axis_angle(Vec3(1, 1, 0).normalized(), 1.1), U + Vec3(0.02, 0, 0), U + Vec3(0.03, 0, 0),
           box_inertia(0.3, 0.04, 0.02, 0.02));
    b.joint("uj", "slider", "tip", U, I,
            {revolute(Vec3::UnitX(), MBX_AXIS_IN_WORLD), revolute(Vec3::UnitY(), MBX_AXIS_IN_WORLD)},
            MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD)
        .name = "J";

    Prim slot = slide;
    slot.axis = Vec3(0, 1, 0);
    slot.has_limits = true;
    slot.lower = -0.02;
    slot.upper = 0.03;
    const Vec3 Q = U + Vec3(0.06, 0, 0);
    b.body("j0", "J_0", 0, 0.1, I, Q, Q, box_inertia(0.1, 0.02, 0.02, 0.02));
    b.joint("slot", "tip", "j0", Q, I, {slot}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);

    const Vec3 F(1, 1, 1);
    b.body("float", "float", 0, 0.5, axis_angle(Vec3(0, 1, 0), 0.6), F, F + Vec3(0, 0, 0.05),
           box_inertia(0.5, 0.1, 0.1, 0.1));
    b.mesh("float", box_mesh("cube", Vec3(0.1, 0.1, 0.1), I, Vec3(0, 0, 0.05)));
    b.body("float_child", "world", 0, 0.2, I, F + Vec3(0.1, 0, 0), F + Vec3(0.15, 0, 0),
           box_inertia(0.2, 0.1, 0.02, 0.02));
    b.joint("hinge", "float", "float_child", F + Vec3(0.1, 0, 0), I,
            {revolute(Vec3::UnitZ(), MBX_AXIS_IN_WORLD, -0.5, 0.5)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    return a;
}

ExportSettings named(const std::string& name) {
    ExportSettings s;
    s.model_name = name;
    return s;
}

Pose side_pose(const json& side) {
    return Pose{rpy_rotation(side["rpy"][0], side["rpy"][1], side["rpy"][2]),
                Vec3(side["xyz"][0], side["xyz"][1], side["xyz"][2])};
}

Vec3 side_axis(const json& side) { return Vec3(side["axis"][0], side["axis"][1], side["axis"][2]); }

int joint_index(const Mechanism& m, const std::string& cad_name) {
    for (size_t j = 0; j < m.joints.size(); ++j)
        if (m.joints[j].name == cad_name) return int(j);
    FAIL("no joint " << cad_name);
    return -1;
}

}  // namespace

TEST_CASE("urdf: spherical joint, prismatics, universal node and a floating pair match forward kinematics") {
    auto t = xtest::translate(odd_assembly());
    const Mechanism& m = *t->mechanism;
    REQUIRE(m.floating_roots == 1);
    const Result r = check_urdf(*t, 42, 6, named("odd"));

    const int ball = joint_index(m, "ball joint");
    REQUIRE(m.joints[size_t(ball)].type == MBX_PRIMITIVE_SPHERICAL);
    // x, y, z of the joint frame, in that order, through two massless links.
    const std::string base = r.layout.joint_name[size_t(ball)];
    const urdf::JointConstSharedPtr x = r.urdf->getJoint(base + "_x"), y = r.urdf->getJoint(base + "_y"),
                                    z = r.urdf->getJoint(base + "_z");
    REQUIRE((x && y && z));
    CHECK(y->parent_link_name == x->child_link_name);
    CHECK(z->parent_link_name == y->child_link_name);
    for (const auto& link : {x->child_link_name, y->child_link_name}) {
        const urdf::LinkConstSharedPtr l = r.urdf->getLink(link);
        REQUIRE(l);
        CHECK(!l->inertial);
        CHECK(!l->visual);
    }
    CHECK(to_vec(x->axis).isApprox(Vec3::UnitX()));
    CHECK(to_vec(y->axis).isApprox(Vec3::UnitY()));
    int approximations = 0;
    for (const Finding& f : r.notes)
        if (f.code == MBX_FINDING_EXPORT_APPROXIMATION) {
            ++approximations;
            CHECK((f.message.find("ball joint") != std::string::npos || f.message.find("'j'") != std::string::npos));
        }
    CHECK(approximations == 2);  // the spherical and the unlimited prismatic

    // The floating root hangs from the root by a floating joint at its CAD pose.
    const int fl = [&] {
        for (size_t b = 0; b < m.bodies.size(); ++b)
            if (b > 0 && m.bodies[b].parent_joint < 0) return int(b);
        return -1;
    }();
    REQUIRE(fl > 0);
    const urdf::LinkConstSharedPtr fl_link = r.urdf->getLink(r.layout.links[size_t(r.layout.body_link[size_t(fl)])].name);
    REQUIRE(fl_link);
    REQUIRE(fl_link->parent_joint);
    CHECK(fl_link->parent_joint->type == urdf::Joint::FLOATING);
    CHECK(fl_link->parent_joint->parent_link_name == "world");
    CHECK(pose_error(to_pose(fl_link->parent_joint->parent_to_joint_origin_transform), m.bodies[size_t(fl)].pose) < 1e-12);
    // Ground is fixed to the root at its (non-identity) pose.
    const urdf::LinkConstSharedPtr ground = r.urdf->getLink(r.layout.links[size_t(r.layout.body_link[0])].name);
    REQUIRE(ground);
    REQUIRE(ground->parent_joint);
    CHECK(ground->parent_joint->type == urdf::Joint::FIXED);
    CHECK(pose_error(to_pose(ground->parent_joint->parent_to_joint_origin_transform), m.bodies[0].pose) < 1e-12);
}

TEST_CASE("urdf: odd and colliding CAD names become unique identifiers") {
    auto t = xtest::translate(odd_assembly());
    const Result r = check_urdf(*t, 3, 1, named("my robot (v2)"));
    CHECK(r.layout.robot == "my_robot_v2");
    CHECK(r.files[0].path == "urdf/my_robot_v2.urdf");
    auto identifier = [](const std::string& n) {
        auto word = [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; };
        return !n.empty() && !std::isdigit(static_cast<unsigned char>(n[0])) && std::all_of(n.begin(), n.end(), word);
    };
    auto check_unique = [&](const std::vector<std::string>& names) {
        std::set<std::string> lower;
        for (const std::string& n : names) {
            CAPTURE(n);
            CHECK(identifier(n));
            std::string l = n;
            for (char& ch : l) ch = char(std::tolower(static_cast<unsigned char>(ch)));
            CHECK(lower.insert(l).second);
        }
    };
    std::vector<std::string> links, joints;
    for (const auto& [name, link] : r.urdf->links_) links.push_back(name);
    for (const auto& [name, joint] : r.urdf->joints_) joints.push_back(name);
    check_unique(links);
    check_unique(joints);
    // A body called "world" in CAD; the root keeps the name.
    CHECK(r.urdf->getRoot()->name == "world");
    const urdf::JointConstSharedPtr hinge = r.urdf->getJoint("hinge");
    REQUIRE(hinge);
    CHECK(hinge->child_link_name == "world_2");
    std::set<std::string> link_set(links.begin(), links.end()), joint_set(joints.begin(), joints.end());
    CHECK(link_set.count("arm_1") == 1);
    CHECK(link_set.count("arm_1_2") == 1);   // the second "arm/1 <é>"
    CHECK(link_set.count("_3rd_link") == 1);
    CHECK(link_set.count("J_0") == 1);
    CHECK(link_set.count("J_0_2") == 1);     // the universal's node, after the body named "J_0"
    CHECK(joint_set.count("j") == 1);
    CHECK(joint_set.count("j_2") == 1);
    CHECK(joint_set.count("ball_joint_x") == 1);
}

TEST_CASE("urdf: fourbar sidecar lists its cut joint where both links have it") {
    auto t = xtest::translate_builtin("fourbar");
    const Mechanism& m = *t->mechanism;
    const Result r = check_urdf(*t, 9, 2, named("fourbar"));
    const OutputFile* f = xtest::find_file(r.files, "urdf/fourbar.cut_joints.json");
    REQUIRE(f != nullptr);
    const json doc = json::parse(f->contents);
    CHECK(doc["format"] == "mbx-urdf-cut-joints");
    CHECK(doc["version"] == 1);
    CHECK(doc["robot"] == "fourbar");
    CHECK(doc["urdf"] == "fourbar.urdf");
    REQUIRE(doc["cut_joints"].size() == 1);
    const json& c = doc["cut_joints"][0];
    const int cut = joint_index(m, "rev_D");
    const Joint& joint = m.joints[size_t(cut)];
    REQUIRE(joint.cut);
    CHECK(c["name"] == r.layout.joint_name[size_t(cut)]);
    CHECK(c["cad_name"] == "rev_D");
    CHECK(c["type"] == "revolute");
    CHECK(c["loop"] == 0);
    CHECK(c["planar_loop"] == true);
    CHECK(c["limits"].is_null());
    CHECK(!r.urdf->getJoint(c["name"].get<std::string>()));  // not in the tree
    const std::string parent = c["parent"]["link"], child = c["child"]["link"];
    CHECK(parent == r.layout.links[size_t(r.layout.body_link[size_t(joint.parent)])].name);
    CHECK(child == r.layout.links[size_t(r.layout.body_link[size_t(joint.child)])].name);

    // At the assembly pose both sides are one frame, with one axis: the CAD axis.
    {
        const auto links = link_poses(*r.urdf, {});
        const Pose a = links.at(parent) * side_pose(c["parent"]), b = links.at(child) * side_pose(c["child"]);
        CHECK(pose_error(a, b) < 1e-9);
        CHECK((a.position - joint.frame.position).norm() < 1e-9);
        const Vec3 axis_a = links.at(parent).rotation * side_axis(c["parent"]);
        const Vec3 axis_b = links.at(child).rotation * side_axis(c["child"]);
        CHECK((axis_a - axis_b).norm() < 1e-9);
        CHECK((axis_a - tree_axis(joint)).norm() < 1e-9);
    }
    // Opened (random tree coordinates), each side still follows its own body.
    std::mt19937 rng(77);
    const ExportModel model = xtest::export_model(*t);
    for (int trial = 0; trial < 3; ++trial) {
        const Configuration q = random_configuration(m, r.layout, rng);
        const std::vector<Pose> fk = forward_kinematics(m, q.mbx);
        const auto links = link_poses(*r.urdf, q.urdf);
        const JointPlacement& p = model.placement(cut);
        CHECK(pose_error(links.at(parent) * side_pose(c["parent"]), fk[size_t(joint.parent)] * p.parent_to_joint) < 1e-9);
        CHECK(pose_error(links.at(child) * side_pose(c["child"]), fk[size_t(joint.child)] * p.joint_to_child.inverse()) <
              1e-9);
    }
}

TEST_CASE("urdf: the loop warning appears once for a looped model, never for a tree") {
    for (const std::string& name : mbx_stub::builtin_names()) {
        CAPTURE(name);
        auto t = xtest::translate_builtin(name);
        const Mechanism& m = *t->mechanism;
        ExportModel model = xtest::export_model(*t, named(name));
        OutputFiles files;
        export_urdf(model, files);
        export_urdf(model, files);  // a second run on the same model adds nothing
        const int expected = m.loops.empty() ? 0 : 1;
        CHECK(count_notes(model.notes(), MBX_FINDING_EXPORT_LOOPS_AS_TREE) == expected);
        for (const Finding& f : model.notes())
            if (f.code == MBX_FINDING_EXPORT_LOOPS_AS_TREE) {
                CHECK(f.severity == MBX_SEVERITY_WARNING);
                CHECK(f.subject.kind == MBX_SUBJECT_MODEL);
                CHECK(f.message.find(name + ".cut_joints.json") != std::string::npos);
            }
    }
    auto arm = xtest::translate_builtin("six_axis_arm");
    REQUIRE(arm->mechanism->loops.empty());  // the tree case above really ran
    auto fourbar = xtest::translate_builtin("fourbar");
    REQUIRE(fourbar->mechanism->loops.size() == 1);
}

TEST_CASE("urdf: re-export is byte-identical, and the written file parses from disk") {
    for (const char* name : {"double_cardan", "planar_sixbar"}) {
        CAPTURE(name);
        auto first = xtest::translate_builtin(name);
        auto second = xtest::translate_builtin(name);
        ExportModel a = xtest::export_model(*first, named(name)), b = xtest::export_model(*second, named(name));
        OutputFiles fa, fb;
        export_urdf(a, fa);
        export_urdf(b, fb);
        REQUIRE(fa.size() == fb.size());
        CHECK(fa.size() == (first->mechanism->loops.empty() ? 1u : 2u));
        for (size_t k = 0; k < fa.size(); ++k) {
            CHECK(fa[k].path == fb[k].path);
            CHECK(fa[k].contents == fb[k].contents);
        }
    }
    auto t = xtest::translate(odd_assembly());
    mbx_test::TempDir dir("mbx_urdf");
    const OutputFiles files = xtest::export_to(*t, dir, MBX_EXPORT_URDF, named("odd"));
    const urdf::ModelInterfaceSharedPtr parsed = urdf::parseURDFFile(dir.file("urdf/odd.urdf"));
    REQUIRE(parsed);
    std::ifstream in(dir.file("urdf/odd.urdf"), std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    CHECK(text.str() == urdf_file(files, "odd").contents);
}

TEST_CASE("urdf: rpy extraction round-trips through urdfdom, also at gimbal lock") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> angle(-3.1, 3.1);
    std::vector<Mat3> rotations;
    for (int k = 0; k < 200; ++k)
        rotations.push_back(Mat3(Eigen::AngleAxisd(angle(rng), Vec3(angle(rng), angle(rng), angle(rng)).normalized())));
    for (double pitch : {M_PI / 2, -M_PI / 2, M_PI / 2 - 1e-9, -M_PI / 2 + 1e-7})
        rotations.push_back(Mat3(Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
                                 Eigen::AngleAxisd(-1.2, Vec3::UnitX())));
    rotations.push_back(Mat3::Identity());
    rotations.push_back(Mat3(Eigen::AngleAxisd(M_PI, Vec3(1, 1, 0).normalized())));
    for (const Mat3& r : rotations) {
        const Vec3 rpy = rpy_from_rotation(r);
        CHECK((rpy_rotation(rpy.x(), rpy.y(), rpy.z()) - r).norm() < 1e-12);
    }
}
}  // namespace MBX_UNITY_ID
