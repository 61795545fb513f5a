// Each builtin, translated by the real plugin, against its hand derivation
// (support/expected_builtins.cpp) and against SI world quantities recomputed
// here from the raw host data (support/stub_geometry.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <set>

#include "support/expected_builtins.h"
#include "support/plugin_fixture.h"
#include "support/stub_geometry.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace itest;

namespace {

std::pair<std::string, uint32_t> ref_of(const mbx_joint_info& j) { return {j.constraint_id, j.primitive_index}; }

bool is_reversed_expected(const ExpectedBuiltin& e, const mbx_joint_info& j) {
    for (const JointRef& r : e.reversed)
        if (r.constraint == j.constraint_id && r.primitive == j.primitive_index) return true;
    return false;
}

}  // namespace

TEST_CASE("builtins: summary counts match the hand derivation") {
    for (const ExpectedBuiltin& e : expected_builtins()) {
        INFO("builtin " << e.name);
        const Run r = translate_builtin(e.name);
        REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
        REQUIRE(r.get() != nullptr);
        const mbx_mechanism_summary s = summary(r.get());
        CHECK(s.part_count == e.parts);
        CHECK(s.rigid_body_count == e.rigid_bodies);
        CHECK(s.joint_node_count == e.joint_nodes);
        CHECK(s.joint_count == e.joints);
        CHECK(s.revolute_count == e.revolutes);
        CHECK(s.prismatic_count == e.prismatics);
        CHECK(s.spherical_count == e.sphericals);
        CHECK(s.weld_count == e.welds);
        CHECK(s.cut_joint_count == e.loops);
        CHECK(s.loop_count == e.loops);
        CHECK(s.planar_loop_count == e.planar_loops);
        CHECK(s.collapsed_weld_loop_count == 0);
        CHECK(s.dof == e.dof);
        CHECK(s.gruebler_dof == e.gruebler);
        CHECK(s.redundant_constraint_count == e.redundant);
        CHECK(s.floating_body_count == 0);
        CHECK(s.error_count == 0);
    }
}

TEST_CASE("builtins: the cut is the J_1 of the loop's last constraint in host order") {
    for (const ExpectedBuiltin& e : expected_builtins()) {
        INFO("builtin " << e.name);
        const Run r = translate_builtin(e.name);
        REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
        const mbx_mechanism* m = r.get();
        const mbx_mechanism_summary s = summary(m);
        REQUIRE(s.loop_count == e.loop_list.size());

        uint32_t cuts = 0;
        for (uint32_t i = 0; i < s.joint_count; ++i) {
            const mbx_joint_info j = joint(m, i);
            if (j.is_cut) {
                ++cuts;
                CHECK(j.loop >= 0);
            } else {
                CHECK(j.loop == -1);
            }
        }
        CHECK(cuts == e.loop_list.size());

        for (uint32_t l = 0; l < s.loop_count; ++l) {
            const ExpectedLoop& x = e.loop_list[l];
            INFO("loop " << l << " expected cut " << x.cut.constraint << " primitive " << x.cut.primitive);
            const mbx_loop_info info = loop(m, l);
            const mbx_joint_info cut = joint(m, info.cut_joint);
            CHECK(std::string(cut.constraint_id) == x.cut.constraint);
            CHECK(cut.primitive_index == x.cut.primitive);
            CHECK(cut.is_cut == 1);
            CHECK(cut.loop == int32_t(l));

            std::set<std::pair<std::string, uint32_t>> expected, actual;
            for (const JointRef& ref : x.members) expected.insert({ref.constraint, ref.primitive});
            const std::vector<uint32_t> members = loop_joints(m, l);
            for (uint32_t j : members) actual.insert(ref_of(joint(m, j)));
            CHECK(actual == expected);
            CHECK(members.size() == x.members.size());
            CHECK(info.joint_count == x.members.size());
            CHECK(std::count(members.begin(), members.end(), info.cut_joint) == 1);

            CHECK(info.dof == x.dof);
            CHECK(info.redundant == x.redundant);
            CHECK(info.gruebler_dof == x.gruebler);
            CHECK(info.planar == (x.planar ? 1 : 0));
            if (x.planar) {
                // The plane's normal is the (common) axis of the loop's revolutes.
                const Vec3 n = vec(info.planar_normal);
                CHECK(n.norm() == mbx_test::relative(1.0, 1e-6));
                CHECK(std::abs(n.dot(vec(cut.axis))) == mbx_test::relative(1.0, 1e-6));
            }
        }
    }
}

