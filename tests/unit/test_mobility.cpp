// Mobility analysis on hand-built mechanisms whose answers are derived by
// hand (Grübler plus the special geometry each one has).
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/mobility/mobility.h"
#include "core/mobility/rank.h"
#include "core/mobility/twist.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

const Vec3 Z = Vec3::UnitZ();

// Builds a spanning tree by hand: bodies are added before their children,
// so depths can be filled in as joints are added.
struct Builder {
    Mechanism mech;

    explicit Builder(double size = 2.0) {
        mech.assembly.size = size;
        RigidBody ground;
        ground.kind = MBX_RIGID_BODY_GROUND;
        ground.id = ground.name = "ground";
        mech.bodies.push_back(ground);
    }
    int body(const std::string& name) {
        RigidBody b;
        b.id = b.name = name;
        mech.bodies.push_back(b);
        return static_cast<int>(mech.bodies.size()) - 1;
    }
    // A root other than ground (the test sets floating_roots itself).
    int floating(const std::string& name) { return body(name); }
    int joint(const std::string& name, mbx_primitive_type type, int parent, int child, const Vec3& axis,
              const Vec3& point) {
        Joint j;
        j.type = type;
        j.name = name;
        j.parent = parent;
        j.child = child;
        j.axis = axis.normalized();
        j.frame.position = point;
        mech.joints.push_back(j);
        return static_cast<int>(mech.joints.size()) - 1;
    }
    int tree(const std::string& name, mbx_primitive_type type, int parent, int child, const Vec3& axis,
             const Vec3& point) {
        int j = joint(name, type, parent, child, axis, point);
        mech.bodies[child].parent_joint = j;
        mech.bodies[child].depth = mech.bodies[parent].depth + 1;
        return j;
    }
    int cut(const std::string& name, mbx_primitive_type type, int parent, int child, const Vec3& axis,
            const Vec3& point) {
        int j = joint(name, type, parent, child, axis, point);
        mech.joints[j].cut = true;
        mech.joints[j].loop = static_cast<int>(mech.loops.size());
        Loop loop;
        loop.cut_joint = j;
        mech.loops.push_back(loop);
        return j;
    }
    int revolute(const std::string& name, int parent, int child, const Vec3& point, const Vec3& axis = Z) {
        return tree(name, MBX_PRIMITIVE_REVOLUTE, parent, child, axis, point);
    }
};

Mechanism analyzed(Mechanism mech, int dense_column_limit = MobilitySettings{}.dense_column_limit) {
    MobilitySettings settings;
    settings.dense_column_limit = dense_column_limit;
    Progress silent;
    analyze_mobility(mech, TranslateOptions{}, silent, settings);
    return mech;
}

int count(const Mechanism& mech, mbx_finding_code code) {
    int n = 0;
    for (const Finding& f : mech.findings) n += f.code == code;
    return n;
}

const Finding* first(const Mechanism& mech, mbx_finding_code code) {
    for (const Finding& f : mech.findings)
        if (f.code == code) return &f;
    return nullptr;
}

bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

// Planar four-bar: crank O_A-A, coupler A-B, rocker B-O_B. The cut closes at
// the rocker pin B (parent: coupler, child: rocker).
struct FourBar {
    Vec3 oa{0, 0, 0}, a{0.3, 0.4, 0}, b{1.2, 0.9, 0}, ob{1.0, 0, 0};
    int crank_pivot, crank_pin, rocker_pivot, rocker_pin;
    Builder build;

    explicit FourBar(const Vec3& offset = Vec3::Zero(), double scale = 1.0, double model_size = 2.0)
        : build(model_size) {
        oa *= scale;
        a *= scale;
        b *= scale;
        ob *= scale;
        int crank = build.body("crank"), coupler = build.body("coupler"), rocker = build.body("rocker");
        crank_pivot = build.revolute("crank pivot", 0, crank, oa + offset);
        crank_pin = build.revolute("crank pin", crank, coupler, a + offset, -Z);  // either sign is parallel
        rocker_pivot = build.revolute("rocker pivot", 0, rocker, ob + offset);
        rocker_pin = build.cut("rocker pin", MBX_PRIMITIVE_REVOLUTE, coupler, rocker, Z, b + offset);
    }
};

// Deterministic scatter in [-1, 1].
double wobble(int i, int salt) { return std::sin(12.9898 * i + 78.233 * salt + 0.5); }

