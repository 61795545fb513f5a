// Collision shapes in scene.glb (opt-in, ExportSettings::scene_collision):
// read back with assimp, every drawn shape is a node named after it, under
// its body's node, whose accumulated transform is the body's world pose
// times the shape's pose, with the vertex count its tessellation or hull
// has, its vertices on the primitive's surface, and a semi-transparent
// material. Planes are not drawn (noted).
#include <cmath>

#include <assimp/material.h>

#include "apps/stub_host/assemblies/builder.h"
#include "export_fixture.h"
#include "core/mechatronics/contact_description.h"
#include "export/mesh/collision_meshes.h"
#include "export/mesh/mesh_export.h"
#include "mesh_readback.h"
#include "sim/contact/convex_hull.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// A ground and one part turned and lifted, with a box mesh off its origin.
std::unique_ptr<xtest::Translated> turned_part() {
    using namespace mbx_stub::build;
    mbx_memory::Assembly a;
    a.name = "turned";
    const mbx_units si{1, 1, 1};
    Builder b(a, "turned", si, si);
    b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, Mat3::Identity(), Vec3::Zero(), Vec3::Zero(), Mat3::Identity());
    const Mat3 turn = Eigen::AngleAxisd(0.5, Vec3(0.2, 0.3, 1).normalized()).toRotationMatrix();
    b.body("part", "Part", 0, 2.0, turn, Vec3(0.3, 0.1, 0.2), Vec3(0.3, 0.1, 0.2), box_inertia(2.0, 0.1, 0.06, 0.04));
    b.mesh("part", box_mesh("part_mesh", Vec3(0.1, 0.06, 0.04), Mat3::Identity(), Vec3(0.01, 0, 0)));
    return xtest::translate(std::move(a));
}

CollisionSpec shape(const std::string& body, CollisionKind kind, const std::string& name) {
    CollisionSpec s;
    s.body = body, s.kind = kind, s.name = name;
    return s;
}

}  // namespace

