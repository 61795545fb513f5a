// Closed triangle meshes for primitive geometry (the VRML97 nodes, URDF's
// box, cylinder and sphere), in the node's local frame as VRML97 clause 6
// defines it (centred on the origin, Y up for
// Cylinder and Cone), counter-clockwise seen from outside. Curved surfaces
// use `segments` facets around the Y axis, so volumes come out slightly
// below the analytic ones.
#pragma once
#include "host_adapters/common/vrml_scene.h"

namespace mbx_files::vrml {

constexpr int primitive_segments = 24;

VrmlMesh box_mesh(double sx, double sy, double sz);
VrmlMesh sphere_mesh(double radius, int segments = primitive_segments);
// Parts switched off in the node (side/top/bottom FALSE) are left out, so
// the mesh is closed only when all of them are on.
VrmlMesh cylinder_mesh(double radius, double height, bool side, bool top, bool bottom,
                       int segments = primitive_segments);
VrmlMesh cone_mesh(double bottom_radius, double height, bool side, bool bottom, int segments = primitive_segments);

}  // namespace mbx_files::vrml