Vec3 generic_axis(int i) { return Vec3(wobble(i, 1), wobble(i, 2), wobble(i, 3) + 0.2).normalized(); }

// Ladder of n four-bars sharing their rungs: rails a_k (tree, a_0 = ground)
// and b_k; loop k is a_{k-1} -X_k- a_k -Y_k- b_k -Z_k(cut)- b_{k-1} -Y_{k-1}- a_{k-1}.
// Planar: all axes z, dof 1 (the first four-bar; every later loop adds a
// dyad). Spatial: generic axes, every loop is a rigid 4R, dof 0.
Mechanism ladder(int n, bool planar) {
    Builder build(n + 1.0);
    auto axis = [&](int i) { return planar ? Z : generic_axis(i); };
    auto point = [&](double x, double y, int i) {
        return Vec3(x + 0.1 * wobble(i, 4), y + 0.1 * wobble(i, 5), planar ? 0.0 : 0.2 * wobble(i, 6));
    };
    int b_prev = build.body("b0");
    build.revolute("Y0", 0, b_prev, point(0, 0.5, 0), axis(0));
    int a_prev = 0;
    for (int k = 1; k <= n; ++k) {
        const std::string s = std::to_string(k);
        int a = build.body("a" + s), b = build.body("b" + s);
        build.revolute("X" + s, a_prev, a, point(k - 0.5, 0, 3 * k), axis(3 * k));
        build.revolute("Y" + s, a, b, point(k, 0.5, 3 * k + 1), axis(3 * k + 1));
        build.cut("Z" + s, MBX_PRIMITIVE_REVOLUTE, b_prev, b, axis(3 * k + 2), point(k - 0.5, 1.2, 3 * k + 2));
        a_prev = a;
        b_prev = b;
    }
    return build.mech;
}

}  // namespace

TEST_CASE("mobility: planar four-bar has one freedom and three planar redundancies") {
    FourBar fb;
    Mechanism m = analyzed(fb.build.mech);
    REQUIRE(m.loops.size() == 1);
    const Loop& loop = m.loops[0];
    CHECK(loop.dof == 1);
    CHECK(loop.redundant == 3);
    CHECK(loop.planar);
    CHECK(loop.planar_normal.isApprox(Z));
    CHECK(loop.gruebler_dof == 1);
    CHECK(m.dof == 1);
    CHECK(m.redundant == 3);
    CHECK(m.gruebler_dof == -2);

    CHECK(count(m, MBX_FINDING_PLANAR_LOOP) == 1);
    CHECK(count(m, MBX_FINDING_REDUNDANT_CONSTRAINTS) == 0);
    CHECK(count(m, MBX_FINDING_MOBILITY_MISMATCH) == 0);
    const Finding* planar = first(m, MBX_FINDING_PLANAR_LOOP);
    REQUIRE(planar);
    CHECK(planar->severity == MBX_SEVERITY_INFO);
    CHECK(planar->subject.kind == MBX_SUBJECT_LOOP);
    CHECK(planar->subject.id == "loop0");
    CHECK(contains(planar->message, "cut at joint \"rocker pin\""));
    CHECK(contains(planar->message, "\"crank pivot\""));
    CHECK(contains(planar->message, "(0, 0, 1)"));
}

TEST_CASE("mobility: loop order and signs close on the hand-computed crank motion") {
    FourBar fb;
    // The host gave this joint follower-relative-to-base, follower on the
    // parent side: its child-w.r.t.-parent axis is -(-z) = +z.
    fb.build.mech.joints[fb.crank_pin].reversed = true;
    Mechanism m = analyzed(fb.build.mech);
    const Loop& loop = m.loops[0];
    // Cut first, the child (rocker) side up to ground, then ground down to
    // the parent (coupler).
    CHECK(loop.joints == std::vector<int>{fb.rocker_pin, fb.rocker_pivot, fb.crank_pivot, fb.crank_pin});
    CHECK(loop.signs == std::vector<int>{-1, +1, -1, -1});

    // Crank rate 1; coupler w3 and rocker w4 from v_B = v_A + w3 z x (B - A)
    // = w4 z x (B - O_B). All rotations are about +z.
    auto perp = [](const Vec3& r) { return Eigen::Vector2d(-r.y(), r.x()); };
    const double w2 = 1;
    Eigen::Matrix2d lhs;
    lhs << perp(fb.b - fb.ob), -perp(fb.b - fb.a);
    Eigen::Vector2d w34 = lhs.colPivHouseholderQr().solve(w2 * perp(fb.a - fb.oa));
    const double w4 = w34[0], w3 = w34[1];
    // Child w.r.t. parent rates about +z, in loop order.
    Eigen::Vector4d rate(w4 - w3, w4, w2, w3 - w2);

    // Independent of the module's twists: world-origin twists about +z.
    Eigen::Matrix<double, 6, 1> sum = Eigen::Matrix<double, 6, 1>::Zero();
    const Vec3 points[4] = {fb.b, fb.ob, fb.oa, fb.a};
    for (int k = 0; k < 4; ++k) {
        Eigen::Matrix<double, 6, 1> s;
        s << Z, points[k].cross(Z);
        sum += loop.signs[k] * s * rate[k];
    }
    CHECK(sum.norm() < 1e-12);
    // The module's own (referred, scaled, reversal-aware) Jacobian agrees.
    CHECK((mobility::loop_jacobian(m, loop, mobility::loop_frame(m, loop, 1e-9)) * rate).norm() < 1e-12);
    CHECK(rate.norm() > 0.5);
}

