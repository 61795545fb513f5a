#include <doctest/doctest.h>

#include <cmath>

#include "core/geometry/mesh_properties.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// Axis-aligned box with half extents h centred at c, outward normals.
void box(const Vec3& c, const Vec3& h, std::vector<Vec3>& v, std::vector<uint32_t>& t) {
    const uint32_t base = uint32_t(v.size());
    for (int i = 0; i < 8; ++i)
        v.push_back(c + Vec3((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z()));
    const uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                               {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (auto& tri : f)
        for (uint32_t k : tri) t.push_back(base + k);
}

}  // namespace

TEST_CASE("box: volume, centroid and inertia match the analytic solid") {
    std::vector<Vec3> v;
    std::vector<uint32_t> t;
    const Vec3 h(0.1, 0.2, 0.3), c(1, -2, 0.5);
    box(c, h, v, t);
    CHECK(check_closure(t).closed);
    SolidAccumulator acc;
    acc.add(v, t);
    SolidProperties p = acc.result();
    const double a = 2 * h.x(), b = 2 * h.y(), d = 2 * h.z();
    CHECK(p.volume == mbx_test::relative(a * b * d, 1e-6));
    CHECK((p.centroid - c).norm() < 1e-12);
    // Solid box: I_xx = m (b^2 + d^2) / 12, with m = density * V.
    const double m = p.volume;
    CHECK(p.inertia_per_density(0, 0) == mbx_test::relative(m * (b * b + d * d) / 12, 1e-6));
    CHECK(p.inertia_per_density(1, 1) == mbx_test::relative(m * (a * a + d * d) / 12, 1e-6));
    CHECK(p.inertia_per_density(2, 2) == mbx_test::relative(m * (a * a + b * b) / 12, 1e-6));
    CHECK(std::abs(p.inertia_per_density(0, 1)) < 1e-15);
}

TEST_CASE("inverted normals give the same solid, an open mesh is detected") {
    std::vector<Vec3> v;
    std::vector<uint32_t> t;
    box(Vec3::Zero(), Vec3(1, 1, 1), v, t);
    std::vector<uint32_t> flipped = t;
    for (size_t i = 0; i < flipped.size(); i += 3) std::swap(flipped[i + 1], flipped[i + 2]);
    SolidAccumulator acc;
    acc.add(v, flipped);
    CHECK(acc.result().volume == mbx_test::relative(8.0, 1e-6));
    CHECK(check_closure(flipped).closed);
    std::vector<uint32_t> open(t.begin(), t.end() - 3);
    MeshClosure c = check_closure(open);
    CHECK_FALSE(c.closed);
    CHECK(c.boundary_edges == 3);
}

TEST_CASE("rotated tetrahedron: analytic centroid and the product-of-inertia sign") {
    // Unit right tetrahedron (0, e1, e2, e3): V = 1/6, centroid (1/4,1/4,1/4).
    // About the origin: int x^2 = 1/60, int xy = 1/120 (so I_xy = -1/120);
    // shifted to the centroid: I_xx = 2/60 - V*(2/16), I_xy = -1/120 + V/16.
    std::vector<Vec3> v = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
    std::vector<uint32_t> t = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    CHECK(check_closure(t).closed);
    SolidAccumulator acc;
    acc.add(v, t);
    SolidProperties p = acc.result();
    const double V = 1.0 / 6.0;
    CHECK(p.volume == mbx_test::relative(V, 1e-6));
    CHECK((p.centroid - Vec3::Constant(0.25)).norm() < 1e-12);
    CHECK(p.inertia_per_density(0, 0) == mbx_test::relative(2.0 / 60 - V * 2.0 / 16, 1e-6));
    CHECK(p.inertia_per_density(0, 1) == mbx_test::relative(-1.0 / 120 + V / 16, 1e-6));
}
}  // namespace MBX_UNITY_ID
