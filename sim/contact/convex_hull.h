// The convex hull of a point cloud (a CAD part's mesh vertices), as the
// collision shape the description file's shape="hull" asks for: contact on
// primitives and convex pieces, never mesh-mesh (FCL's mesh-mesh depths and
// normals are unreliable).
#pragma once
#include <string>
#include <vector>

#include "sim/contact/shape.h"

namespace mbx::sim::contact {

// Vertex cap of a hull. Collision cost grows with the hull's size (FCL's GJK
// support search walks every vertex, the half-space manifold tests each one)
// and MuJoCo bounds its hulls the same way (maxhullvert). A CAD part's hull
// seldom reaches it; one that would is cut short (see convex_hull).
inline constexpr int kMaxHullVertices = 256;

struct HullStats {
    size_t points = 0;    // points given
    bool capped = false;  // the cap stopped the hull before every point was on or inside it
    // Factor the capped hull was scaled by about its centroid so that it
    // contains every point again (1 when not capped).
    double inflation = 1;
};

// Triangulated hull of `points`, with only the vertices on the hull, faces
// counter-clockwise seen from outside. Quickhull with conflict lists: each
// point outside the current hull is kept on one face it sees, the farthest
// point of a face is added next and only the points of the faces it replaces
// are tested again, so the cost is near-linear in the number of points.
// At most `max_vertices` vertices (>= 4): when the cap stops the hull with
// points still outside, it is scaled about its centroid until it contains
// them all (an outer bound like the mesh's, not an inner one), stats say by
// how much. Throws mbx::Error naming `name` when the points are not finite
// or span no volume (fewer than four points off one plane).
ConvexHull convex_hull(const std::vector<Eigen::Vector3d>& points, const std::string& name,
                       int max_vertices = kMaxHullVertices, HullStats* stats = nullptr);

}  // namespace mbx::sim::contact
