#include "export/mesh/assimp_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <assimp/Exporter.hpp>
#include <assimp/material.h>

namespace mbx {

namespace {

[[noreturn]] void reject(const Subject& subject, const std::string& what, const std::string& why) {
    throw Error(MBX_ERROR_INVALID_INPUT, subject, what + ": mesh not written, " + why);
}

}  // namespace

std::unique_ptr<aiMesh> combine_parts(const std::vector<Mesh>& parts, const std::string& name, const Subject& subject,
                                      const std::string& what) {
    // Sizes first, so the arrays are allocated once and a huge part is
    // converted straight into them.
    size_t vertex_count = 0, triangle_count = 0;
    for (const Mesh& part : parts) {
        if (part.triangles.empty()) continue;
        if (part.triangles.size() % 3 != 0)
            reject(subject, what, "part '" + part.name + "' has an index count that is not a multiple of 3");
        vertex_count += part.vertices.size();
        triangle_count += part.triangles.size() / 3;
    }
    if (triangle_count == 0) reject(subject, what, "it has no triangles");
    constexpr size_t limit = std::numeric_limits<int32_t>::max();  // assimp counts in 32 bits, some signed
    if (vertex_count > limit || triangle_count > limit) reject(subject, what, "it has more than 2^31 vertices or triangles");

    auto mesh = std::make_unique<aiMesh>();
    mesh->mName = aiString(name);
    mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    mesh->mMaterialIndex = 0;
    // aiMesh's destructor frees whatever has been allocated so far (faces
    // free their own indices), so a check below may throw at any point.
    mesh->mVertices = new aiVector3D[vertex_count];
    mesh->mNumVertices = unsigned(vertex_count);
    mesh->mFaces = new aiFace[triangle_count];
    mesh->mNumFaces = unsigned(triangle_count);

    size_t v_out = 0, f_out = 0;
    for (const Mesh& part : parts) {
        if (part.triangles.empty()) continue;
        const size_t base = v_out;
        for (const Vec3& v : part.vertices) {
            const aiVector3D f(float(v.x()), float(v.y()), float(v.z()));
            if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z))
                reject(subject, what,
                       "part '" + part.name + "' has a vertex that is not a finite float (vertex " +
                           std::to_string(v_out - base) + ")");
            mesh->mVertices[v_out++] = f;
        }
        const size_t n = part.vertices.size();
        for (size_t t = 0; t < part.triangles.size(); t += 3) {
            aiFace& face = mesh->mFaces[f_out++];
            face.mIndices = new unsigned[3];
            face.mNumIndices = 3;
            for (size_t k = 0; k < 3; ++k) {
                const uint32_t i = part.triangles[t + k];
                if (i >= n)
                    reject(subject, what,
                           "part '" + part.name + "' has a triangle index " + std::to_string(i) + " beyond its " +
                               std::to_string(n) + " vertices");
                face.mIndices[k] = unsigned(base + i);
            }
        }
    }
    return mesh;
}

std::unique_ptr<aiScene> new_scene(const std::string& root_name) {
    auto scene = std::make_unique<aiScene>();
    scene->mRootNode = new aiNode(root_name);
    scene->mMaterials = new aiMaterial*[1]();
    scene->mMaterials[0] = new aiMaterial;
    scene->mNumMaterials = 1;
    aiMaterial& grey = *scene->mMaterials[0];
    const aiString material_name("mbx_default");
    grey.AddProperty(&material_name, AI_MATKEY_NAME);
    const aiColor3D colour(0.7f, 0.7f, 0.7f);
    grey.AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
    return scene;
}

namespace {

// A new material at the end of the scene's list.
aiMaterial* append_material(aiScene& scene) {
    auto** list = new aiMaterial*[scene.mNumMaterials + 1]();
    for (unsigned i = 0; i < scene.mNumMaterials; ++i) list[i] = scene.mMaterials[i];
    delete[] scene.mMaterials;
    scene.mMaterials = list;
    return list[scene.mNumMaterials] = new aiMaterial;
}

}  // namespace

