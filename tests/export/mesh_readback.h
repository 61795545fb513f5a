// Shared by the mesh tests: files read back with assimp's importer (the
// consumer) and triangles compared as sets, independent of vertex order,
// vertex sharing and triangle order, which formats and readers change.
#pragma once
#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <doctest/doctest.h>

#include "core/assembly/shape_loader.h"
#include "core/math.h"
#include "host_adapters/memory/memory_host.h"

namespace xmesh {

using Triangle = std::array<double, 9>;  // three vertices, x y z each

// Same triangle, same winding, starting at its lexicographically smallest vertex.
inline Triangle canonical(Triangle t) {
    int first = 0;
    for (int k = 1; k < 3; ++k)
        if (std::lexicographical_compare(t.begin() + 3 * k, t.begin() + 3 * k + 3, t.begin() + 3 * first,
                                         t.begin() + 3 * first + 3))
            first = k;
    Triangle r;
    for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) r[size_t(3 * k + c)] = t[size_t(3 * ((first + k) % 3) + c)];
    return r;
}

// A file read back by assimp (kept alive with its importer).
struct ReadBack {
    std::unique_ptr<Assimp::Importer> importer = std::make_unique<Assimp::Importer>();
    const aiScene* scene = nullptr;
};

// `hint` is the extension assimp should assume ("stl", "obj", "glb").
inline ReadBack read_back(const std::string& bytes, const char* hint, unsigned flags = 0) {
    ReadBack r;
    r.scene = r.importer->ReadFileFromMemory(bytes.data(), bytes.size(), flags, hint);
    INFO("assimp: " << r.importer->GetErrorString());
    REQUIRE(r.scene != nullptr);
    return r;
}

inline mbx::Pose pose_of(const aiMatrix4x4& m) {
    mbx::Pose p;
    for (unsigned r = 0; r < 3; ++r) {
        for (unsigned c = 0; c < 3; ++c) p.rotation(r, c) = m[r][c];
        p.position[r] = m[r][3];
    }
    return p;
}

// Accumulated transform of `node` from the scene root (root included).
inline mbx::Pose world_of(const aiNode* node) {
    mbx::Pose p;
    for (; node; node = node->mParent) p = pose_of(node->mTransformation) * p;
    return p;
}

inline void add_triangles(const aiMesh* m, const mbx::Pose& pose, std::vector<Triangle>& out) {
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
        const aiFace& face = m->mFaces[f];
        REQUIRE(face.mNumIndices == 3);
        Triangle t;
        for (unsigned k = 0; k < 3; ++k) {
            const aiVector3D& v = m->mVertices[face.mIndices[k]];
            const mbx::Vec3 w = pose.apply(mbx::Vec3(v.x, v.y, v.z));
            for (unsigned c = 0; c < 3; ++c) t[3 * k + c] = w[c];
        }
        out.push_back(canonical(t));
    }
}

inline void collect(const aiScene* s, const aiNode* node, const mbx::Pose& parent, std::vector<Triangle>& out) {
    const mbx::Pose here = parent * pose_of(node->mTransformation);
    for (unsigned i = 0; i < node->mNumMeshes; ++i) add_triangles(s->mMeshes[node->mMeshes[i]], here, out);
    for (unsigned c = 0; c < node->mNumChildren; ++c) collect(s, node->mChildren[c], here, out);
}

// One mesh's triangles in its own frame, sorted.
inline std::vector<Triangle> triangles(const aiMesh* m) {
    std::vector<Triangle> out;
    add_triangles(m, mbx::Pose{}, out);
    std::sort(out.begin(), out.end());
    return out;
}

// Every triangle of the scene in its root frame, sorted.
inline std::vector<Triangle> triangles(const aiScene* s) {
    std::vector<Triangle> out;
    collect(s, s->mRootNode, mbx::Pose{}, out);
    std::sort(out.begin(), out.end());
    return out;
}

// x rounded to float. Through a volatile because GCC 12.2's SLP vectorizer
// at -O2 drops the rounding in double(float(x)) inside small loops (checked:
// the plain expression gives x back unrounded for 2 of 3 coordinates).
inline double float_rounded(double x) {
    volatile float f = float(x);
    return double(f);
}

// The source meshes' triangles as the file should hold them: vertices
// rounded to float (every format stores float), sorted.
inline std::vector<Triangle> source_triangles(const std::vector<mbx::Mesh>& meshes, const mbx::Pose& pose = {}) {
    std::vector<Triangle> out;
    for (const mbx::Mesh& m : meshes)
        for (size_t i = 0; i + 2 < m.triangles.size(); i += 3) {
            Triangle t;
            for (size_t k = 0; k < 3; ++k) {
                const mbx::Vec3& v = m.vertices[m.triangles[i + k]];
                for (int c = 0; c < 3; ++c) t[3 * k + c] = float_rounded(v[c]);
            }
            if (!(pose.rotation.isIdentity(0) && pose.position.isZero(0))) {
                for (size_t k = 0; k < 3; ++k) {
                    const mbx::Vec3 w = pose.apply(mbx::Vec3(t[3 * k], t[3 * k + 1], t[3 * k + 2]));
                    for (int c = 0; c < 3; ++c) t[3 * k + c] = w[c];
                }
            }
            out.push_back(canonical(t));
        }
    std::sort(out.begin(), out.end());
    return out;
}

// Axis-aligned bounds.
struct Box {
    mbx::Vec3 lo = mbx::Vec3::Constant(std::numeric_limits<double>::infinity());
    mbx::Vec3 hi = -mbx::Vec3::Constant(std::numeric_limits<double>::infinity());
    void add(const mbx::Vec3& v) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
};

inline mbx::Mat3 rotation_of(const mbx_pose& p) {
    mbx::Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = p.rotation[3 * i + j];
    return r;
}
inline mbx::Vec3 position_of(const mbx_pose& p) { return mbx::Vec3(p.position[0], p.position[1], p.position[2]); }

// World vertices of a host body's meshes, straight from the host data
// (body pose, mesh pose, host length unit), without the SDK's loader.
inline std::vector<mbx::Vec3> host_world_vertices(const mbx_memory::Assembly& a, const std::string& body_id) {
    const mbx_memory::Body* body = nullptr;
    for (const auto& b : a.bodies)
        if (b.id == body_id) body = &b;
    REQUIRE(body != nullptr);
    const double unit = body->units.length_to_m == 0 ? 1.0 : body->units.length_to_m;
    std::vector<mbx::Vec3> out;
    const auto it = a.shapes.find(body_id);
    if (it == a.shapes.end()) return out;
    for (const mbx_memory::Mesh& m : it->second)
        for (size_t i = 0; i + 2 < m.vertices.size(); i += 3) {
            const mbx::Vec3 v(m.vertices[i], m.vertices[i + 1], m.vertices[i + 2]);
            const mbx::Vec3 in_body = rotation_of(m.pose) * v + position_of(m.pose);
            out.push_back(unit * (rotation_of(body->pose) * in_body + position_of(body->pose)));
        }
    return out;
}

// Largest coordinate difference between two sorted triangle lists of equal size.
inline double max_difference(const std::vector<Triangle>& a, const std::vector<Triangle>& b) {
    REQUIRE(a.size() == b.size());
    double d = 0;
    for (size_t i = 0; i < a.size(); ++i)
        for (size_t c = 0; c < 9; ++c) d = std::max(d, std::abs(a[i][c] - b[i][c]));
    return d;
}

}  // namespace xmesh