TEST_CASE("mobility: loop below a moving body stops at the lowest common ancestor") {
    // Base body 1 on ground; a four-bar on it: 1-2-4 and 1-3, cut 4-3.
    Builder build;
    int b1 = build.body("base"), b2 = build.body("crank"), b3 = build.body("rocker"), b4 = build.body("coupler");
    build.revolute("J1", 0, b1, Vec3(-1, 0, 0));
    int j2 = build.revolute("J2", b1, b2, Vec3(0, 0, 0));
    int j3 = build.revolute("J3", b1, b3, Vec3(1.1, 0.1, 0));
    int j4 = build.revolute("J4", b2, b4, Vec3(0.2, 0.6, 0));
    int j5 = build.cut("J5", MBX_PRIMITIVE_REVOLUTE, b4, b3, Z, Vec3(1.0, 1.0, 0));
    Mechanism m = analyzed(build.mech);
    const Loop& loop = m.loops[0];
    CHECK(loop.joints == std::vector<int>{j5, j3, j2, j4});
    CHECK(loop.signs == std::vector<int>{-1, +1, -1, -1});
    CHECK(loop.dof == 1);
    CHECK(m.dof == 2);  // the four-bar plus the base's rotation

    // Telescoping: with any body "potentials" V, sign-weighted differences
    // V(child) - V(parent) around a correctly traced loop cancel.
    Eigen::VectorXd potential(static_cast<Eigen::Index>(m.bodies.size()));
    for (Eigen::Index b = 0; b < potential.size(); ++b) potential[b] = wobble(static_cast<int>(b), 7);
    double sum = 0;
    for (size_t k = 0; k < loop.joints.size(); ++k) {
        const Joint& j = m.joints[loop.joints[k]];
        sum += loop.signs[k] * (potential[j.child] - potential[j.parent]);
    }
    CHECK(std::abs(sum) < 1e-12);
}

TEST_CASE("mobility: spatial RSSR moves with the crank and the coupler's idle spin") {
    Builder build;
    int crank = build.body("crank"), coupler = build.body("coupler"), rocker = build.body("rocker");
    build.revolute("R1", 0, crank, Vec3(0, 0, 0), Z);
    build.tree("S_A", MBX_PRIMITIVE_SPHERICAL, crank, coupler, Z, Vec3(0.5, 0, 0.1));
    build.revolute("R2", 0, rocker, Vec3(2, 0, 0), Vec3(1, 0, 0.3));
    build.cut("S_B", MBX_PRIMITIVE_SPHERICAL, coupler, rocker, Z, Vec3(1.5, 0.8, 0.6));
    Mechanism m = analyzed(build.mech);
    const Loop& loop = m.loops[0];
    CHECK(loop.dof == 2);
    CHECK(loop.redundant == 0);
    CHECK_FALSE(loop.planar);
    CHECK(loop.gruebler_dof == 2);
    CHECK(m.dof == 2);
    CHECK(m.gruebler_dof == 2);
    CHECK(m.findings.empty());
}

