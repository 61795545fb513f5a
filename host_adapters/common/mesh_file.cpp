#include "mesh_file.h"
#include "core/input_file.h"
#include "host_adapters/common/text.h"
#include "host_adapters/step/assembly.h"
#include "host_adapters/step/tessellate.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

namespace mbx_files {
namespace fs = std::filesystem;
namespace {

void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, mbx_memory::Mesh& out) {
    const aiMatrix4x4 world = parent * node.mTransformation;
    for (unsigned k = 0; k < node.mNumMeshes; ++k) {
        const aiMesh& mesh = *scene.mMeshes[node.mMeshes[k]];
        const uint32_t base = uint32_t(out.vertices.size() / 3);
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
            const aiVector3D p = world * mesh.mVertices[v];
            out.vertices.insert(out.vertices.end(), {double(p.x), double(p.y), double(p.z)});
        }
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
            const aiFace& face = mesh.mFaces[f];
            if (face.mNumIndices != 3) continue;  // points and lines carry no volume
            for (unsigned i = 0; i < 3; ++i) out.triangles.push_back(base + face.mIndices[i]);
        }
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c) collect(scene, *node.mChildren[c], world, out);
}

}  // namespace

MeshFileFinder::MeshFileFinder(std::vector<std::string> directories) : directories_(std::move(directories)) {}

const std::map<std::string, std::string>* MeshFileFinder::listing(const std::string& directory) {
    auto found = listings_.find(directory);
    if (found == listings_.end()) {
        std::error_code ec;
        std::vector<std::string> names;
        for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
            std::error_code file_ec;
            if (it->is_regular_file(file_ec)) names.push_back(it->path().filename().string());
        }
        std::optional<std::map<std::string, std::string>> map;
        if (!ec) {
            // Sorted so that, among names differing only in case, the choice
            // does not depend on the order the file system lists them in.
            std::sort(names.begin(), names.end());
            map.emplace();
            for (const std::string& n : names) map->emplace(lower_case(n), n);
        }
        found = listings_.emplace(directory, std::move(map)).first;
    }
    return found->second ? &*found->second : nullptr;
}

std::string MeshFileFinder::find(const std::string& name) {
    std::string portable = name;
    std::replace(portable.begin(), portable.end(), '\\', '/');
    const fs::path path(portable);
    const std::string file = path.filename().string();
    if (file.empty()) return {};
    std::vector<fs::path> candidates;
    if (path.is_absolute())
        candidates.push_back(path.parent_path());
    else
        for (const std::string& d : directories_) candidates.push_back(fs::path(d) / path.parent_path());
    for (const fs::path& dir : candidates) {
        const std::string directory = dir.empty() ? std::string(".") : dir.lexically_normal().string();
        std::error_code ec;
        if (fs::is_regular_file(fs::path(directory) / file, ec)) return (fs::path(directory) / file).string();
        const std::map<std::string, std::string>* names = listing(directory);
        if (!names) continue;
        const auto it = names->find(lower_case(file));
        if (it != names->end()) return (fs::path(directory) / it->second).string();
    }
    return {};
}

bool probe_mesh_file(const std::string& path, std::string& why) {
    why = mbx::input_file_problem(path);
    if (!why.empty()) return false;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        why = std::string("cannot open it: ") + std::strerror(errno);
        return false;
    }
    std::error_code ec;
    const uintmax_t size = fs::file_size(path, ec);
    if (ec || size == 0) {
        why = ec ? "cannot read its size: " + ec.message() : std::string("the file is empty");
        return false;
    }
    if (is_step_file(path)) {
        char head[64] = {};
        in.read(head, sizeof head);
        const std::string text(head, size_t(in.gcount()));
        const size_t first = text.find_first_not_of(" \t\r\n");
        if (first == std::string::npos || text.compare(first, 12, "ISO-10303-21") != 0) {
            why = "it does not start as a STEP file does ('ISO-10303-21;')";
            return false;
        }
        return true;
    }
    if (lower_case(fs::path(path).extension().string()) != ".stl") return true;
    char head[1024] = {};
    in.read(head, sizeof head);
    const size_t got = size_t(in.gcount());
    if (got >= 84) {
        uint32_t count = 0;
        for (int i = 3; i >= 0; --i) count = (count << 8) | static_cast<unsigned char>(head[80 + i]);
        if (uintmax_t(84) + uintmax_t(50) * count == size && count > 0) return true;
    }
    const std::string text = lower_case(std::string(head, got));
    const size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos || text.compare(first, 5, "solid") != 0 || text.find("facet") == std::string::npos) {
        why = "it is neither a binary STL (84 bytes plus 50 per triangle) nor an ASCII STL ('solid' ... 'facet')";
        return false;
    }
    // A cut-off ASCII STL (an interrupted copy) lacks its closing keyword;
    // catching it here makes it a diagnostic in the report, not a late load failure.
    char tail[256] = {};
    const uintmax_t tail_size = std::min<uintmax_t>(size, sizeof tail);
    in.clear();
    in.seekg(std::streamoff(size - tail_size));
    in.read(tail, std::streamsize(tail_size));
    if (lower_case(std::string(tail, size_t(in.gcount()))).find("endsolid") == std::string::npos) {
        why = "the ASCII STL is cut off (no 'endsolid' at its end)";
        return false;
    }
    return true;
}

