#include <doctest/doctest.h>

#include <algorithm>

#include "assembly_builder.h"
#include "core/translator/translate.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

std::unique_ptr<Mechanism> run(const test::AssemblyBuilder& b) {
    Progress progress;
    return translate_assembly(b.a, {}, TranslateOptions{}, progress);
}

int count_code(const Mechanism& m, mbx_finding_code code, const std::string& subject_id = {}) {
    int n = 0;
    for (const Finding& f : m.findings)
        n += f.code == code && (subject_id.empty() || f.subject.id == subject_id);
    return n;
}

// Planar four-bar: ground pivots at (0,0) and (4,0), crank tip (0,1), rocker tip (4,2).
test::AssemblyBuilder fourbar(bool helper_root = true) {
    test::AssemblyBuilder b;
    int ground = b.part("ground", 10, Vec3(2, 0, 0), MBX_BODY_GROUND);
    int base = ground;
    if (helper_root) {
        int root = b.part("RootPart", 0, Vec3::Zero(), MBX_BODY_HELPER);
        int frame_link = b.part("frame_link", 2, Vec3(2, 0, 0));
        b.weld("w_root", ground, root);
        b.weld("w_frame", root, frame_link);
        base = frame_link;
    }
    int crank = b.part("crank", 1, Vec3(0, 0.5, 0));
    int coupler = b.part("coupler", 1, Vec3(2, 1.5, 0));
    int rocker = b.part("rocker", 1, Vec3(4, 1, 0));
    b.revolute("j_crank", base, crank, Vec3(0, 0, 0));
    b.revolute("j_coupler", crank, coupler, Vec3(0, 1, 0));
    b.revolute("j_rocker_tip", coupler, rocker, Vec3(4, 2, 0));
    b.revolute("j_rocker", base, rocker, Vec3(4, 0, 0));
    return b;
}

}  // namespace

TEST_CASE("four-bar: welds and helper merge into ground, the last loop joint in host order is cut") {
    auto m = run(fourbar());
    // ground + crank + coupler + rocker; ground, RootPart and frame_link are one body.
    REQUIRE(m->bodies.size() == 4);
    CHECK(m->bodies[0].parts.size() == 3);
    CHECK(m->weld_count == 2);
    REQUIRE(m->joints.size() == 4);
    REQUIRE(m->loops.size() == 1);
    const Joint& cut = m->joints[size_t(m->loops[0].cut_joint)];
    CHECK(cut.name == "j_rocker");
    CHECK(cut.cut);
    CHECK(cut.loop == 0);
    // j_rocker_tip reached the rocker from the coupler, so its base is the parent.
    const Joint& tip = m->joints[2];
    CHECK_FALSE(tip.cut);
    CHECK(m->bodies[size_t(tip.child)].name == "rocker");
    CHECK_FALSE(tip.reversed);
    CHECK(m->floating_roots == 0);
    CHECK(m->count(MBX_SEVERITY_ERROR) == 0);
}

TEST_CASE("cut joint choice follows host order") {
    test::AssemblyBuilder b = fourbar(false);
    // Move the crank joint to the end: now it closes the loop and is cut, and
    // the crank is reached through the coupler (its joint to the coupler is reversed).
    std::rotate(b.a.constraints.begin(), b.a.constraints.begin() + 1, b.a.constraints.end());
    auto m = run(b);
    REQUIRE(m->loops.size() == 1);
    CHECK(m->joints[size_t(m->loops[0].cut_joint)].name == "j_crank");
    const Joint* coupler_joint = nullptr;
    for (const Joint& j : m->joints)
        if (j.name == "j_coupler") coupler_joint = &j;
    REQUIRE(coupler_joint);
    CHECK(coupler_joint->reversed);  // CAD base (crank) is the tree child
    CHECK(m->bodies[size_t(coupler_joint->child)].name == "crank");
}