TEST_CASE("mobility: skew 4R loop without Bennett geometry is rigid") {
    Builder build;
    int b1 = build.body("l1"), b2 = build.body("l2"), b3 = build.body("l3");
    build.revolute("R1", 0, b1, Vec3(0, 0, 0), Vec3(1, 0.2, 0.1));
    build.revolute("R2", b1, b2, Vec3(1, 0, 0.2), Vec3(0.1, 1, 0.3));
    build.revolute("R3", b2, b3, Vec3(1.1, 1, 0), Vec3(0.3, -0.2, 1));
    build.cut("R4", MBX_PRIMITIVE_REVOLUTE, b3, 0, Vec3(-0.5, 0.4, 0.7), Vec3(0, 0.9, 0.4));
    Mechanism m = analyzed(build.mech);
    const Loop& loop = m.loops[0];
    CHECK(loop.dof == 0);
    CHECK(loop.redundant == 2);
    CHECK_FALSE(loop.planar);
    CHECK(loop.gruebler_dof == -2);
    CHECK(m.dof == 0);
    CHECK(m.redundant == 2);

    const Finding* redundant = first(m, MBX_FINDING_REDUNDANT_CONSTRAINTS);
    REQUIRE(redundant);
    CHECK(redundant->severity == MBX_SEVERITY_WARNING);
    CHECK(contains(redundant->message, "2 redundant constraints"));
    CHECK(contains(redundant->message, "cut at joint \"R4\""));
    const Finding* mismatch = first(m, MBX_FINDING_MOBILITY_MISMATCH);
    REQUIRE(mismatch);
    CHECK(mismatch->severity == MBX_SEVERITY_INFO);
    CHECK(contains(mismatch->message, "rigid"));
}

TEST_CASE("mobility: slider-crank is a planar loop with one freedom") {
    Builder build;
    int crank = build.body("crank"), rod = build.body("rod"), slider = build.body("slider");
    build.revolute("crank pivot", 0, crank, Vec3(0, 0, 0), -Z);
    build.revolute("crank pin", crank, rod, Vec3(0.3, 0.2, 0));
    build.revolute("wrist pin", rod, slider, Vec3(1.0, 0.05, 0));
    build.cut("slide", MBX_PRIMITIVE_PRISMATIC, 0, slider, Vec3(1, 0, 0), Vec3(1.0, 0.05, 0));
    Mechanism m = analyzed(build.mech);
    const Loop& loop = m.loops[0];
    CHECK(loop.planar);
    CHECK(loop.planar_normal.isApprox(Z));
    CHECK(loop.dof == 1);
    CHECK(loop.redundant == 3);
    CHECK(loop.gruebler_dof == 1);
    CHECK(m.dof == 1);
    CHECK(count(m, MBX_FINDING_REDUNDANT_CONSTRAINTS) == 0);
}

TEST_CASE("mobility: a prismatic joint along the normal makes a loop non-planar") {
    Builder build;
    int crank = build.body("crank"), rod = build.body("rod"), slider = build.body("slider");
    build.revolute("crank pivot", 0, crank, Vec3(0, 0, 0));
    build.revolute("crank pin", crank, rod, Vec3(0.3, 0.2, 0));
    build.revolute("wrist pin", rod, slider, Vec3(1.0, 0.05, 0));
    build.cut("slide", MBX_PRIMITIVE_PRISMATIC, 0, slider, Z, Vec3(1.0, 0.05, 0));
    Mechanism m = analyzed(build.mech);
    CHECK_FALSE(m.loops[0].planar);
    CHECK(m.loops[0].gruebler_dof == -2);
}

TEST_CASE("mobility: planar five-bar has two freedoms") {
    Builder build;
    int l1 = build.body("l1"), l2 = build.body("l2"), l3 = build.body("l3"), l4 = build.body("l4");
    build.revolute("O1", 0, l1, Vec3(0, 0, 0));
    build.revolute("A", l1, l2, Vec3(0.2, 0.5, 0));
    build.revolute("O2", 0, l4, Vec3(1.5, 0, 0));
    build.revolute("C", l4, l3, Vec3(1.7, 0.6, 0));
    build.cut("B", MBX_PRIMITIVE_REVOLUTE, l2, l3, Z, Vec3(0.9, 1.1, 0));
    Mechanism m = analyzed(build.mech);
    CHECK(m.loops[0].dof == 2);
    CHECK(m.loops[0].redundant == 3);
    CHECK(m.loops[0].gruebler_dof == 2);
    CHECK(m.dof == 2);
}