TEST_CASE("builtins: parts land in the expected rigid bodies") {
    for (const ExpectedBuiltin& e : expected_builtins()) {
        INFO("builtin " << e.name);
        const mbx_stub::Assembly a = builtin(e.name);
        const Run r = translate(a);
        REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
        const mbx_mechanism* m = r.get();

        for (const std::string& id : e.in_ground) CHECK_MESSAGE(find_part(m, id) == 0, id);
        std::map<uint32_t, std::set<std::string>> by_body;
        for (const auto& b : a.bodies) by_body[find_part(m, b.id)].insert(b.id);
        for (const auto& group : e.merged) {
            const uint32_t index = find_part(m, group.front());
            CHECK(by_body[index] == std::set<std::string>(group.begin(), group.end()));
            const mbx_rigid_body_info info = rigid_body(m, index);
            CHECK(info.kind == MBX_RIGID_BODY_DYNAMIC);
            CHECK(info.part_count == group.size());
        }
        // Every dynamic rigid body holds either one part or an expected group.
        const mbx_mechanism_summary s = summary(m);
        for (uint32_t i = 1; i <= s.rigid_body_count; ++i) {
            const mbx_rigid_body_info info = rigid_body(m, i);
            CHECK(info.kind == MBX_RIGID_BODY_DYNAMIC);
            CHECK(info.part_count == by_body[i].size());
            CHECK(by_body[i].count(info.id) == 1);  // named after one of its parts
        }
        for (uint32_t i = 1 + s.rigid_body_count; i < body_total(m); ++i)
            CHECK(rigid_body(m, i).kind == MBX_RIGID_BODY_JOINT_NODE);
        CHECK(rigid_body(m, 0).kind == MBX_RIGID_BODY_GROUND);

        // Tree directions: parent side is the CAD base unless listed as reversed.
        for (uint32_t i = 0; i < s.joint_count; ++i) {
            const mbx_joint_info j = joint(m, i);
            if (j.is_cut) continue;
            INFO("joint " << j.name);
            CHECK(j.reversed == (is_reversed_expected(e, j) ? 1 : 0));
            CHECK(rigid_body(m, j.child).parent_joint == int32_t(i));
        }
    }
}

TEST_CASE("builtins: joint frames and axes arrive in SI world coordinates") {
    // Frames come IN_WORLD and IN_BODY, axes IN_WORLD and IN_BASE_FRAME, in
    // mm (fourbar), cm bodies with mm frames (double_cardan), or SI.
    for (const ExpectedBuiltin& e : expected_builtins()) {
        INFO("builtin " << e.name);
        const mbx_stub::Assembly a = builtin(e.name);
        const Run r = translate(a);
        REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
        const mbx_mechanism* m = r.get();
        for (uint32_t i = 0; i < joint_total(m); ++i) {
            const mbx_joint_info j = joint(m, i);
            INFO("joint " << j.name);
            const mbx_stub::Constraint& c = constraint_by_id(a, j.constraint_id);
            REQUIRE(j.primitive_index < c.chain.size());
            const mbx_stub::Primitive& p = c.chain[j.primitive_index];
            CHECK(j.type == p.type);
            const WorldPose base = frame_world(a, frame_by_id(a, c.base_frame_id));
            CHECK((vec(j.frame.position) - base.p).norm() < 1e-9);
            const Vec3 axis = axis_world(a, c, p);
            const double along = vec(j.axis).dot(axis);
            CHECK((j.reversed ? std::abs(along) : along) == mbx_test::relative(1.0, 1e-12));
            CHECK(j.has_limits == (p.has_limits ? 1 : 0));
            if (p.has_limits && p.type == MBX_PRIMITIVE_REVOLUTE) {
                CHECK(j.lower == mbx_test::relative(p.lower, 1e-6));  // radians are SI already
                CHECK(j.upper == mbx_test::relative(p.upper, 1e-6));
            }
        }
    }
}

TEST_CASE("builtins: every rigid body carries the compound mass of its parts") {
    for (const ExpectedBuiltin& e : expected_builtins()) {
        INFO("builtin " << e.name);
        const mbx_stub::Assembly a = builtin(e.name);
        const Run r = translate(a);
        REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
        const mbx_mechanism* m = r.get();
        const mbx_mechanism_summary s = summary(m);
        for (uint32_t i = 1; i <= s.rigid_body_count; ++i) {
            const mbx_rigid_body_info info = rigid_body(m, i);
            INFO("rigid body " << info.id);
            std::vector<MassWorld> parts;
            std::vector<WorldPose> poses;
            for (const auto& b : a.bodies) {
                if (find_part(m, b.id) != i) continue;
                parts.push_back(mass_world(b));
                poses.push_back(body_world(b));
            }
            REQUIRE(!parts.empty());
            const MassWorld want = combine(parts);
            const WorldPose pose = world(info.pose, 1.0);
            CHECK(info.mass == mbx_test::relative(want.mass, 1e-12));
            CHECK((pose.apply(vec(info.com)) - want.com).norm() < 1e-12);
            const Mat3 inertia = pose.R * rotation(info.inertia) * pose.R.transpose();
            CHECK((inertia - want.inertia).cwiseAbs().maxCoeff() < 1e-9 * want.inertia.cwiseAbs().maxCoeff());
            // The body frame is the frame of one of its parts (the principal one).
            bool matches_a_part = false;
            for (const WorldPose& p : poses)
                matches_a_part |= (p.p - pose.p).norm() < 1e-12 && (p.R - pose.R).cwiseAbs().maxCoeff() < 1e-9;
            CHECK(matches_a_part);
        }
    }
}
}  // namespace MBX_UNITY_ID
