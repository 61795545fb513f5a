// The collision shapes of a model (ExportSettings::contact) as triangle
// meshes, for the formats that draw them (the glTF scene, the view) or take
// a hull as a mesh file (URDF): primitives tessellated, a hull computed from
// its part's mesh exactly as the simulator computes it (same cap).
#pragma once
#include <string>
#include <vector>

#include "export/common/export_model.h"

namespace mbx {

// Tessellation of the round primitives: segments around the axis, and rings
// from pole to pole of a sphere (a capsule's caps take half as many each).
inline constexpr int kCollisionSegments = 24;
inline constexpr int kCollisionRings = 12;

struct CollisionMesh {
    int shape = -1;       // index into the model's ResolvedContact::shapes
    std::string node;     // a unique identifier ("collision_" + the shape's name, made safe): glTF node names
    int body = -1;        // mechanism body
    Pose pose;            // the shape's frame in the body frame
    Mesh mesh;            // triangles in the shape's frame, outward
};

// Every shape that has a surface: planes are unbounded and left out, and so
// is a hull whose part has no mesh (both noted, naming `format`). With
// `hulls_only`, the primitives are left out too (without a note).
std::vector<CollisionMesh> collision_meshes(ExportModel& model, const std::string& format, bool hulls_only = false);

// The triangles of a shape of `kind` with the spec's sizes (not for planes or hulls).
Mesh primitive_mesh(const CollisionSpec& spec);

}  // namespace mbx