TEST_CASE("mobility: coaxial revolutes are special geometry beyond planarity") {
    Builder build;
    int wheel = build.body("wheel");
    build.revolute("bearing 1", 0, wheel, Vec3(0, 0, 0));
    build.cut("bearing 2", MBX_PRIMITIVE_REVOLUTE, 0, wheel, Z, Vec3(0, 0, 0.5));
    Mechanism m = analyzed(build.mech);
    const Loop& loop = m.loops[0];
    CHECK(loop.planar);
    CHECK(loop.dof == 1);
    CHECK(loop.redundant == 5);
    CHECK(loop.gruebler_dof == -1);
    const Finding* redundant = first(m, MBX_FINDING_REDUNDANT_CONSTRAINTS);
    REQUIRE(redundant);
    CHECK(contains(redundant->message, "2 redundant constraints beyond"));
    const Finding* mismatch = first(m, MBX_FINDING_MOBILITY_MISMATCH);
    REQUIRE(mismatch);
    CHECK(contains(mismatch->message, "special"));
}

TEST_CASE("mobility: six-bar with two coupled loops has one freedom on both rank paths") {
    // Four-bar G-1-2-3 plus a dyad 4-5 from ternary coupler 2 to ground.
    Builder build;
    int l1 = build.body("crank"), l2 = build.body("coupler"), l3 = build.body("rocker");
    int l4 = build.body("link 4"), l5 = build.body("link 5");
    int o1 = build.revolute("O1", 0, l1, Vec3(0, 0, 0));
    int a = build.revolute("A", l1, l2, Vec3(0.4, 0.8, 0));
    int b = build.revolute("B", l2, l3, Vec3(1.8, 1.2, 0));
    int o3 = build.cut("O3", MBX_PRIMITIVE_REVOLUTE, 0, l3, Z, Vec3(2.0, 0, 0));
    int c = build.revolute("C", l2, l4, Vec3(1.0, 1.6, 0));
    int o5 = build.revolute("O5", 0, l5, Vec3(-0.8, 1.0, 0));
    int d = build.cut("D", MBX_PRIMITIVE_REVOLUTE, l4, l5, Z, Vec3(0.2, 2.4, 0));

    for (int limit : {256, 0}) {
        CAPTURE(limit);
        Mechanism m = analyzed(build.mech, limit);
        REQUIRE(m.loops.size() == 2);
        CHECK(m.loops[0].joints == std::vector<int>{o3, b, a, o1});
        CHECK(m.loops[0].signs == std::vector<int>{-1, +1, +1, +1});
        CHECK(m.loops[1].joints == std::vector<int>{d, o5, o1, a, c});
        CHECK(m.loops[1].signs == std::vector<int>{-1, +1, -1, -1, -1});
        CHECK(m.loops[0].dof == 1);
        CHECK(m.loops[1].dof == 2);  // the five-bar G-1-2-4-5 alone
        CHECK(m.dof == 1);
        CHECK(m.redundant == 6);
        CHECK(m.gruebler_dof == -5);
        CHECK(count(m, MBX_FINDING_PLANAR_LOOP) == 2);
        CHECK(m.count(MBX_SEVERITY_WARNING) == 0);
    }
}

TEST_CASE("mobility: serial chain and floating root") {
    Builder build;
    int b1 = build.body("b1"), b2 = build.body("b2"), b3 = build.body("b3");
    build.revolute("R", 0, b1, Vec3(0, 0, 0));
    build.tree("P", MBX_PRIMITIVE_PRISMATIC, b1, b2, Vec3(1, 0, 0), Vec3(0.5, 0, 0));
    build.tree("S", MBX_PRIMITIVE_SPHERICAL, b2, b3, Z, Vec3(1, 0, 0));
    Mechanism chain = analyzed(build.mech);
    CHECK(chain.loops.empty());
    CHECK(chain.dof == 5);
    CHECK(chain.gruebler_dof == 5);
    CHECK(chain.redundant == 0);
    CHECK(chain.findings.empty());

    int root = build.floating("free");
    int arm = build.body("arm");
    build.revolute("hinge", root, arm, Vec3(3, 0, 0));
    build.mech.floating_roots = 1;
    Mechanism floating = analyzed(build.mech);
    CHECK(floating.dof == 5 + 1 + 6);
    CHECK(floating.gruebler_dof == 5 + 1 + 6);
}

