// URDF <collision> elements from the description's collision shapes, read
// back by urdfdom: each one's geometry type and sizes are the shape's, and
// its origin, composed with the link poses urdfdom's joints give, puts it
// where the shape is on its body at the CAD pose (the link frame is not the
// body frame: it sits at the parent joint's point). A hull is a mesh file
// whose vertices, through that origin, are the corners of the part's mesh.
#include <cmath>

#include "apps/stub_host/assemblies/builder.h"
#include "core/mechatronics/contact_description.h"
#include "mesh_readback.h"
#include "urdf_consumer.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// A ground and a part turned and lifted, hinged to the ground at a point
// away from the part's origin, with a box mesh off its origin.
std::unique_ptr<xtest::Translated> hinged_part() {
    using namespace mbx_stub::build;
    mbx_memory::Assembly a;
    a.name = "hinged";
    const mbx_units si{1, 1, 1};
    Builder b(a, "hinged", si, si);
    const Mat3 tilt = Eigen::AngleAxisd(0.2, Vec3::UnitX()).toRotationMatrix();
    b.body("ground", "Ground", MBX_BODY_GROUND, 3.0, tilt, Vec3(0, 0, -0.1), Vec3(0, 0, -0.1), box_inertia(3.0, 0.4, 0.4, 0.05));
    const Mat3 turn = Eigen::AngleAxisd(0.5, Vec3(0.2, 0.3, 1).normalized()).toRotationMatrix();
    b.body("part", "Part", 0, 2.0, turn, Vec3(0.3, 0.1, 0.2), Vec3(0.3, 0.1, 0.2), box_inertia(2.0, 0.1, 0.06, 0.04));
    b.mesh("part", box_mesh("part_mesh", Vec3(0.1, 0.06, 0.04), Mat3::Identity(), Vec3(0.01, 0, 0)));
    b.joint("hinge", "ground", "part", Vec3(0.35, 0.12, 0.18), Mat3::Identity(), {revolute(Vec3(0, 1, 0.3).normalized())},
            MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    return xtest::translate(std::move(a));
}

CollisionSpec shape(const std::string& body, CollisionKind kind, const std::string& name) {
    CollisionSpec s;
    s.body = body, s.kind = kind, s.name = name;
    return s;
}

}  // namespace

