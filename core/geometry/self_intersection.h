// Whether a triangle mesh crosses itself: a triangle's edge passing through
// another triangle that shares no corner with it there. A mesh can be closed
// (every edge used twice) and still fold through itself, which a volume
// integral would silently count twice or not at all; tessellators are
// checked with this, and a mesh that fails it is no solid.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "core/math.h"

namespace mbx {

struct SelfIntersections {
    size_t count = 0;  // crossing triangle pairs found (up to the limit asked for)
    std::vector<std::pair<uint32_t, uint32_t>> pairs;  // the first few, by triangle index
};

// Finds crossing pairs with a uniform grid over the triangles' bounding
// boxes (cost near-linear in the triangle count for meshes of even density).
// Pairs sharing an edge never count; pairs sharing one corner count only
// where they cross away from it; an edge within 1e-6 rad of the other
// triangle's plane does not count (coplanar overlaps are the closure check's
// to find: they leave an edge used twice in one direction). Stops after
// `limit` pairs.
SelfIntersections find_self_intersections(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& triangles,
                                          size_t limit = 100);

}  // namespace mbx