TEST_CASE("mobility: a cut joint between separate trees is an internal error") {
    Builder build;
    int b1 = build.body("b1"), root = build.floating("free");
    build.revolute("R", 0, b1, Vec3(0, 0, 0));
    build.cut("bridge", MBX_PRIMITIVE_REVOLUTE, b1, root, Z, Vec3(1, 0, 0));
    build.mech.floating_roots = 1;
    Mechanism m = build.mech;
    try {
        analyze_mobility(m, TranslateOptions{});
        FAIL("expected an error");
    } catch (const Error& e) {
        CHECK(e.status() == MBX_ERROR_INTERNAL);
        CHECK(e.subject().id == "loop0");
        CHECK(contains(e.what(), "bridge"));
    }
}

TEST_CASE("mobility: results do not depend on where the model sits or how big it is") {
    SUBCASE("far from the origin") {
        FourBar far(Vec3(1e5, -3e4, 2e4));
        Mechanism m = analyzed(far.build.mech);
        CHECK(m.loops[0].dof == 1);
        CHECK(m.loops[0].redundant == 3);
        CHECK(m.loops[0].planar);
        CHECK(m.dof == 1);
    }
    SUBCASE("a 1 cm four-bar in a 100 m model") {
        FourBar tiny(Vec3(40, 10, 3), 0.01, 100.0);
        tiny.build.mech.length_tolerance = 1e-5 * 100.0;
        Mechanism m = analyzed(tiny.build.mech);
        CHECK(m.loops[0].dof == 1);
        CHECK(m.loops[0].redundant == 3);
        CHECK(m.dof == 1);
    }
}

TEST_CASE("mobility: long ladders keep exactly one freedom at any model size") {
    // The mobility attenuates along the ladder, so its null vector is
    // graded; the sparse check must find it without counting it twice when
    // a column was already dropped for it. With one length for the whole
    // model instead of one per loop, the translational rows of unit loops in
    // a 2001 m model fall below the tolerance (9 spurious freedoms).
    Mechanism m = analyzed(ladder(2000, true));
    CHECK(m.assembly.size == 2001.0);
    CHECK(m.dof == 1);
    CHECK(m.redundant == 6000);
}

TEST_CASE("mobility: loops of very different sizes sharing a prismatic joint") {
    // Two slider-cranks drive one slider, one a thousand times smaller.
    Builder build(2.0);
    int c1 = build.body("crank 1"), r1 = build.body("rod 1"), slider = build.body("slider");
    int c2 = build.body("crank 2"), r2 = build.body("rod 2");
    build.tree("slide", MBX_PRIMITIVE_PRISMATIC, 0, slider, Vec3(1, 0, 0), Vec3(1.0, 0.05, 0));
    build.revolute("O1", 0, c1, Vec3(0, 0, 0));
    build.revolute("A1", c1, r1, Vec3(0.3, 0.2, 0));
    build.cut("B1", MBX_PRIMITIVE_REVOLUTE, r1, slider, Z, Vec3(1.0, 0.05, 0));
    const Vec3 base(1.0, 0.05, 0);
    build.revolute("O2", 0, c2, base + Vec3(-0.0007, -0.0004, 0));
    build.revolute("A2", c2, r2, base + Vec3(-0.0005, 0.0003, 0));
    build.cut("B2", MBX_PRIMITIVE_REVOLUTE, r2, slider, Z, base + Vec3(0.0001, 0.0001, 0));
    build.mech.length_tolerance = 1e-9;
    for (int limit : {256, 0}) {
        CAPTURE(limit);
        Mechanism m = analyzed(build.mech, limit);
        CHECK(m.loops[0].dof == 1);
        CHECK(m.loops[1].dof == 1);
        CHECK(m.loops[0].planar);
        CHECK(m.loops[1].planar);
        CHECK(m.dof == 1);
        CHECK(m.redundant == 6);
    }
}

TEST_CASE("mobility: planar normal sign is deterministic") {
    // Plane spanned by u = (1, 1, 0)/sqrt2 and z; axes given as +-n with
    // n = (-1, 1, 0)/sqrt2; the reported normal has a positive x.
    const Vec3 n = Vec3(-1, 1, 0).normalized(), u = Vec3(1, 1, 0).normalized();
    auto at = [&](double x, double y) { return Vec3(x * u + y * Z); };
    Builder build;
    int crank = build.body("crank"), coupler = build.body("coupler"), rocker = build.body("rocker");
    build.revolute("O_A", 0, crank, at(0, 0), n);
    build.revolute("A", crank, coupler, at(0.3, 0.4), -n);
    build.revolute("O_B", 0, rocker, at(1.0, 0), n);
    build.cut("B", MBX_PRIMITIVE_REVOLUTE, coupler, rocker, -n, at(1.2, 0.9));
    Mechanism m = analyzed(build.mech);
    CHECK(m.loops[0].planar);
    CHECK(m.loops[0].planar_normal.isApprox(-n));
    CHECK(m.loops[0].dof == 1);
    const Finding* planar = first(m, MBX_FINDING_PLANAR_LOOP);
    REQUIRE(planar);
    CHECK(contains(planar->message, "(0.707107, -0.707107, 0)"));
}