TEST_CASE("the same input gives the same mechanism") {
    auto m1 = run(fourbar());
    auto m2 = run(fourbar());
    REQUIRE(m1->joints.size() == m2->joints.size());
    for (size_t i = 0; i < m1->joints.size(); ++i) {
        CHECK(m1->joints[i].parent == m2->joints[i].parent);
        CHECK(m1->joints[i].child == m2->joints[i].child);
        CHECK(m1->joints[i].cut == m2->joints[i].cut);
    }
}

TEST_CASE("a multi-primitive chain becomes massless joint nodes, a cut chain cuts at J_1") {
    test::AssemblyBuilder b;
    int ground = b.part("ground", 1, Vec3::Zero(), MBX_BODY_GROUND);
    int slider = b.part("slider", 1, Vec3(0, 0, 1));
    // Cylindrical: prismatic + revolute along z.
    b.joint("cyl", ground, slider, Vec3(0, 0, 1), {MBX_PRIMITIVE_PRISMATIC, MBX_PRIMITIVE_REVOLUTE});
    auto m = run(b);
    REQUIRE(m->bodies.size() == 3);
    CHECK(m->bodies[2].kind == MBX_RIGID_BODY_JOINT_NODE);
    CHECK(m->bodies[2].id == "cyl#0");
    REQUIRE(m->joints.size() == 2);
    CHECK(m->joints[0].type == MBX_PRIMITIVE_PRISMATIC);
    CHECK(m->joints[0].parent == 0);
    CHECK(m->joints[0].child == 2);
    CHECK(m->joints[1].type == MBX_PRIMITIVE_REVOLUTE);
    CHECK(m->joints[1].parent == 2);
    CHECK(m->joints[1].child == 1);
    CHECK(m->dof == 2);

    // A second chain between the same bodies closes a loop: its J_1 is cut and
    // its J_N..J_2 stay in the tree hanging from the base.
    b.joint("cyl2", ground, slider, Vec3(0, 0, 1), {MBX_PRIMITIVE_PRISMATIC, MBX_PRIMITIVE_REVOLUTE});
    m = run(b);
    REQUIRE(m->loops.size() == 1);
    const Joint& cut = m->joints[size_t(m->loops[0].cut_joint)];
    CHECK(cut.name == "cyl2#1");
    CHECK(cut.type == MBX_PRIMITIVE_REVOLUTE);
    CHECK(m->joints[2].name == "cyl2#0");
    CHECK_FALSE(m->joints[2].cut);
    CHECK(m->dof == 2);  // the coaxial second cylinder removes nothing
}

TEST_CASE("helpers attached to nothing are dropped, unconnected and floating bodies are named") {
    test::AssemblyBuilder b;
    b.part("ground", 1, Vec3::Zero(), MBX_BODY_GROUND);
    b.part("lonely_root", 0, Vec3(1, 0, 0), MBX_BODY_HELPER);
    b.part("loose", 2, Vec3(2, 0, 0));
    int a1 = b.part("float_a", 1, Vec3(3, 0, 0));
    int a2 = b.part("float_b", 1, Vec3(4, 0, 0));
    b.revolute("float_joint", a1, a2, Vec3(3.5, 0, 0));
    auto m = run(b);
    CHECK(count_code(*m, MBX_FINDING_HELPER_BODY_DROPPED, "lonely_root") == 1);
    CHECK(m->part_body[1] == -1);
    CHECK(count_code(*m, MBX_FINDING_BODY_UNCONNECTED, "loose") == 1);
    CHECK(count_code(*m, MBX_FINDING_FLOATING_SUBASSEMBLY, "float_a") == 1);
    CHECK(m->floating_roots == 2);
    CHECK(m->dof == 6 + 6 + 1);
}