TEST_CASE("urdf collision: each shape's geometry, and its origin placing it on its body, read back by urdfdom") {
    auto t = hinged_part();
    const Mechanism& m = *t->mechanism;
    ContactSpec spec;
    CollisionSpec sphere = shape("hinged/part", CollisionKind::Sphere, "tip");
    sphere.radius = 0.01, sphere.position = Vec3(0.004, 0, 0.01);
    CollisionSpec box = shape("hinged/part", CollisionKind::Box, "pad");
    box.size = Vec3(0.02, 0.03, 0.01), box.position = Vec3(0, 0.02, 0.05), box.rpy = Vec3(0.3, -0.1, 0.2);
    CollisionSpec cylinder = shape("hinged/part", CollisionKind::Cylinder, "drum");
    cylinder.radius = 0.015, cylinder.length = 0.02, cylinder.position = Vec3(-0.04, 0, 0.03), cylinder.rpy = Vec3(0, 0.4, 0);
    CollisionSpec capsule = shape("hinged/part", CollisionKind::Capsule, "rod");
    capsule.radius = 0.005, capsule.length = 0.08, capsule.position = Vec3(0, -0.03, 0), capsule.rpy = Vec3(0, M_PI / 2, 0.1);
    CollisionSpec stop = shape("hinged/ground", CollisionKind::Box, "stop");
    stop.size = Vec3(0.05, 0.05, 0.05), stop.position = Vec3(0.1, 0, 0.05);
    spec.shapes = {sphere, box, cylinder, capsule, shape("hinged/part", CollisionKind::Hull, "shell"), stop,
                   shape("world", CollisionKind::Plane, "floor")};
    std::vector<LibraryError> errors;
    ExportSettings settings;
    settings.model_name = "hinged";
    settings.contact = resolve_contact(spec, m, errors);
    REQUIRE(errors.empty());
    REQUIRE(settings.contact.shapes.size() == 7);

    ExportModel model = xtest::export_model(*t, settings);
    OutputFiles files;
    export_urdf(model, files);
    const OutputFile* file = xtest::find_file(files, "urdf/hinged.urdf");
    REQUIRE(file);
    const urdf::ModelInterfaceSharedPtr u = urdf::parseURDF(file->contents);
    REQUIRE(u);
    const std::map<std::string, Pose> links = urdf_test::link_poses(*u, {});

    // Every <collision> by name, with its world pose at zero coordinates.
    struct Read {
        urdf::CollisionSharedPtr element;
        Pose world;
    };
    std::map<std::string, Read> read;
    for (const auto& [name, link] : u->links_)
        for (const urdf::CollisionSharedPtr& c : link->collision_array) {
            CHECK(read.count(c->name) == 0);
            read[c->name] = {c, links.at(name) * urdf_test::to_pose(c->origin)};
        }
    CHECK(read.size() == 8);  // five shapes, the capsule's two end spheres, the hull; no plane
    bool plane_noted = false;
    for (const Finding& f : model.notes()) plane_noted |= f.message.find("plane 'floor' has no URDF geometry") != std::string::npos;
    CHECK(plane_noted);

    auto placed = [&](const std::string& name, const Pose& want) {
        CAPTURE(name);
        REQUIRE(read.count(name));
        CHECK(urdf_test::pose_error(read[name].world, want) < 1e-9);
        return read[name].element->geometry;
    };
    for (const ResolvedCollision& r : settings.contact.shapes) {
        const Pose want = m.bodies[size_t(r.body)].pose * r.pose;  // CAD pose = zero coordinates
        const CollisionSpec& s = r.spec;
        switch (s.kind) {
        case CollisionKind::Sphere: {
            const auto g = placed(r.name, want);
            REQUIRE(g->type == urdf::Geometry::SPHERE);
            CHECK(std::static_pointer_cast<urdf::Sphere>(g)->radius == mbx_test::relative(s.radius, 1e-6));
            break;
        }
        case CollisionKind::Box: {
            const auto g = placed(r.name, want);
            REQUIRE(g->type == urdf::Geometry::BOX);
            CHECK((urdf_test::to_vec(std::static_pointer_cast<urdf::Box>(g)->dim) - s.size).norm() < 1e-12);
            break;
        }
        case CollisionKind::Cylinder:
        case CollisionKind::Capsule: {
            const auto g = placed(r.name, want);
            REQUIRE(g->type == urdf::Geometry::CYLINDER);
            CHECK(std::static_pointer_cast<urdf::Cylinder>(g)->radius == mbx_test::relative(s.radius, 1e-6));
            CHECK(std::static_pointer_cast<urdf::Cylinder>(g)->length == mbx_test::relative(s.length, 1e-6));
            if (s.kind == CollisionKind::Capsule)
                for (const char* end : {"_cap0", "_cap1"}) {
                    // The caps' centres: the axis ends, along the shape's z.
                    const double z = (end[4] == '0' ? -0.5 : 0.5) * s.length;
                    const auto cap = placed(r.name + end, want * Pose{Mat3::Identity(), Vec3(0, 0, z)});
                    REQUIRE(cap->type == urdf::Geometry::SPHERE);
                    CHECK(std::static_pointer_cast<urdf::Sphere>(cap)->radius == mbx_test::relative(s.radius, 1e-6));
                }
            break;
        }
        case CollisionKind::Hull: {
            const auto g = placed(r.name, want);
            REQUIRE(g->type == urdf::Geometry::MESH);
            const std::string filename = std::static_pointer_cast<urdf::Mesh>(g)->filename;
            CHECK(filename.rfind("../meshes/collision/", 0) == 0);
            const OutputFile* stl = xtest::find_file(files, filename.substr(3));
            REQUIRE(stl);
            const xmesh::ReadBack back = xmesh::read_back(stl->contents, "stl");
            REQUIRE(back.scene->mNumMeshes == 1);
            const aiMesh* mesh = back.scene->mMeshes[0];
            CHECK(mesh->mNumFaces == 12);  // the box's hull: two triangles a side
            std::vector<Vec3> corners;
            for (const Mesh& part : t->body_shapes(r.body))
                for (const Vec3& p : part.vertices) corners.push_back(m.bodies[size_t(r.body)].pose.apply(p));
            for (unsigned k = 0; k < mesh->mNumVertices; ++k) {
                const Vec3 x = read[r.name].world.apply(Vec3(mesh->mVertices[k].x, mesh->mVertices[k].y, mesh->mVertices[k].z));
                double nearest = 1e300;
                for (const Vec3& c : corners) nearest = std::min(nearest, (c - x).norm());
                CHECK(nearest < 1e-6);  // float
            }
            break;
        }
        case CollisionKind::Plane: CHECK(read.count(r.name) == 0); break;
        }
    }
}
}  // namespace MBX_UNITY_ID
