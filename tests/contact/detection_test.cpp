// Collision detection (sim/contact/detection.h) against closed forms: the
// depth, normal and point of a sphere or capsule on a plane and of two
// spheres; a box resting on a tilted plane gets all four corners of its
// face (FCL alone gives one); shapes on one body or on bodies joined by a
// joint never collide; and random box/convex pairs never throw and give unit
// normals that separate the shapes.
#include <doctest/doctest.h>

#include <random>

#include "tests/export/export_fixture.h"
#include "sim/build_model.h"
#include "sim/contact/detection.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::sim::contact;

namespace {

// A model to carry shapes: the six-axis arm's bodies, their world poses
// set by hand (detection reads only data.x_world).
struct Bodies {
    std::unique_ptr<xtest::Translated> t = xtest::translate_builtin("six_axis_arm");
    sim::Model model = sim::build_model(*t->mechanism);
    sim::Data data{model};
    Bodies() {
        REQUIRE(model.body_count() >= 5);
        for (auto& x : data.x_world) x = sim::Transform<double>{Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()};
    }
    void place(int body, const Eigen::Matrix3d& R, const Eigen::Vector3d& p) { data.x_world[size_t(body)] = {R, p}; }
};

Shape plane(const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity(), const Eigen::Vector3d& p = Eigen::Vector3d::Zero()) {
    Shape s;
    s.kind = ShapeKind::HalfSpace, s.name = "ground", s.body = 0, s.rotation = R, s.position = p;
    return s;
}

Shape sphere(int body, double r, const char* name = "ball") {
    Shape s;
    s.kind = ShapeKind::Sphere, s.name = name, s.body = body, s.radius = r;
    return s;
}

Shape box(int body, const Eigen::Vector3d& size) {
    Shape s;
    s.kind = ShapeKind::Box, s.name = "box", s.body = body, s.size = size;
    return s;
}

Eigen::Matrix3d rot(double angle, const Eigen::Vector3d& axis) {
    return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

}  // namespace

TEST_CASE("contact detection: a sphere sunk into a tilted plane, and two spheres") {
    Bodies b;
    const Eigen::Matrix3d tilt = rot(0.3, Eigen::Vector3d(1, 2, 0));
    const Eigen::Vector3d n = tilt.col(2);
    Scene scene(b.model, {plane(tilt), sphere(3, 0.1)});
    // Centre 0.08 above the plane along its normal: 0.02 deep.
    const Eigen::Vector3d along(0.4, -0.2, 0);
    const Eigen::Vector3d on_plane = along - n * n.dot(along);
    b.place(3, Eigen::Matrix3d::Identity(), on_plane + 0.08 * n);
    std::vector<Contact> c;
    scene.detect(b.data, c);
    REQUIRE(c.size() == 1);
    CHECK(c[0].shape_a == 0);  // the plane first
    CHECK(c[0].shape_b == 1);
    CHECK(c[0].depth == mbx_test::relative(0.02, 1e-6));
    CHECK((c[0].normal - n).norm() < 1e-6);  // from the plane into the sphere
    // The point lies between the sphere's lowest point and the plane.
    CHECK(std::abs(n.dot(c[0].point - on_plane)) < 0.02 + 1e-9);
    // Lifted clear: nothing.
    b.place(3, Eigen::Matrix3d::Identity(), on_plane + 0.1001 * n);
    scene.detect(b.data, c);
    CHECK(c.empty());

    // Two spheres of 0.1 and 0.05, centres 0.12 apart: 0.03 deep, normal along the centres.
    Scene two(b.model, {sphere(2, 0.1, "a"), sphere(4, 0.05, "b")});
    b.place(2, Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 1, 1));
    const Eigen::Vector3d dir = Eigen::Vector3d(1, -2, 2).normalized();
    b.place(4, rot(1.0, Eigen::Vector3d::UnitX()), Eigen::Vector3d(1, 1, 1) + 0.12 * dir);
    two.detect(b.data, c);
    REQUIRE(c.size() == 1);
    CHECK(c[0].depth == mbx_test::relative(0.03, 1e-6));
    CHECK((c[0].normal - dir).norm() < 1e-6);
}

TEST_CASE("contact detection: a box on a tilted plane touches with all four corners of its face") {
    Bodies b;
    const Eigen::Matrix3d tilt = rot(0.25, Eigen::Vector3d::UnitY());
    Scene scene(b.model, {plane(tilt, Eigen::Vector3d(0, 0, 0.5)), box(3, Eigen::Vector3d(0.2, 0.1, 0.05))});
    // The box's face parallel to the plane, 1 mm into it; then tipped by a small angle.
    const Eigen::Vector3d n = tilt.col(2);
    b.place(3, tilt, Eigen::Vector3d(0, 0, 0.5) + (0.025 - 0.001) * n);
    std::vector<Contact> c;
    scene.detect(b.data, c);
    REQUIRE(c.size() == 4);
    for (const Contact& k : c) {
        CHECK(k.depth == mbx_test::relative(0.001, 1e-6));
        CHECK((k.normal - n).norm() < 1e-12);
    }
    // Tipped about the box's x axis by 0.005 rad: two corners deeper, two shallower (or clear).
    b.place(3, tilt * rot(0.005, Eigen::Vector3d::UnitX()), Eigen::Vector3d(0, 0, 0.5) + (0.025 - 0.001) * n);
    scene.detect(b.data, c);
    REQUIRE(c.size() == 4);
    double deepest = 0, shallowest = 1;
    for (const Contact& k : c) deepest = std::max(deepest, k.depth), shallowest = std::min(shallowest, k.depth);
    // Corners at y = +-0.05, z = -0.025 tipped by 0.005 go to z' = +-0.05 sin(0.005) - 0.025 cos(0.005):
    // depth 0.001 +- 0.05 sin(0.005) - 0.025 (1 - cos 0.005).
    CHECK(deepest == mbx_test::relative(0.001 + 0.05 * std::sin(0.005) - 0.025 * (1 - std::cos(0.005)), 1e-9));
    CHECK(shallowest == mbx_test::relative(0.001 - 0.05 * std::sin(0.005) - 0.025 * (1 - std::cos(0.005)), 1e-6));
}

