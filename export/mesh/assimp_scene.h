// Bridges mbx meshes to assimp: a body's parts combined into one aiMesh
// (validated, so NaN or a bad index never reaches a file), scenes built from
// those meshes, and the bytes assimp's exporters make of a scene.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <assimp/scene.h>

#include "core/assembly/shape_loader.h"
#include "core/finding.h"
#include "core/math.h"

namespace mbx {

// All triangles of `parts` as one triangle mesh named `name`, vertices
// converted to float once. Throws Error(MBX_ERROR_INVALID_INPUT, subject)
// naming `what` (e.g. "rigid body 'arm'") when a vertex is not finite (or
// overflows float), an index is out of range, or nothing is left to write.
std::unique_ptr<aiMesh> combine_parts(const std::vector<Mesh>& parts, const std::string& name, const Subject& subject,
                                      const std::string& what);

// An empty scene with one neutral grey material (exporters index it) and a
// root node named `root_name`.
std::unique_ptr<aiScene> new_scene(const std::string& root_name);

// Adds a semi-transparent orange material for collision shapes (glTF: alpha
// mode BLEND) and returns its index.
unsigned add_collision_material(aiScene& scene);

// Adds a material of the host's colour (red, green, blue, alpha in 0..1; an
// alpha below 1 makes it see-through) and returns its index.
unsigned add_colour_material(aiScene& scene, const std::array<double, 4>& rgba);

// Moves `meshes` into `scene` (replacing its mesh list).
void set_meshes(aiScene& scene, std::vector<std::unique_ptr<aiMesh>> meshes);

// Adds a node below `parent` (null: the root) that instances `meshes` at
// `pose` relative to it (a pose close to identity gets a helper parent
// node); returns the node. glTF writes a node's meshes as one mesh with a
// primitive each.
aiNode* add_mesh_node(aiScene& scene, const std::string& name, const std::vector<unsigned>& meshes, const Pose& pose,
                      aiNode* parent = nullptr);

// The main (first) blob assimp's exporter `format_id` makes of `scene`.
// Throws Error(MBX_ERROR_INTERNAL) when assimp fails or yields companion
// files (an exporter choice that would leave the main file dangling).
std::string export_blob(const aiScene& scene, const char* format_id, const std::string& what);

}  // namespace mbx
