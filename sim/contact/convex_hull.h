// The convex hull of a point cloud (a CAD part's mesh vertices), as the
// collision shape the description file's shape="hull" asks for: contact on
// primitives and convex pieces, never mesh-mesh (FCL's mesh-mesh depths and
// normals are unreliable).
#pragma once
#include <string>
#include <vector>

#include "sim/contact/shape.h"

namespace mbx::sim::contact {

// Triangulated hull of `points` (incremental: each point outside the current
// hull replaces the faces it sees by a fan over their horizon), with only
// the vertices on the hull, faces counter-clockwise seen from outside.
// Throws mbx::Error naming `name` when the points are not finite or span no
// volume (fewer than four points off one plane).
ConvexHull convex_hull(const std::vector<Eigen::Vector3d>& points, const std::string& name);

}  // namespace mbx::sim::contact
