#include "export/mesh/mesh_export.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <map>

#include "export/mesh/assimp_scene.h"
#include "export/mesh/collision_meshes.h"

namespace mbx {

namespace {

// assimp ids: binary STL, OBJ without the .mtl companion, and binary glTF
// (assimp 5.2.5's text glTF always points at a separate .bin, it cannot
// embed the buffer as a data URI, so a self-contained glTF has to be .glb).
const char* assimp_format(mbx_mesh_format format) {
    switch (format) {
    case MBX_MESH_OBJ: return "objnomtl";
    case MBX_MESH_GLTF: return "glb2";
    case MBX_MESH_STL: break;
    }
    return "stlb";
}

// assimp stamps every binary STL with the same "AssimpScene" header; a
// header naming the mesh tells files apart. It must not start with "solid"
// (readers would take the file for ASCII STL), which the "mbx " prefix
// guarantees.
void stamp_stl_header(std::string& bytes, const std::string& name) {
    constexpr size_t header = 80;
    if (bytes.size() < header + 4) return;
    const std::string text = "mbx " + name;
    std::fill(bytes.begin(), bytes.begin() + header, '\0');
    std::memcpy(&bytes[0], text.data(), std::min(text.size(), header));
}

std::string encode(const std::vector<Mesh>& meshes, const std::string& name, mbx_mesh_format format,
                   const Subject& subject, const std::string& what) {
    std::unique_ptr<aiScene> scene = new_scene(name);
    std::vector<std::unique_ptr<aiMesh>> list;
    list.push_back(combine_parts(meshes, name, subject, what));
    set_meshes(*scene, std::move(list));
    // The body's mesh sits on the root node, untransformed: the file is in
    // the body frame.
    scene->mRootNode->mMeshes = new unsigned[1]{0};
    scene->mRootNode->mNumMeshes = 1;
    std::string bytes = export_blob(*scene, assimp_format(format), what);
    if (format == MBX_MESH_STL) stamp_stl_header(bytes, name);
    return bytes;
}

Subject subject_of(const RigidBody& body) { return Subject::rigid_body(body.id, body.name); }
std::string describe(const RigidBody& body) { return "rigid body '" + body.name + "'"; }

}  // namespace

std::string encode_mesh(const std::vector<Mesh>& meshes, const std::string& name, mbx_mesh_format format) {
    return encode(meshes, name, format, Subject{}, "mesh '" + name + "'");
}

void export_body_meshes(ExportModel& model, mbx_mesh_format format, OutputFiles& out) {
    const Mechanism& m = model.mechanism();
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        const int body = int(b);
        if (!model.has_mesh(body)) continue;
        const RigidBody& rb = m.bodies[b];
        out.push_back(OutputFile{model.mesh_path(body, format),
                                 encode(model.shapes(body), model.mesh_stem(body), format, subject_of(rb), describe(rb))});
    }
}

void export_scene(ExportModel& model, OutputFiles& out, bool collision) {
    const Mechanism& m = model.mechanism();
    // assimp's glTF writer makes node names unique by renaming later ones, so
    // the root gets a name no body stem can have (stems are identifiers).
    std::unique_ptr<aiScene> scene = new_scene(model.settings().model_name + " (assembly)");
    std::vector<std::unique_ptr<aiMesh>> meshes;
    // A body's parts in the colours the host gave them: one mesh per colour
    // (the default grey for parts without one), all on the body's node.
    std::map<std::array<double, 4>, unsigned> material_of;
    std::vector<std::pair<int, std::vector<unsigned>>> bodies;  // body, its meshes
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        const int body = int(b);
        if (!model.has_mesh(body)) continue;
        const RigidBody& rb = m.bodies[b];
        std::map<std::array<double, 4>, std::vector<Mesh>> by_colour;
        for (const Mesh& part : model.shapes(body))
            if (!part.triangles.empty()) by_colour[part.has_color() ? part.color : std::array<double, 4>{}].push_back(part);
        std::vector<unsigned> own;
        for (const auto& [colour, parts] : by_colour) {
            const std::string name = model.mesh_stem(body) + (own.empty() ? "" : "#" + std::to_string(own.size()));
            meshes.push_back(combine_parts(parts, name, subject_of(rb), describe(rb)));
            if (colour[3] > 0) {
                auto found = material_of.find(colour);
                if (found == material_of.end()) found = material_of.emplace(colour, add_colour_material(*scene, colour)).first;
                meshes.back()->mMaterialIndex = found->second;
            }
            own.push_back(unsigned(meshes.size() - 1));
        }
        bodies.emplace_back(body, std::move(own));
    }
    if (bodies.empty()) return;  // nothing to show; an empty glTF scene would only confuse
    const unsigned body_meshes = unsigned(meshes.size());
    std::vector<CollisionMesh> shapes;
    if (collision) shapes = collision_meshes(model, "glTF scene");
    const unsigned collision_material = shapes.empty() ? 0 : add_collision_material(*scene);
    for (const CollisionMesh& c : shapes) {
        meshes.push_back(combine_parts({c.mesh}, c.node, Subject::model(c.mesh.name), "collision shape '" + c.mesh.name + "'"));
        meshes.back()->mMaterialIndex = collision_material;
    }
    set_meshes(*scene, std::move(meshes));
    // One node per body at its world pose in the assembly configuration,
    // named like its mesh file (body name made unique and file-safe).
    std::vector<aiNode*> body_node(m.bodies.size(), nullptr);
    for (const auto& [body, own] : bodies)
        body_node[size_t(body)] = add_mesh_node(*scene, model.mesh_stem(body), own, m.bodies[size_t(body)].pose);
    for (size_t i = 0; i < shapes.size(); ++i) {
        const CollisionMesh& c = shapes[i];
        aiNode* parent = body_node[size_t(c.body)];
        add_mesh_node(*scene, c.node, {body_meshes + unsigned(i)}, parent ? c.pose : m.bodies[size_t(c.body)].pose * c.pose,
                      parent);
    }
    out.push_back(OutputFile{"scene.glb", export_blob(*scene, "glb2", "the assembly scene")});
}

}  // namespace mbx