TEST_CASE("contact detection: capsules, filtering and bad shapes") {
    Bodies b;
    Shape capsule;
    capsule.kind = ShapeKind::Capsule, capsule.name = "rod", capsule.body = 3, capsule.radius = 0.02, capsule.length = 0.3;
    // Lying along x on the ground plane, its axis 0.015 above: 0.005 deep along its length.
    capsule.rotation = rot(M_PI / 2, Eigen::Vector3d::UnitY());
    Shape on_parent = sphere(2, 0.5, "parent");  // body 2 is body 3's parent in the arm
    Shape same_body = sphere(3, 0.5, "same");
    Scene scene(b.model, {plane(), capsule, on_parent, same_body});
    b.place(3, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.015));
    b.place(2, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.8));
    std::vector<Contact> c;
    scene.detect(b.data, c);
    // The capsule and the sphere on body 3 touch the plane; the big spheres
    // overlap the capsule but are joined to it (parent) or on its body.
    int rod = 0;
    for (const Contact& k : c) {
        CHECK(k.shape_a == 0);
        if (k.shape_b == 1) {
            ++rod;
            CHECK(k.depth == mbx_test::relative(0.005, 1e-6));
            CHECK(k.normal.z() == mbx_test::relative(1, 1e-6));
        }
    }
    CHECK(rod >= 1);
    REQUIRE(b.model.bodies[3].parent == 2);
    // Groups: the sphere on body 3 masked out of everything.
    std::vector<Shape> masked = scene.shapes();
    masked[3].mask = 0;
    Scene filtered(b.model, masked);
    filtered.detect(b.data, c);
    for (const Contact& k : c) CHECK(k.shape_b != 3);

    Shape bad = sphere(3, -1, "negative");
    CHECK_THROWS_WITH_AS(Scene(b.model, {bad}), doctest::Contains("collision shape 'negative': radius must be a positive number"), Error);
    Shape nowhere = sphere(99, 0.1, "lost");
    CHECK_THROWS_WITH_AS(Scene(b.model, {nowhere}), doctest::Contains("'lost': its body 99"), Error);
}

TEST_CASE("contact detection: random box and convex pairs never throw, normals are unit and separate") {
    Bodies b;
    auto octahedron = std::make_shared<ConvexHull>();
    octahedron->vertices = {{0.1, 0, 0}, {-0.1, 0, 0}, {0, 0.1, 0}, {0, -0.1, 0}, {0, 0, 0.1}, {0, 0, -0.1}};
    const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (const auto& f : faces) octahedron->faces.insert(octahedron->faces.end(), {3, f[0], f[1], f[2]});
    octahedron->face_count = 8;
    Shape hull;
    hull.kind = ShapeKind::Convex, hull.name = "octahedron", hull.body = 4, hull.hull = octahedron;
    Scene scene(b.model, {box(2, Eigen::Vector3d(0.2, 0.15, 0.1)), hull});
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Contact> c;
    // The 1e5 pairs; violations are counted so that a failure says
    // how many, not 1e5 lines.
    constexpr int kPairs = 100000;
    size_t touching = 0, contacts = 0, bad_normal = 0, negative_depth = 0, flipped = 0, fcl_failures = 0;
    for (int i = 0; i < kPairs; ++i) {
        b.place(2, rot(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng) + 1e-3)), Eigen::Vector3d::Zero());
        b.place(4, rot(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng) + 1e-3)),
                0.2 * Eigen::Vector3d(u(rng), u(rng), u(rng)));
        REQUIRE_NOTHROW(scene.detect(b.data, c));
        fcl_failures += scene.stats().failed_pairs;
        touching += !c.empty();
        for (const Contact& k : c) {
            ++contacts;
            bad_normal += !(std::abs(k.normal.norm() - 1) < 1e-9);
            negative_depth += !(k.depth >= -1e-9);
            // From the box (a) into the octahedron (b): roughly from a's centre towards b's.
            const Eigen::Vector3d between = b.data.x_world[4].p - b.data.x_world[2].p;
            flipped += between.norm() > 0.05 && !(k.normal.dot(between) > -1e-9);
        }
    }
    MESSAGE(touching << " of " << kPairs << " random poses touch, " << contacts << " contacts, FCL failed on "
                     << fcl_failures << " pairs");
    CHECK(bad_normal == 0);
    CHECK(negative_depth == 0);
    CHECK(flipped == 0);
    CHECK(touching > kPairs / 10);
}
}  // namespace MBX_UNITY_ID
