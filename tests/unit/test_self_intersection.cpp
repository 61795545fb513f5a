// Self-intersection of triangle meshes: a closed mesh that folds through
// itself is found, a sound one (sharing corners and edges everywhere) is not.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "core/geometry/mesh_properties.h"
#include "core/geometry/self_intersection.h"

namespace MBX_UNITY_ID {

using mbx::Vec3;

namespace {

// A closed octahedron (8 faces, outward) around the origin.
void octahedron(std::vector<Vec3>& v, std::vector<uint32_t>& t) {
    v = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    t = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
}

}  // namespace

TEST_CASE("self-intersection: a sound closed mesh has none, two overlapping copies of it have some") {
    std::vector<Vec3> v;
    std::vector<uint32_t> t;
    octahedron(v, t);
    REQUIRE(mbx::check_closure(t).closed);
    CHECK(mbx::find_self_intersections(v, t).count == 0);
    // A second copy, shifted half its size: still closed, but the two
    // surfaces pass through each other.
    const size_t n = v.size(), m = t.size();
    for (size_t k = 0; k < n; ++k) v.push_back(v[k] + Vec3(0.5, 0.1, 0.05));
    for (size_t k = 0; k < m; ++k) t.push_back(t[k] + uint32_t(n));
    REQUIRE(mbx::check_closure(t).closed);
    const mbx::SelfIntersections found = mbx::find_self_intersections(v, t);
    CHECK(found.count > 0);
    REQUIRE_FALSE(found.pairs.empty());
    // Every pair named crosses for real: its triangles share no edge.
    for (const auto& p : found.pairs) {
        int shared = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) shared += t[3 * p.first + size_t(i)] == t[3 * p.second + size_t(j)];
        CHECK(shared < 2);
    }
}

TEST_CASE("self-intersection: two separate triangles crossing, touching at a corner, and a fine sphere") {
    std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}};
    std::vector<uint32_t> t = {0, 1, 2, 3, 4, 5};
    CHECK(mbx::find_self_intersections(v, t).count == 1);
    // Moved beside the first: they no longer meet.
    for (size_t k = 3; k < 6; ++k) v[k].x() += 5;
    CHECK(mbx::find_self_intersections(v, t).count == 0);
    // Sharing a corner and otherwise apart (a fan): none.
    v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0.5}, {0, -1, 0.5}};
    t = {0, 1, 2, 0, 3, 4};
    CHECK(mbx::find_self_intersections(v, t).count == 0);
    // A UV sphere of 40 x 20 quads: thousands of neighbouring triangles, none crossing.
    v.clear();
    t.clear();
    const int nu = 40, nv = 20;
    v.push_back({0, 0, -1});
    for (int j = 1; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const double th = 2 * M_PI * i / nu, ph = -M_PI / 2 + M_PI * j / nv;
            v.push_back({std::cos(ph) * std::cos(th), std::cos(ph) * std::sin(th), std::sin(ph)});
        }
    v.push_back({0, 0, 1});
    auto at = [&](int j, int i) { return uint32_t(1 + (j - 1) * nu + (i % nu)); };
    for (int i = 0; i < nu; ++i) t.insert(t.end(), {0, at(1, i + 1), at(1, i)});
    for (int j = 1; j + 1 < nv; ++j)
        for (int i = 0; i < nu; ++i) t.insert(t.end(), {at(j, i), at(j, i + 1), at(j + 1, i + 1), at(j, i), at(j + 1, i + 1), at(j + 1, i)});
    for (int i = 0; i < nu; ++i) t.insert(t.end(), {uint32_t(v.size() - 1), at(nv - 1, i), at(nv - 1, i + 1)});
    REQUIRE(mbx::check_closure(t).closed);
    CHECK(mbx::find_self_intersections(v, t).count == 0);
    // One vertex dragged through the far side.
    v[size_t(at(10, 0))] = Vec3(-1.5, 0, 0);
    CHECK(mbx::find_self_intersections(v, t).count > 0);
}

}  // namespace MBX_UNITY_ID
