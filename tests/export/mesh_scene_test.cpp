// scene.glb: the whole assembly as a binary glTF, read back by assimp. Node
// transforms are checked against mbx's forward kinematics at zero
// coordinates, and the world geometry against the host's own data (its
// units, body poses and mesh poses), so frames and units are both covered.
#include "export_fixture.h"
#include "export/mesh/mesh_export.h"
#include "mesh_readback.h"

namespace MBX_UNITY_ID {

using namespace mbx;

TEST_CASE("mesh scene: one node per body with geometry at its world pose, geometry in metres") {
    // six_axis_arm: SI, merged parts, rotated part frames; fourbar: mm and
    // g; double_cardan: cm and mm, joint nodes (no geometry).
    for (const std::string name : {"six_axis_arm", "fourbar", "double_cardan"}) {
        CAPTURE(name);
        mbx_memory::Assembly host;
        REQUIRE(mbx_stub::builtin_assembly(name, host));
        auto t = xtest::translate_builtin(name);
        const Mechanism& m = *t->mechanism;
        ExportSettings settings;
        settings.model_name = name;
        ExportModel model = xtest::export_model(*t, settings);
        OutputFiles files;
        export_scene(model, files);
        REQUIRE(files.size() == 1);
        CHECK(files[0].path == "scene.glb");
        CHECK(files[0].contents.compare(0, 4, "glTF") == 0);

        const xmesh::ReadBack r = xmesh::read_back(files[0].contents, "glb");
        const aiNode* root = r.scene->mRootNode;
        const std::vector<Pose> world = forward_kinematics(m, {});
        size_t with_geometry = 0, total_source = 0, total_read = 0;
        for (size_t b = 0; b < m.bodies.size(); ++b) {
            CAPTURE(m.bodies[b].name);
            const std::vector<Mesh>& source = t->body_shapes(int(b));
            size_t source_triangles = 0;
            for (const Mesh& mesh : source) source_triangles += mesh.triangles.size() / 3;
            if (source_triangles == 0) continue;
            ++with_geometry;
            total_source += source_triangles;

            const aiNode* node = root->FindNode(model.mesh_stem(int(b)).c_str());
            REQUIRE(node != nullptr);
            REQUIRE(node->mNumMeshes == 1);
            const aiMesh* mesh = r.scene->mMeshes[node->mMeshes[0]];
            CHECK(std::string(mesh->mName.C_Str()) == model.mesh_stem(int(b)));
            total_read += mesh->mNumFaces;

            // Node pose = the body's world pose from forward kinematics.
            const Pose got = xmesh::world_of(node);
            CHECK((got.rotation - world[b].rotation).cwiseAbs().maxCoeff() < 1e-6);
            CHECK((got.position - world[b].position).cwiseAbs().maxCoeff() < 1e-6);

            // The mesh itself is in the body frame: exactly the source triangles.
            const auto local = xmesh::triangles(mesh);
            CHECK(xmesh::max_difference(local, xmesh::source_triangles(source)) == 0);

            // In the world, the node's geometry covers what the host placed
            // there: its parts' meshes through body poses, mesh poses and units.
            xmesh::Box want, seen;
            for (int p : m.bodies[b].parts)
                for (const Vec3& v : xmesh::host_world_vertices(host, m.assembly.parts[size_t(p)].id)) want.add(v);
            for (unsigned v = 0; v < mesh->mNumVertices; ++v)
                seen.add(got.apply(Vec3(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z)));
            CHECK((seen.lo - want.lo).cwiseAbs().maxCoeff() < 1e-6);
            CHECK((seen.hi - want.hi).cwiseAbs().maxCoeff() < 1e-6);
        }
        CHECK(root->mNumChildren == with_geometry);  // one (possibly helper) node per body
        CHECK(r.scene->mNumMeshes == with_geometry);
        CHECK(total_read == total_source);
        CHECK(with_geometry >= 3);
    }
}

TEST_CASE("mesh scene: nothing is written when no body has geometry") {
    auto t = xtest::translate_builtin("fourbar");
    ExportModel model(*t->mechanism, BodyShapes{}, ExportSettings{});
    OutputFiles files;
    export_scene(model, files);
    export_body_meshes(model, MBX_MESH_STL, files);
    CHECK(files.empty());
}

TEST_CASE("mesh scene: poses within assimp's 0.01 identity tolerance keep their exact offset") {
    // assimp drops node matrices that IsIdentity() accepts (0.01 per entry);
    // ergoCub has bodies 0.05 mm off the origin. Move bodies of the arm there.
    auto t = xtest::translate_builtin("six_axis_arm");
    Mechanism m = *t->mechanism;
    REQUIRE(m.bodies.size() >= 5);
    m.bodies[1].pose = Pose{Mat3::Identity(), Vec3(0.003, -0.002, 5e-5)};
    m.bodies[2].pose = Pose{Eigen::AngleAxisd(0.004, Vec3(1, 2, 3).normalized()).toRotationMatrix(), Vec3(0.001, 0, 0)};
    m.bodies[3].pose = Pose{};  // exactly the origin: needs no matrix at all
    m.bodies[4].pose = Pose{Eigen::AngleAxisd(0.5, Vec3::UnitZ()).toRotationMatrix(), Vec3(0.2, 0.1, 0.3)};
    // The model is named like a body: assimp renames duplicate node names,
    // so the body nodes must still carry their own.
    ExportSettings settings;
    settings.model_name = ExportModel(m, [&](int b) -> const std::vector<Mesh>& { return t->body_shapes(b); },
                                      ExportSettings{}).mesh_stem(1);
    ExportModel model(m, [&](int b) -> const std::vector<Mesh>& { return t->body_shapes(b); }, settings);
    OutputFiles files;
    export_scene(model, files);
    REQUIRE(files.size() == 1);
    const xmesh::ReadBack r = xmesh::read_back(files[0].contents, "glb");
    for (int b = 0; b <= 4; ++b) {
        CAPTURE(b);
        REQUIRE(model.has_mesh(b));
        const aiNode* node = r.scene->mRootNode->FindNode(model.mesh_stem(b).c_str());
        REQUIRE(node != nullptr);
        CHECK(node->mNumMeshes == 1);
        const Pose got = xmesh::world_of(node);
        CHECK((got.rotation - m.bodies[size_t(b)].pose.rotation).cwiseAbs().maxCoeff() < 1e-7);
        CHECK((got.position - m.bodies[size_t(b)].pose.position).cwiseAbs().maxCoeff() < 1e-7);
    }
}
}  // namespace MBX_UNITY_ID
