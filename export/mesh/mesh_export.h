// Mesh files through assimp: one per rigid body (its parts' meshes combined,
// body frame, metres) and a whole-assembly glTF scene at the CAD pose.
#pragma once
#include <string>
#include <vector>

#include "export/common/export_model.h"

namespace mbx {

// The bytes of one mesh file holding `meshes` (body frame, metres). Formats
// that need companion files (OBJ's .mtl, glTF's .bin) are avoided: OBJ is
// written without materials and glTF as one binary .glb file.
std::string encode_mesh(const std::vector<Mesh>& meshes, const std::string& name, mbx_mesh_format format);

// Appends meshes/<stem>.<ext> for every body that has geometry.
void export_body_meshes(ExportModel& model, mbx_mesh_format format, OutputFiles& out);

// Appends scene.glb: every body's mesh as a node at its world pose. With
// `collision`, also every collision shape (collision_meshes.h) as a
// semi-transparent node named like CollisionMesh::node: a child of its
// body's node at its pose in the body frame (so it moves with the body), or
// at its world pose under the root when the body has no mesh.
void export_scene(ExportModel& model, OutputFiles& out, bool collision = false);

}  // namespace mbx