bool is_step_file(const std::string& path) {
    const std::string ext = lower_case(fs::path(path).extension().string());
    return ext == ".step" || ext == ".stp";
}

namespace {

// Every placed solid of a STEP file as one mesh (assimp reads no mechanical
// STEP). Faces that could not be meshed leave holes: said in the error only
// when nothing at all was meshed, since a mesh with a hole still shows the
// part (the mass check and the report judge its closure).
bool load_step(const std::string& path, mbx_memory::Mesh& out, std::string& error, double unit_m) {
    try {
        const mbx_step::File file = mbx_step::read_part21_file(path);
        const mbx_step::Brep brep = mbx_step::read_breps(file);
        const mbx_step::Assembly placed = mbx_step::place_solids(file, brep);
        const std::vector<mbx_step::SolidMesh> meshes = mbx_step::tessellate(brep, mbx_step::Tolerance{});
        const double scale = unit_m > 0 ? 1.0 / unit_m : 1.0;
        for (const mbx_step::PlacedSolid& p : placed.solids) {
            const mbx_step::TriangleMesh& m = meshes[p.solid].mesh;
            const uint32_t base = uint32_t(out.vertices.size() / 3);
            for (const Eigen::Vector3d& v : m.points) {
                const Eigen::Vector3d w = (p.pose * v) * scale;
                out.vertices.insert(out.vertices.end(), {w.x(), w.y(), w.z()});
            }
            for (const auto& t : m.triangles)
                out.triangles.insert(out.triangles.end(), {base + t[0], base + t[1], base + t[2]});
        }
        if (out.triangles.empty()) {
            error = brep.solids.empty() ? "it holds no solid mbx reads (no B-rep)"
                                        : "none of its faces could be meshed";
            return false;
        }
        return true;
    } catch (const mbx_step::ReadError& e) {
        error = e.what();
        return false;
    } catch (const std::bad_alloc&) {
        error = "it needs more memory than is available to mesh";
        return false;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

}  // namespace

bool load_mesh_file(const std::string& path, mbx_memory::Mesh& out, std::string& error, double unit_m) {
    if (is_step_file(path)) {
        out = mbx_memory::Mesh{};
        out.name = fs::path(path).filename().string();
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) out.pose.rotation[3 * i + j] = i == j ? 1.0 : 0.0;
        return load_step(path, out, error, unit_m);
    }
    Assimp::Importer importer;
    // STL stores a normal per facet corner; with normals kept, JoinIdenticalVertices
    // would not weld corners of differently facing facets and no mesh would be closed.
    importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                            aiComponent_COLORS | aiComponent_TEXCOORDS);
    // A Collada file's vertices are in the part's (the link's) frame as CAD
    // and robot exporters write them; assimp would otherwise turn a Z_UP file
    // (Blender's, the Franka Panda's) onto its own Y-up convention.
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    const aiScene* scene =
        importer.ReadFile(path, aiProcess_RemoveComponent | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
    if (!scene || !scene->mRootNode) {
        error = importer.GetErrorString();
        if (error.empty()) error = "assimp could not read it";
        return false;
    }
    out = mbx_memory::Mesh{};
    out.name = fs::path(path).filename().string();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out.pose.rotation[3 * i + j] = i == j ? 1.0 : 0.0;
    collect(*scene, *scene->mRootNode, aiMatrix4x4(), out);
    if (out.triangles.empty()) {
        error = "it holds no triangles";
        return false;
    }
    return true;
}

}  // namespace mbx_files