TEST_CASE("weld-only loops collapse and are reported") {
    test::AssemblyBuilder b;
    int g = b.part("ground", 1, Vec3::Zero(), MBX_BODY_GROUND);
    int p = b.part("p", 1, Vec3(1, 0, 0));
    int q = b.part("q", 1, Vec3(2, 0, 0));
    b.weld("w1", g, p);
    b.weld("w2", p, q);
    b.weld("w3", q, g);  // closes a loop of welds
    auto m = run(b);
    CHECK(m->bodies.size() == 1);
    CHECK(m->collapsed_weld_loops == 1);
    CHECK(count_code(*m, MBX_FINDING_WELD_LOOP_COLLAPSED, "w3") == 1);
    CHECK(m->loops.empty());
    CHECK(m->dof == 0);
}

TEST_CASE("a joint between parts welded together is ignored with a warning") {
    test::AssemblyBuilder b;
    int g = b.part("ground", 1, Vec3::Zero(), MBX_BODY_GROUND);
    int p = b.part("p", 1, Vec3(1, 0, 0));
    b.weld("w", g, p);
    b.revolute("stuck", g, p, Vec3(0.5, 0, 0));
    auto m = run(b);
    CHECK(m->joints.empty());
    CHECK(count_code(*m, MBX_FINDING_SELF_CONSTRAINT, "stuck") == 1);
}

TEST_CASE("validation names parts with bad inertia, massless bodies and joints whose frames are apart") {
    test::AssemblyBuilder b;
    int g = b.part("ground", 1, Vec3::Zero(), MBX_BODY_GROUND);
    int mirrored = b.part("mirrored", 1, Vec3(1, 0, 0), 0, Mat3::Identity(), Vec3(-1, -2, -2.5).asDiagonal());
    int flat = b.part("flat", 1, Vec3(2, 0, 0), 0, Mat3::Identity(), Vec3(1, 1, 3).asDiagonal());
    int ghost = b.part("ghost", 0, Vec3(3, 0, 0));
    b.revolute("j1", g, mirrored, Vec3(0.5, 0, 0));
    b.revolute("j2", mirrored, flat, Vec3(1.5, 0, 0));
    int j3 = b.revolute("j3", flat, ghost, Vec3(2.5, 0, 0));
    b.a.frames[size_t(b.a.constraints[size_t(j3)].follower_frame)].world.position = Vec3(2.5, 0.01, 0);
    auto m = run(b);
    CHECK(count_code(*m, MBX_FINDING_INERTIA_NOT_POSITIVE_DEFINITE, "mirrored") == 1);
    CHECK(count_code(*m, MBX_FINDING_INERTIA_TRIANGLE_INEQUALITY, "flat") == 1);
    CHECK(count_code(*m, MBX_FINDING_ZERO_MASS_BODY, "ghost") == 1);
    CHECK(count_code(*m, MBX_FINDING_JOINT_FRAMES_APART, "j3") == 1);
    CHECK(count_code(*m, MBX_FINDING_JOINT_FRAMES_APART, "j2") == 0);
    for (const Finding& f : m->findings)
        if (f.code == MBX_FINDING_JOINT_FRAMES_APART) CHECK(f.message.find("10 mm") != std::string::npos);
}

TEST_CASE("a prismatic joint may start slid along its axis, not across it") {
    test::AssemblyBuilder b;
    int g = b.part("ground", 1, Vec3::Zero(), MBX_BODY_GROUND);
    int s = b.part("slider", 1, Vec3(1, 0, 0));
    int c = b.joint("slide", g, s, Vec3(0, 0, 0), {MBX_PRIMITIVE_PRISMATIC}, Vec3::UnitX());
    b.a.frames[size_t(b.a.constraints[size_t(c)].follower_frame)].world.position = Vec3(0.3, 0, 0);
    auto m = run(b);
    CHECK(count_code(*m, MBX_FINDING_JOINT_FRAMES_APART) == 0);
    b.a.frames[size_t(b.a.constraints[size_t(c)].follower_frame)].world.position = Vec3(0.3, 0.2, 0);
    m = run(b);
    CHECK(count_code(*m, MBX_FINDING_JOINT_FRAMES_APART, "slide") == 1);
}
}  // namespace MBX_UNITY_ID