TEST_CASE("mobility: a loop planar only within tolerance reports the numeric difference") {
    // One axis tilted by 9e-6 rad: parallel within the planarity tolerance
    // (1e-5), not within the rank tolerance, so the loop locks numerically.
    FourBar fb;
    const double tilt = 9e-6;
    fb.build.mech.joints[fb.crank_pin].axis = Vec3(std::sin(tilt), 0, -std::cos(tilt));
    Mechanism m = analyzed(fb.build.mech);
    const Loop& loop = m.loops[0];
    CHECK(loop.planar);
    CHECK(loop.gruebler_dof == 1);
    CHECK(loop.dof == 0);
    CHECK(count(m, MBX_FINDING_REDUNDANT_CONSTRAINTS) == 0);
    const Finding* mismatch = first(m, MBX_FINDING_MOBILITY_MISMATCH);
    REQUIRE(mismatch);
    CHECK(contains(mismatch->message, "planarity tolerance"));
}

TEST_CASE("mobility: progress ticks per loop and a host can cancel") {
    Mechanism m = ladder(2100, true);
    int calls = 0;
    auto cancel = [](void* user, const char*, double fraction) -> int {
        ++*static_cast<int*>(user);
        return fraction > 0 ? 1 : 0;  // let the stage start, stop at the first tick report
    };
    Progress progress(cancel, &calls);
    try {
        analyze_mobility(m, TranslateOptions{}, progress);  // opens its own "mobility" stage
        FAIL("expected cancellation");
    } catch (const Error& e) {
        CHECK(e.status() == MBX_ERROR_CANCELLED);
    }
    CHECK(calls == 2);
}

TEST_CASE("mobility: dense and sparse ranks agree on coupled ladders") {
    const int n = 40;  // 121 columns: dense by default
    for (int limit : {256, 0}) {
        CAPTURE(limit);
        Mechanism planar = analyzed(ladder(n, true), limit);
        CHECK(planar.dof == 1);
        CHECK(planar.redundant == 3 * n);
        CHECK(planar.gruebler_dof == 3 * n + 1 - 6 * n);
        Mechanism spatial = analyzed(ladder(n, false), limit);
        CHECK(spatial.dof == 0);
        CHECK(spatial.redundant == 3 * n - 1);
        for (const Loop& loop : spatial.loops) CHECK(loop.dof == 0);
    }
}

TEST_CASE("mobility: dense and sparse ranks agree on random coupled mechanisms") {
    // Random trees with short-cycle cut joints; axes drawn from a small set
    // so that exact special geometry (parallel axes, planar sub-loops) is
    // common, points from a coarse grid so that some coincide.
    for (int seed = 0; seed < 24; ++seed) {
        CAPTURE(seed);
        int draw = seed * 1000;
        auto next = [&](int range) {
            double u = 0.5 * (wobble(++draw, 17) + 1.0);
            return std::min(range - 1, static_cast<int>(u * range));
        };
        const Vec3 axes[4] = {Z, Vec3::UnitX(), Vec3(1, 1, 0).normalized(), generic_axis(seed)};
        auto type = [&]() {
            int t = next(10);
            return t < 6 ? MBX_PRIMITIVE_REVOLUTE : t < 8 ? MBX_PRIMITIVE_PRISMATIC : MBX_PRIMITIVE_SPHERICAL;
        };
        auto point = [&]() { return Vec3(0.5 * next(4), 0.5 * next(4), 0.5 * next(3)); };
        Builder build(3.0);
        const int bodies = 40;
        for (int b = 1; b <= bodies; ++b) {
            build.body("b" + std::to_string(b));
            int parent = std::max(0, b - 1 - next(3));
            build.tree("t" + std::to_string(b), type(), parent, b, axes[next(4)], point());
        }
        for (int c = 0; c < 20; ++c) {
            int a = 1 + next(bodies), b = std::min(bodies, a + 1 + next(4));
            build.cut("c" + std::to_string(c), type(), a, b, axes[next(4)], point());
        }
        build.mech.length_tolerance = 1e-9;
        Mechanism dense = analyzed(build.mech, 100000);
        Mechanism sparse = analyzed(build.mech, 0);
        CHECK(dense.dof == sparse.dof);
        CHECK(dense.redundant == sparse.redundant);
        CHECK(dense.dof >= 0);
    }
}

