// match_shapes on a 100k-node scene: the spatial hash keeps the cost near
// linear, so this takes well under a second; the bound is loose for slow or
// instrumented builds.
#include <chrono>
#include <cstdint>

#include <doctest/doctest.h>

#include "scene_builder.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace matching_test;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

// Deterministic and the same on every platform.
class Lcg {
public:
    double uniform() {
        state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
        return double(state_ >> 11) * 0x1.0p-53;
    }

private:
    uint64_t state_ = 12345;
};

}  // namespace

TEST_CASE("a 100k-node scene matches in near-linear time") {
    const int side = 37;  // 37^3 = 50653 grid points, 0.1 apart
    const size_t body_count = 50000;
    Lcg rng;
    std::vector<mbx_files::BodyPose> bodies;
    bodies.reserve(body_count);
    for (size_t b = 0; b < body_count; ++b) {
        // Every tenth body shares the previous one's position, turned: the
        // orientation filter runs at scale too.
        const size_t slot = b % 10 == 9 ? b - 1 : b;
        const Vector3d p(0.1 * double(slot % side), 0.1 * double(slot / side % side), 0.1 * double(slot / side / side));
        const Vector3d axis(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5 + 1e-3);
        const double angle = 0.5 + 2.0 * rng.uniform();
        bodies.push_back(body(std::to_string(b), "PART" + std::to_string(b), p, rot(axis, angle)));
    }
    // Every body: its part Transform, and under it a shifted part holding
    // the shape (the CAD-export layout) -> 100k nodes. Shapes in mm, model
    // in m, so the automatic scale has to try its factors on all of them.
    SceneBuilder s;
    for (size_t b = body_count; b-- > 0;) {
        const auto& w = bodies[b].world;
        const int t = s.add(-1, pose(1000 * Vector3d(w.translation()), w.linear()), "", "PART" + std::to_string(b));
        const int child = s.add(t, pose(Vector3d(30, 0, 0)), "", "", "Group");
        s.mesh(child, tetra("", 10));
    }
    REQUIRE(s.scene.nodes.size() == 100000);

    const auto t0 = std::chrono::steady_clock::now();
    const mbx_files::MatchResult r = mbx_files::match_shapes(s.scene, bodies);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MESSAGE("matched 100000 nodes against 50000 bodies (automatic scale) in " << seconds << " s");
    CHECK(seconds < 10);
    CHECK(r.vrml_scale == mbx_test::relative(0.001, 1e-6));
    CHECK(r.issues.empty());
    CHECK(r.matched_nodes == body_count);
    REQUIRE(r.meshes.size() == body_count);
    // Nodes come in reverse body order.
    for (size_t i = 0; i < r.meshes.size(); i += 997) CHECK(r.meshes[i].body == int(body_count - 1 - i));
    // The shape's origin sits 30 mm along its body's x.
    CHECK((first_vertex(r.meshes[123]) - Vector3d(0.03, 0, 0)).norm() < 1e-9);
}
}  // namespace MBX_UNITY_ID