unsigned add_colour_material(aiScene& scene, const std::array<double, 4>& rgba) {
    aiMaterial* material = append_material(scene);
    const aiString name("mbx_colour_" + std::to_string(scene.mNumMaterials));
    material->AddProperty(&name, AI_MATKEY_NAME);
    const aiColor3D colour{float(rgba[0]), float(rgba[1]), float(rgba[2])};
    material->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
    if (rgba[3] < 1) {
        const float opacity = float(rgba[3]);
        material->AddProperty(&opacity, 1, AI_MATKEY_OPACITY);
    }
    return scene.mNumMaterials++;
}

unsigned add_collision_material(aiScene& scene) {
    aiMaterial* material = append_material(scene);
    const aiString name("mbx_collision");
    material->AddProperty(&name, AI_MATKEY_NAME);
    const aiColor3D colour(1.0f, 0.45f, 0.1f);
    material->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
    // assimp's glTF writer turns an opacity below 1 into alpha mode BLEND
    // with that alpha: the part's own mesh stays visible through its hull.
    const float opacity = 0.35f;
    material->AddProperty(&opacity, 1, AI_MATKEY_OPACITY);
    return scene.mNumMaterials++;
}

void set_meshes(aiScene& scene, std::vector<std::unique_ptr<aiMesh>> meshes) {
    auto** list = new aiMesh*[meshes.size()]();
    for (size_t i = 0; i < meshes.size(); ++i) list[i] = meshes[i].release();
    scene.mMeshes = list;
    scene.mNumMeshes = unsigned(meshes.size());
}

namespace {

aiMatrix4x4 matrix_of(const Pose& pose) {
    aiMatrix4x4 m;  // identity to start with
    for (unsigned r = 0; r < 3; ++r) {
        for (unsigned c = 0; c < 3; ++c) m[r][c] = float(pose.rotation(int(r), int(c)));
        m[r][3] = float(pose.position[int(r)]);
    }
    return m;
}

bool exactly_identity(const aiMatrix4x4& m) { return m == aiMatrix4x4(); }

}  // namespace

aiNode* add_mesh_node(aiScene& scene, const std::string& name, const std::vector<unsigned>& meshes, const Pose& pose,
                      aiNode* parent) {
    auto node = std::make_unique<aiNode>(name);
    node->mMeshes = new unsigned[meshes.size()];
    std::copy(meshes.begin(), meshes.end(), node->mMeshes);
    node->mNumMeshes = unsigned(meshes.size());
    node->mTransformation = matrix_of(pose);
    if (!parent) parent = scene.mRootNode;
    // assimp's glTF exporter writes no transform for a node whose matrix
    // aiMatrix4x4::IsIdentity() accepts, and that test allows 0.01 in every
    // entry: a body 5 mm from the origin would land on it. Such a pose goes
    // under a helper node turned 180 degrees about x, and the body node takes
    // the rest. The turn only flips signs, so both matrices are exact in
    // float and compose back to the pose.
    if (node->mTransformation.IsIdentity() && !exactly_identity(node->mTransformation)) {
        Pose turn;
        turn.rotation = Vec3(1, -1, -1).asDiagonal();
        auto frame = std::make_unique<aiNode>(name + "#frame");
        frame->mTransformation = matrix_of(turn);
        node->mTransformation = matrix_of(turn.inverse() * pose);
        aiNode* raw = frame.release();
        parent->addChildren(1, &raw);  // sets raw->mParent; the parent owns it from here
        parent = raw;
    }
    aiNode* raw = node.release();
    parent->addChildren(1, &raw);
    return raw;
}

std::string export_blob(const aiScene& scene, const char* format_id, const std::string& what) {
    // One Exporter per call: its IO system and blob are private to this
    // call, so exports on several threads do not share assimp state (the
    // default logger stays the global null logger; we never create one).
    Assimp::Exporter exporter;
    const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, format_id);
    if (!blob)
        throw Error(MBX_ERROR_INTERNAL, Subject{},
                    what + ": assimp could not write '" + format_id + "': " + exporter.GetErrorString());
    if (blob->next)
        throw Error(MBX_ERROR_INTERNAL, Subject{},
                    what + ": assimp's '" + format_id + "' exporter wants a companion file, which mbx does not write");
    return std::string(static_cast<const char*>(blob->data), blob->size);
}

}  // namespace mbx
