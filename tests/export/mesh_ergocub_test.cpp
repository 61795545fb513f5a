// ergoCub (PMXML + 66 ASCII STL files): one binary STL per rigid body with
// geometry, whose triangle count is the sum of its parts' source files,
// counted straight from the STL text (not through assimp or mbx's loader).
#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <pugixml.hpp>

#include "export_fixture.h"
#include "export/mesh/mesh_export.h"
#include "mesh_readback.h"
#include "tests/common/skip.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

std::string unquote(std::string s) {
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
    return s;
}

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Triangles in an STL file: "facet" records of ASCII STL, or the binary count.
size_t stl_triangles(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    const std::string bytes = s.str();
    REQUIRE(bytes.size() >= 84);
    if (bytes.compare(0, 5, "solid") == 0 && bytes.find("facet") != std::string::npos) {
        size_t n = 0;
        for (size_t at = bytes.find("endfacet"); at != std::string::npos; at = bytes.find("endfacet", at + 8)) ++n;
        return n;
    }
    uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    return n;
}

}  // namespace

TEST_CASE("mesh files: ergoCub gives one STL per body with geometry, triangles summed over its parts") {
    const std::string root = mbx_test::shared_data("pmxml/ergocub");
    const std::string xml = root + "/SIM_ERGOCUB_1-0.xml";
    const std::string mesh_dir = root + "/meshes/simmechanics";
    if (!std::filesystem::exists(xml)) {
        MBX_SKIP("ergoCub data not present at " << root);
    }
    // Files on disk by lower-case name (the XML spells them in upper case).
    std::map<std::string, std::string> on_disk;
    for (const auto& e : std::filesystem::directory_iterator(mesh_dir))
        on_disk[lower(e.path().filename().string())] = e.path().string();

    // Part (by name and by node id) -> triangles of its geometry file.
    pugi::xml_document doc;
    REQUIRE(doc.load_file(xml.c_str()));
    std::map<std::string, size_t> part_triangles;
    size_t files_named = 0;
    for (const pugi::xpath_node& x : doc.select_nodes("//Body[geometryFileName]")) {
        const pugi::xml_node body = x.node();
        const std::string file = lower(unquote(body.child_value("geometryFileName")));
        if (file.empty()) continue;
        const auto it = on_disk.find(file);
        if (it == on_disk.end()) continue;
        ++files_named;
        const size_t n = stl_triangles(it->second);
        part_triangles[unquote(body.child_value("name"))] = n;
        part_triangles[unquote(body.child_value("nodeID"))] = n;
    }
    CHECK(files_named >= 60);

    mbx_files::FileAdapterOptions options;
    options.mesh_dirs.push_back(mesh_dir);
    auto t = xtest::translate_file(xml, options);
    const Mechanism& m = *t->mechanism;
    ExportModel model = xtest::export_model(*t);
    OutputFiles files;
    export_body_meshes(model, MBX_MESH_STL, files);
    CHECK(model.notes().empty());  // every mesh loaded

    size_t with_geometry = 0, merged = 0;
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        const RigidBody& rb = m.bodies[b];
        CAPTURE(rb.name);
        size_t expected = 0, parts_with_files = 0;
        for (int p : rb.parts) {
            const Part& part = m.assembly.parts[size_t(p)];
            auto it = part_triangles.find(part.name);
            if (it == part_triangles.end()) it = part_triangles.find(part.id);
            if (it == part_triangles.end()) continue;
            expected += it->second;
            ++parts_with_files;
        }
        merged += parts_with_files >= 2;
        if (expected == 0) {
            CHECK_FALSE(model.has_mesh(int(b)));
            continue;
        }
        ++with_geometry;
        REQUIRE(model.has_mesh(int(b)));
        const OutputFile* f = xtest::find_file(files, model.mesh_path(int(b), MBX_MESH_STL));
        REQUIRE(f != nullptr);
        const xmesh::ReadBack r = xmesh::read_back(f->contents, "stl");
        size_t read = 0;
        for (unsigned i = 0; i < r.scene->mNumMeshes; ++i) read += r.scene->mMeshes[i]->mNumFaces;
        CHECK(read == expected);
        // The triangles are the loaded ones (body frame, metres), to float.
        CHECK(xmesh::max_difference(xmesh::triangles(r.scene), xmesh::source_triangles(t->body_shapes(int(b)))) == 0);
    }
    CHECK(files.size() == with_geometry);
    CHECK(with_geometry >= 30);

    // The whole robot as one scene: a node per meshed body at its world pose.
    OutputFiles scene;
    export_scene(model, scene);
    REQUIRE(scene.size() == 1);
    const xmesh::ReadBack r = xmesh::read_back(scene[0].contents, "glb");
    CHECK(r.scene->mRootNode->mNumChildren == with_geometry);
    const std::vector<Pose> world = forward_kinematics(m, {});
    size_t scene_triangles = 0, source_triangles = 0;
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        if (!model.has_mesh(int(b))) continue;
        for (const Mesh& mesh : t->body_shapes(int(b))) source_triangles += mesh.triangles.size() / 3;
        const aiNode* node = r.scene->mRootNode->FindNode(model.mesh_stem(int(b)).c_str());
        REQUIRE(node != nullptr);
        REQUIRE(node->mNumMeshes == 1);
        scene_triangles += r.scene->mMeshes[node->mMeshes[0]]->mNumFaces;
        const Pose got = xmesh::world_of(node);
        CHECK((got.rotation - world[b].rotation).cwiseAbs().maxCoeff() < 1e-6);
        CHECK((got.position - world[b].position).cwiseAbs().maxCoeff() < 1e-6);
    }
    CHECK(scene_triangles == source_triangles);

    MESSAGE("ergoCub: " << with_geometry << " mesh files, " << merged << " bodies merged from 2+ meshed parts");
}
}  // namespace MBX_UNITY_ID
