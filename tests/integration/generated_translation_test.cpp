// Generated assemblies at benchmark scale translate to exactly the counts
// the generator documents (which the stub tests verify independently with a
// screw oracle), deterministically.
#include <doctest/doctest.h>

#include <algorithm>

#include "support/fingerprint.h"
#include "support/plugin_fixture.h"

namespace MBX_UNITY_ID {

using namespace itest;

TEST_CASE("generated: translation counts match the generator's") {
    const std::pair<size_t, uint32_t> cases[] = {{2, 1}, {25, 3}, {200, 1}, {200, 2}, {1000, 42}};
    for (const auto& one : cases) {
        const size_t n = one.first;
        const uint32_t seed = one.second;
        INFO("generate_assembly(" << n << ", " << seed << ")");
        mbx_stub::GeneratedCounts c;
        const Run r = translate(mbx_stub::generate_assembly(n, seed, &c));
        REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
        const mbx_mechanism_summary s = summary(r.get());
        CHECK(s.part_count == c.parts);
        CHECK(s.rigid_body_count == c.rigid_bodies);
        CHECK(s.joint_node_count == c.joint_nodes);
        CHECK(s.joint_count == c.joints);
        CHECK(s.revolute_count == c.revolutes);
        CHECK(s.spherical_count == c.sphericals);
        CHECK(s.prismatic_count == 0);
        CHECK(s.weld_count == c.welds);
        CHECK(s.loop_count == c.loops);
        CHECK(s.cut_joint_count == c.loops);
        CHECK(s.planar_loop_count == c.planar_loops);
        CHECK(s.collapsed_weld_loop_count == 0);
        CHECK(s.dof == c.dof);
        CHECK(s.redundant_constraint_count == c.redundant);
        CHECK(s.floating_body_count == 0);
        CHECK(s.error_count == 0);
        CHECK(r.host->counts().shapes == 0);

        // Loops stay local (4 joints each) and the tree stays as shallow as documented.
        for (uint32_t l = 0; l < s.loop_count; ++l) CHECK(loop(r.get(), l).joint_count == 4);
        size_t deepest = 0;
        for (uint32_t b = 1; b < body_total(r.get()); ++b) {
            size_t depth = 0;
            for (uint32_t at = b; at != 0; ++depth) {
                const int32_t up = rigid_body(r.get(), at).parent_joint;
                REQUIRE(up >= 0);
                at = joint(r.get(), uint32_t(up)).parent;
                REQUIRE(depth < body_total(r.get()));
            }
            deepest = std::max(deepest, depth);
        }
        CHECK(deepest == c.max_depth);
    }
}

TEST_CASE("generated: translating the same assembly twice gives the same mechanism") {
    const mbx_stub::Assembly a = mbx_stub::generate_assembly(300, 8);
    const Run one = translate(a), two = translate(a);
    REQUIRE(one.status == MBX_OK);
    REQUIRE(two.status == MBX_OK);
    CHECK(fingerprint(one.get()) == fingerprint(two.get()));
}
}  // namespace MBX_UNITY_ID