TEST_CASE("scene collision: a node per shape under its body, at the shape's pose, with its vertex count") {
    auto t = turned_part();
    const Mechanism& m = *t->mechanism;
    ContactSpec spec;
    // A sphere 4 mm off the body origin: a transform assimp would drop as
    // "identity" unless written through the helper node.
    CollisionSpec sphere = shape("turned/part", CollisionKind::Sphere, "tip");
    sphere.radius = 0.01, sphere.position = Vec3(0.004, 0, 0);
    CollisionSpec box = shape("turned/part", CollisionKind::Box, "pad");
    box.size = Vec3(0.02, 0.03, 0.01), box.position = Vec3(0, 0.02, 0.05), box.rpy = Vec3(0.3, 0, 0.2);
    CollisionSpec capsule = shape("turned/part", CollisionKind::Capsule, "rod");
    capsule.radius = 0.005, capsule.length = 0.08, capsule.position = Vec3(0, -0.03, 0), capsule.rpy = Vec3(0, M_PI / 2, 0);
    CollisionSpec cylinder = shape("turned/part", CollisionKind::Cylinder, "drum");
    cylinder.radius = 0.015, cylinder.length = 0.02, cylinder.position = Vec3(-0.04, 0, 0.03);
    spec.shapes = {sphere, box, capsule, cylinder, shape("turned/part", CollisionKind::Hull, ""),
                   shape("world", CollisionKind::Plane, "floor")};
    std::vector<LibraryError> errors;
    ExportSettings settings;
    settings.model_name = "turned";
    settings.contact = resolve_contact(spec, m, errors);
    REQUIRE(errors.empty());
    REQUIRE(settings.contact.shapes.size() == 6);

    // Off by default.
    {
        ExportModel plain = xtest::export_model(*t, settings);
        OutputFiles files;
        export_scene(plain, files);
        const xmesh::ReadBack r = xmesh::read_back(files.at(0).contents, "glb");
        CHECK(r.scene->mNumMeshes == 1);
    }
    settings.scene_collision = true;
    ExportModel model = xtest::export_model(*t, settings);
    OutputFiles files;
    export_scene(model, files, true);
    REQUIRE(files.size() == 1);
    const xmesh::ReadBack r = xmesh::read_back(files[0].contents, "glb");
    CHECK(r.scene->mNumMeshes == 6);  // the body and five shapes (the plane is not drawn)
    bool plane_noted = false;
    for (const Finding& f : model.notes())
        plane_noted |= f.message.find("plane 'floor' is unbounded and left out") != std::string::npos;
    CHECK(plane_noted);

    const int body = 1;
    const aiNode* body_node = r.scene->mRootNode->FindNode(model.mesh_stem(body).c_str());
    REQUIRE(body_node);
    const Pose body_pose = m.bodies[size_t(body)].pose;
    const size_t n = kCollisionSegments, rings = kCollisionRings;
    struct Want {
        const char* node;
        size_t vertices;
    };
    std::vector<Eigen::Vector3d> mesh_points;
    for (const Mesh& mesh : t->body_shapes(body)) mesh_points.insert(mesh_points.end(), mesh.vertices.begin(), mesh.vertices.end());
    const size_t hull_vertices = sim::contact::convex_hull(mesh_points, "hull").vertices.size();
    CHECK(hull_vertices == 8);
    const Want wants[] = {{"collision_tip", 2 + (rings - 1) * n},
                          {"collision_pad", 8},
                          {"collision_rod", 2 + rings * n},
                          {"collision_drum", 2 + 2 * n},
                          {"collision_Part_hull", hull_vertices}};
    for (size_t i = 0; i < 5; ++i) {
        const Want& w = wants[i];
        const ResolvedCollision& c = settings.contact.shapes[i];
        CAPTURE(std::string(w.node));
        const aiNode* node = r.scene->mRootNode->FindNode(w.node);
        REQUIRE(node);
        // Under the body's node, so it moves with the body in the view.
        bool under_body = false;
        for (const aiNode* p = node->mParent; p; p = p->mParent) under_body |= p == body_node;
        CHECK(under_body);
        const Pose want = body_pose * c.pose;
        const Pose got = xmesh::world_of(node);
        CHECK((got.rotation - want.rotation).cwiseAbs().maxCoeff() < 1e-6);
        CHECK((got.position - want.position).cwiseAbs().maxCoeff() < 1e-6);
        REQUIRE(node->mNumMeshes == 1);
        const aiMesh* mesh = r.scene->mMeshes[node->mMeshes[0]];
        CHECK(mesh->mNumVertices == w.vertices);
        // Semi-transparent.
        float opacity = 1;
        r.scene->mMaterials[mesh->mMaterialIndex]->Get(AI_MATKEY_OPACITY, opacity);
        CHECK(opacity < 0.5f);
        // Every vertex, taken to the world through the node, on the shape's
        // surface there (float precision).
        for (unsigned k = 0; k < mesh->mNumVertices; ++k) {
            const Vec3 x = got.apply(Vec3(mesh->mVertices[k].x, mesh->mVertices[k].y, mesh->mVertices[k].z));
            const Vec3 local = want.inverse().apply(x);  // in the shape's frame
            const CollisionSpec& s = c.spec;
            switch (s.kind) {
            case CollisionKind::Sphere: CHECK(std::abs(local.norm() - s.radius) < 1e-6); break;
            case CollisionKind::Box: CHECK((local.cwiseAbs() - s.size / 2).cwiseAbs().maxCoeff() < 1e-6); break;
            case CollisionKind::Cylinder: {
                const double radial = local.head<2>().norm();
                CHECK((std::abs(radial - s.radius) < 1e-6 || radial < 1e-6));  // the rim, or a cap's centre
                CHECK(std::abs(std::abs(local.z()) - s.length / 2) < 1e-6);
                break;
            }
            case CollisionKind::Capsule: {
                const double z = std::clamp(local.z(), -s.length / 2, s.length / 2);
                CHECK(std::abs((local - Vec3(0, 0, z)).norm() - s.radius) < 1e-6);
                break;
            }
            case CollisionKind::Hull: {
                // The box mesh's corners: the world points of the host's mesh.
                double nearest = 1e300;
                for (const Eigen::Vector3d& p : mesh_points) nearest = std::min(nearest, (body_pose.apply(p) - x).norm());
                CHECK(nearest < 1e-6);
                break;
            }
            case CollisionKind::Plane: break;
            }
        }
    }
}
}  // namespace MBX_UNITY_ID