TEST_CASE("mobility: sparse rank matches dense rank on a block-sparse matrix with planted dependencies") {
    // 30 row blocks of 6 rows over 60 columns, each touching 5 columns;
    // columns 50..59 are then replaced by combinations of earlier ones.
    const int blocks = 30, columns = 60;
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(6 * blocks, columns);
    for (int b = 0; b < blocks; ++b)
        for (int k = 0; k < 5; ++k) {
            int c = (2 * b + 7 * k) % columns;
            for (int r = 0; r < 6; ++r) m(6 * b + r, c) = wobble(b * 100 + k * 10 + r, 8);
        }
    for (int c = 50; c < columns; ++c) m.col(c) = m.col(c - 50) - 0.5 * m.col(c - 49);
    std::vector<mobility::RowBlock> rows;
    for (int b = 0; b < blocks; ++b) {
        mobility::RowBlock block;
        for (int c = 0; c < columns; ++c)
            if (m.block(6 * b, c, 6, 1).norm() > 0) block.columns.push_back(c);
        block.values.resize(6, static_cast<Eigen::Index>(block.columns.size()));
        for (size_t k = 0; k < block.columns.size(); ++k)
            block.values.col(static_cast<Eigen::Index>(k)) = m.block(6 * b, block.columns[k], 6, 1);
        rows.push_back(block);
    }
    CHECK(mobility::assemble(rows, columns).isApprox(m));
    const int dense = mobility::dense_rank(m, 1e-6);
    CHECK(dense == 50);
    CHECK(mobility::sparse_rank(rows, columns, 1e-6) == dense);
}

TEST_CASE("mobility: sparse rank sees a graded dependency that local pivots miss") {
    // Blocks of 2 rows over columns k, k+1, k+2, both orthogonal to the
    // local part of x with x_k ~ 2^-k: J x = 0 with x spanning 1e-90. The
    // elimination runs from column 0, so the last column's pivot is its
    // residual amplified by 1/x_last, far above tau; only the check of the
    // pivot rows finds the missing rank.
    const int n = 300, columns = n + 2;
    Eigen::VectorXd x(columns);
    for (int k = 0; k < columns; ++k) x[k] = std::ldexp(1.0 + 0.2 * wobble(k, 10), -k);
    std::vector<mobility::RowBlock> rows;
    for (int k = 0; k < n; ++k) {
        mobility::RowBlock block;
        block.columns = {k, k + 1, k + 2};
        const Eigen::Vector3d local = x.segment(k, 3).normalized();
        block.values.resize(2, 3);
        for (int r = 0; r < 2; ++r) {
            Eigen::Vector3d g(wobble(k, 11 + r), wobble(k, 13 + r), wobble(k, 15 + r));
            block.values.row(r) = (g - g.dot(local) * local).transpose();
        }
        rows.push_back(block);
    }
    const Eigen::MatrixXd j = mobility::assemble(rows, columns);
    CHECK((j * x).norm() < 1e-12);
    CHECK(mobility::dense_rank(j, 1e-6) == n + 1);
    CHECK(mobility::sparse_rank(rows, columns, 1e-6) == n + 1);
    // Pinning the end where x is large restores full rank (pinning the other
    // end would not: 1e-90 is below any tolerance).
    mobility::RowBlock pin;
    pin.columns = {0};
    pin.values = Eigen::MatrixXd::Ones(1, 1);
    rows.push_back(pin);
    CHECK(mobility::dense_rank(mobility::assemble(rows, columns), 1e-6) == n + 2);
    CHECK(mobility::sparse_rank(rows, columns, 1e-6) == n + 2);
}

TEST_CASE("mobility: a 10 000-loop ladder keeps its single freedom") {
    // A long coupled group is where the sparse path and its scaling matter;
    // its speed is measured by bench_translate, not here.
    const int n = 10000;
    Mechanism m = ladder(n, true);
    analyze_mobility(m, TranslateOptions{});
    CHECK(m.loops.size() == static_cast<size_t>(n));
    CHECK(m.dof == 1);
    CHECK(m.redundant == 3 * n);
}
}  // namespace MBX_UNITY_ID
