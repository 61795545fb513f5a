// The stub's data must be right before it can judge the SDK: ids resolve,
// joint frames coincide, inertias are physical, and the hand-derived
// mobility of every builtin (and the generator's documented counts) agree
// with an independent screw-theory oracle. No plugin is needed here.
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <set>
#include <sstream>

#include "support/expected_builtins.h"
#include "support/screw_mobility.h"
#include "support/stub_geometry.h"

namespace MBX_UNITY_ID {

using namespace itest;
using mbx_stub::Assembly;

namespace {

// Relative to the assembly scale (about 1 m), far below the SDK's automatic
// tolerance of 1e-5 of the bounding-box diagonal.
constexpr double kCoincide = 1e-9;

void check_consistent(const Assembly& a) {
    INFO("assembly " << a.name);
    std::set<std::string> body_ids, frame_ids, constraint_ids;
    size_t ground = 0;
    for (const auto& b : a.bodies) {
        INFO("body " << b.id);
        CHECK(body_ids.insert(b.id).second);
        ground += (b.flags & MBX_BODY_GROUND) != 0;
        const Mat3 r = rotation(b.pose.rotation);
        CHECK((r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-12);
        CHECK(r.determinant() > 0);
        if (b.flags & MBX_BODY_HELPER) {
            CHECK(b.mass == 0);
            continue;
        }
        CHECK(b.mass > 0);
        const Mat3 inertia = rotation(b.inertia);
        CHECK((inertia - inertia.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * inertia.cwiseAbs().maxCoeff());
        const Eigen::Vector3d m = Eigen::SelfAdjointEigenSolver<Mat3>(inertia).eigenvalues();
        CHECK(m.minCoeff() > 0);
        CHECK(m(0) + m(1) >= m(2) * (1 - 1e-12));
        CHECK(m(0) + m(2) >= m(1) * (1 - 1e-12));
        CHECK(m(1) + m(2) >= m(0) * (1 - 1e-12));
    }
    CHECK(ground >= 1);
    for (const auto& f : a.frames) {
        INFO("frame " << f.id);
        CHECK(frame_ids.insert(f.id).second);
        CHECK(body_ids.count(f.body_id) == 1);
        const Mat3 r = rotation(f.pose.rotation);
        CHECK((r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-12);
    }
    for (const auto& c : a.constraints) {
        INFO("constraint " << c.id);
        CHECK(constraint_ids.insert(c.id).second);
        REQUIRE(frame_ids.count(c.base_frame_id) == 1);
        REQUIRE(frame_ids.count(c.follower_frame_id) == 1);
        REQUIRE(!c.chain.empty());
        const WorldPose base = frame_world(a, frame_by_id(a, c.base_frame_id));
        const WorldPose follower = frame_world(a, frame_by_id(a, c.follower_frame_id));
        CHECK((base.p - follower.p).norm() < kCoincide);
        CHECK((base.R - follower.R).cwiseAbs().maxCoeff() < 1e-9);
        for (const auto& p : c.chain)
            if (p.type == MBX_PRIMITIVE_REVOLUTE || p.type == MBX_PRIMITIVE_PRISMATIC)
                CHECK(std::abs(vec(p.axis).norm() - 1) < 1e-12);
    }
    for (const auto& [body_id, meshes] : a.shapes) {
        CHECK(body_ids.count(body_id) == 1);
        for (const auto& m : meshes) {
            REQUIRE(m.vertices.size() % 3 == 0);
            REQUIRE(m.triangles.size() % 3 == 0);
            for (uint32_t t : m.triangles) CHECK(t < m.vertices.size() / 3);
        }
    }
}

std::string serialize(const Assembly& a) {
    std::ostringstream out;
    out.precision(17);
    out << a.name << '|' << a.source << '\n';
    for (const auto& b : a.bodies) {
        out << b.id << ' ' << b.name << ' ' << b.flags << ' ' << b.mass;
        for (double v : b.com) out << ' ' << v;
        for (double v : b.inertia) out << ' ' << v;
        for (double v : b.pose.position) out << ' ' << v;
        for (double v : b.pose.rotation) out << ' ' << v;
        out << '\n';
    }
    for (const auto& f : a.frames) {
        out << f.id << ' ' << f.body_id << ' ' << f.reference;
        for (double v : f.pose.position) out << ' ' << v;
        for (double v : f.pose.rotation) out << ' ' << v;
        out << '\n';
    }
    for (const auto& c : a.constraints) {
        out << c.id << ' ' << c.base_frame_id << ' ' << c.follower_frame_id;
        for (const auto& p : c.chain) out << ' ' << p.type << ':' << p.axis[0] << ',' << p.axis[1] << ',' << p.axis[2];
        out << '\n';
    }
    for (const auto& [id, meshes] : a.shapes)
        for (const auto& m : meshes) {
            out << id << ' ' << m.name;
            for (double v : m.vertices) out << ' ' << v;
            out << '\n';
        }
    return out.str();
}

}  // namespace

TEST_CASE("stub: builtin names are sorted and every one loads") {
    const std::vector<std::string> names = mbx_stub::builtin_names();
    CHECK(names == std::vector<std::string>{"double_cardan", "fourbar", "planar_sixbar", "six_axis_arm"});
    for (const auto& name : names) {
        Assembly a;
        CHECK(mbx_stub::builtin_assembly(name, a));
        CHECK(a.name == name);
    }
    Assembly a;
    CHECK_FALSE(mbx_stub::builtin_assembly("no_such_assembly", a));
}

TEST_CASE("stub: builtins are self-consistent in their host units") {
    for (const auto& name : mbx_stub::builtin_names()) {
        Assembly a;
        REQUIRE(mbx_stub::builtin_assembly(name, a));
        check_consistent(a);
        // Both reference paths and both axis paths are served by every builtin.
        std::set<int> frame_refs, axis_refs;
        for (const auto& f : a.frames) frame_refs.insert(f.reference);
        for (const auto& c : a.constraints)
            for (const auto& p : c.chain)
                if (p.type == MBX_PRIMITIVE_REVOLUTE) axis_refs.insert(p.axis_reference);
        CHECK(frame_refs.size() == 2);
        CHECK(axis_refs.size() == 2);
        for (const auto& b : a.bodies)
            if (!(b.flags & MBX_BODY_HELPER)) CHECK_MESSAGE(a.shapes.count(b.id) == 1, "no mesh for " << b.id);
    }
}

TEST_CASE("stub: hand-derived mobility of the builtins agrees with the screw oracle") {
    for (const ExpectedBuiltin& e : expected_builtins()) {
        INFO("builtin " << e.name);
        Assembly a;
        REQUIRE(mbx_stub::builtin_assembly(e.name, a));
        const OracleResult r = screw_mobility(a);
        CHECK(a.bodies.size() == e.parts);
        CHECK(r.rigid_bodies == e.rigid_bodies);
        CHECK(r.joint_nodes == e.joint_nodes);
        CHECK(r.joints == e.joints);
        CHECK(r.dof == e.dof);
        CHECK(r.redundant == int(e.redundant));
        REQUIRE(r.loops.size() == e.loop_list.size());
        for (size_t l = 0; l < r.loops.size(); ++l) {
            INFO("loop " << l);
            CHECK(r.loops[l].cut_constraint == e.loop_list[l].cut.constraint);
            CHECK(r.loops[l].cut_primitive == e.loop_list[l].cut.primitive);
            CHECK(r.loops[l].joint_count == e.loop_list[l].members.size());
            CHECK(r.loops[l].dof == e.loop_list[l].dof);
            CHECK(r.loops[l].redundant == int(e.loop_list[l].redundant));
            CHECK(r.loops[l].planar == e.loop_list[l].planar);
        }
    }
}

TEST_CASE("stub: generated assemblies match their documented counts") {
    const std::pair<size_t, uint32_t> cases[] = {{0, 1},   {2, 1},   {3, 7},   {10, 2},
                                                 {57, 3}, {200, 1}, {200, 2}, {401, 9}};
    for (const auto& one : cases) {
        const size_t n = one.first;
        const uint32_t seed = one.second;
        INFO("generate_assembly(" << n << ", " << seed << ")");
        mbx_stub::GeneratedCounts c;
        const Assembly a = mbx_stub::generate_assembly(n, seed, &c);
        check_consistent(a);
        CHECK(c.parts == std::max<size_t>(n, 2));
        CHECK(a.bodies.size() == c.parts);
        size_t welds = 0, revolutes = 0, sphericals = 0, helpers = 0;
        for (const auto& con : a.constraints) {
            bool weld = true;
            for (const auto& p : con.chain) {
                weld = weld && p.type == MBX_PRIMITIVE_WELD;
                revolutes += p.type == MBX_PRIMITIVE_REVOLUTE;
                sphericals += p.type == MBX_PRIMITIVE_SPHERICAL;
            }
            welds += weld;
        }
        for (const auto& b : a.bodies) helpers += (b.flags & MBX_BODY_HELPER) != 0;
        CHECK(welds == c.welds);
        CHECK(revolutes == c.revolutes);
        CHECK(sphericals == c.sphericals);
        CHECK(helpers == c.helpers);
        CHECK(c.joints == c.revolutes + c.sphericals);
        CHECK(c.rigid_bodies == c.parts - 1 - c.welds);
        CHECK(c.loops == c.planar_loops + c.spatial_loops);

        const OracleResult r = screw_mobility(a);
        CHECK(r.rigid_bodies == c.rigid_bodies);
        CHECK(r.joint_nodes == c.joint_nodes);
        CHECK(r.joints == c.joints);
        CHECK(r.loops.size() == c.loops);
        size_t planar = 0;
        for (const auto& l : r.loops) {
            planar += l.planar;
            CHECK(l.joint_count == 4);  // loops are local to their cluster
        }
        CHECK(planar == c.planar_loops);
        CHECK(r.dof == c.dof);
        CHECK(r.redundant == int(c.redundant));
    }
}

TEST_CASE("stub: generated assemblies have loops and clusters at scale") {
    // The figures quoted in generator.cpp's comment.
    mbx_stub::GeneratedCounts c;
    const Assembly a = mbx_stub::generate_assembly(1000, 42, &c);
    CHECK(a.bodies.size() == 1000);
    CHECK(c.branches == 25);
    CHECK(c.welds == 203);
    CHECK(c.helpers == 69);
    CHECK(c.rigid_bodies == 796);
    CHECK(c.joint_nodes == 37);
    CHECK(c.loops == 125);
    CHECK(c.planar_loops == 53);
    CHECK(c.dof == 655);
    CHECK(c.max_depth == 36);
}

TEST_CASE("stub: the generator is deterministic and seed-dependent") {
    CHECK(serialize(mbx_stub::generate_assembly(150, 5)) == serialize(mbx_stub::generate_assembly(150, 5)));
    CHECK(serialize(mbx_stub::generate_assembly(150, 5)) != serialize(mbx_stub::generate_assembly(150, 6)));
    Assembly x, y;
    REQUIRE(mbx_stub::builtin_assembly("double_cardan", x));
    REQUIRE(mbx_stub::builtin_assembly("double_cardan", y));
    CHECK(serialize(x) == serialize(y));
}
}  // namespace MBX_UNITY_ID
