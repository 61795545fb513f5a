// The default collision shapes from the CAD geometry (docs/contact.md): the
// description's body="*" hull gives a convex hull per moving part with a
// mesh, a body's own shapes replace it. Checked on the real ergoCub export
// (66 STL meshes): every hull holds its mesh's vertices, stays within the
// vertex cap, and a part dropped onto a plane with its hull comes to rest on
// its lowest hull vertex.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <set>

#include "contact_scenes.h"
#include "tests/export/export_fixture.h"
#include "core/mechatronics/contact_description.h"
#include "sim/build_model.h"
#include "sim/contact/contact_step.h"
#include "sim/contact/convex_hull.h"
#include "sim/contact/detection.h"
#include "sim/dynamics.h"
#include "tests/common/skip.h"
#include "tests/common/slow_build.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::sim::contact;

namespace {

constexpr double g = 9.81;

std::unique_ptr<xtest::Translated> ergocub() {
    const std::string root = mbx_test::shared_data("pmxml/ergocub");
    mbx_files::FileAdapterOptions o;
    o.mesh_dirs.push_back(root + "/meshes/simmechanics");
    return xtest::translate_file(root + "/SIM_ERGOCUB_1-0.xml", o);
}

CollisionSpec hull_default() {
    CollisionSpec s;
    s.body = "*", s.kind = CollisionKind::Hull;
    return s;
}

// The vertices of part `part`'s meshes in its body's frame.
std::vector<Eigen::Vector3d> part_points(xtest::Translated& t, int body, int part) {
    std::vector<Eigen::Vector3d> points;
    const std::string& id = t.mechanism->assembly.parts[size_t(part)].id;
    for (const Mesh& mesh : t.body_shapes(body))
        if (mesh.part_id == id) points.insert(points.end(), mesh.vertices.begin(), mesh.vertices.end());
    return points;
}

// Largest distance of a point outside the hull (<= 0: all inside).
double outside(const ConvexHull& h, const std::vector<Eigen::Vector3d>& points) {
    double worst = -1e300;
    for (int f = 0; f < h.face_count; ++f) {
        const Eigen::Vector3d& a = h.vertices[size_t(h.faces[size_t(4 * f + 1)])];
        const Eigen::Vector3d& b = h.vertices[size_t(h.faces[size_t(4 * f + 2)])];
        const Eigen::Vector3d& c = h.vertices[size_t(h.faces[size_t(4 * f + 3)])];
        const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
        for (const Eigen::Vector3d& p : points) worst = std::max(worst, n.dot(p - a));
    }
    return worst;
}

}  // namespace

TEST_CASE("default hulls: a body's own shapes replace the default, parts without a mesh are skipped, asking twice is once") {
    auto t = xtest::translate_builtin("double_cardan");
    const Mechanism& m = *t->mechanism;
    int moving = 0, first = -1;
    size_t parts = 0;
    for (size_t b = 1; b < m.bodies.size(); ++b)
        if (m.bodies[b].kind == MBX_RIGID_BODY_DYNAMIC) {
            ++moving, parts += m.bodies[b].parts.size();
            if (first < 0) first = int(b);
        }
    REQUIRE(moving >= 2);
    ContactSpec spec;
    spec.shapes.push_back(hull_default());
    std::vector<LibraryError> errors;
    const ResolvedContact all = resolve_contact(spec, m, errors);
    REQUIRE(errors.empty());
    CHECK(all.shapes.size() == parts);
    for (const ResolvedCollision& r : all.shapes) CHECK(r.from_default);

    // A sphere on the first moving body (named by its id) and the default
    // again: that body keeps only its sphere, every other body its hulls.
    CollisionSpec sphere;
    sphere.body = m.bodies[size_t(first)].id, sphere.kind = CollisionKind::Sphere, sphere.radius = 0.01;
    spec.shapes.push_back(sphere);
    spec.shapes.push_back(hull_default());
    const ResolvedContact some = resolve_contact(spec, m, errors);
    REQUIRE(errors.empty());
    CHECK(some.shapes.size() == parts - m.bodies[size_t(first)].parts.size() + 1);
    for (const ResolvedCollision& r : some.shapes) {
        CHECK((r.body == first) == (r.spec.kind == CollisionKind::Sphere));
        CHECK(r.from_default == (r.spec.kind == CollisionKind::Hull));
    }
}

TEST_CASE("default hulls: every ergoCub part with a mesh gets a hull holding its mesh's vertices, within the vertex cap") {
    auto t = ergocub();
    REQUIRE(t);
    const Mechanism& m = *t->mechanism;
    ContactSpec spec;
    spec.shapes.push_back(hull_default());
    std::vector<LibraryError> errors;
    const ResolvedContact rc = resolve_contact(spec, m, errors);
    REQUIRE(errors.empty());
    // The parts that have a mesh, counted from the meshes themselves.
    std::set<std::string> meshed;
    for (size_t b = 1; b < m.bodies.size(); ++b)
        for (const Mesh& mesh : t->body_shapes(int(b)))
            if (!mesh.vertices.empty()) meshed.insert(mesh.part_id);
    CHECK(meshed.size() >= 60);

    size_t hulls = 0, without_mesh = 0, capped = 0, points_total = 0;
    double worst_inflation = 1, seconds = 0;
    std::set<std::string> hulled;
    for (const ResolvedCollision& r : rc.shapes) {
        const std::vector<Eigen::Vector3d> points = part_points(*t, r.body, r.hull_part);
        if (points.empty()) {
            ++without_mesh;  // the simulator and the exports skip these (noted)
            continue;
        }
        HullStats stats;
        const auto t0 = std::chrono::steady_clock::now();
        const ConvexHull h = convex_hull(points, r.name, kMaxHullVertices, &stats);
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        ++hulls, points_total += points.size();
        hulled.insert(m.assembly.parts[size_t(r.hull_part)].id);
        CHECK(int(h.vertices.size()) <= kMaxHullVertices);
        CHECK(h.face_count == 2 * int(h.vertices.size()) - 4);
        Eigen::Vector3d lo = points[0], hi = points[0];
        for (const Eigen::Vector3d& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        INFO(r.name << ": " << points.size() << " mesh vertices, " << h.vertices.size() << " on the hull");
        CHECK(outside(h, points) <= 1e-8 * (hi - lo).norm());
        if (stats.capped) ++capped, worst_inflation = std::max(worst_inflation, stats.inflation);
    }
    CHECK(hulled == meshed);  // exactly the parts with a mesh
    MESSAGE("ergoCub: " << hulls << " hulls over " << points_total << " mesh vertices in " << seconds << " s; "
                        << without_mesh << " moving parts without a mesh; " << capped
                        << " hulls capped, largest inflation " << worst_inflation);
}

TEST_CASE("default hulls: hull cost grows near-linearly with the point count") {
    // Points on an ellipsoid are all on the exact hull, so the cap is what
    // keeps the work per point bounded; inside a ball most points are
    // dropped at once.
    std::mt19937 rng(3);
    std::normal_distribution<double> gauss;
    auto cloud = [&](size_t n) {
        std::vector<Eigen::Vector3d> p(n);
        for (auto& x : p) x = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized().cwiseProduct(Eigen::Vector3d(0.3, 0.1, 0.05));
        return p;
    };
    auto best_time = [&](const std::vector<Eigen::Vector3d>& p, HullStats& stats) {
        double best = 1e300;
        for (int k = 0; k < 3; ++k) {
            const auto t0 = std::chrono::steady_clock::now();
            const ConvexHull h = convex_hull(p, "cloud", kMaxHullVertices, &stats);
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            CHECK(int(h.vertices.size()) <= kMaxHullVertices);
            CHECK(outside(h, p) <= 1e-8);
        }
        return best;
    };
    HullStats small_stats, large_stats;
    // The sanitizers' build checks the same ratio on an eighth of the points.
    const size_t n_small = kSlowBuild ? 6250 : 50000;
    const auto small = cloud(n_small), large = cloud(8 * n_small);
    const double t_small = best_time(small, small_stats), t_large = best_time(large, large_stats);
    CHECK(small_stats.capped);
    CHECK(large_stats.capped);
    // 256 vertices spread over the ellipsoid: within a few percent of it.
    CHECK(large_stats.inflation < 1.05);
    // Eight times the points: linear is 8x the time, quadratic 64x.
    MESSAGE("hull of " << n_small << " points " << t_small * 1e3 << " ms, of " << 8 * n_small << " " << t_large * 1e3 << " ms (ratio " << t_large / t_small
                                  << "); inflation " << small_stats.inflation << ", " << large_stats.inflation);
    CHECK(t_large / t_small < 20);
}

TEST_CASE("default hulls: an ergoCub part dropped onto a plane with its default hull rests on its lowest hull vertex") {
    auto t = ergocub();
    REQUIRE(t);
    const Mechanism& m = *t->mechanism;
    ContactSpec spec;
    spec.shapes.push_back(hull_default());
    std::vector<LibraryError> errors;
    const ResolvedContact rc = resolve_contact(spec, m, errors);
    REQUIRE(errors.empty());
    // The single-part body with the most mesh vertices.
    const ResolvedCollision* pick = nullptr;
    size_t most = 0;
    for (const ResolvedCollision& r : rc.shapes) {
        const RigidBody& body = m.bodies[size_t(r.body)];
        if (body.parts.size() != 1 || body.mass < 0.1) continue;
        const size_t n = part_points(*t, r.body, r.hull_part).size();
        if (n > most) most = n, pick = &r;
    }
    REQUIRE(pick);
    const RigidBody& body = m.bodies[size_t(pick->body)];
    // The hull about the body's centre of mass, which is the free body's origin.
    std::vector<Eigen::Vector3d> points = part_points(*t, pick->body, pick->hull_part);
    for (Eigen::Vector3d& p : points) p -= body.com;
    auto hull = std::make_shared<const ConvexHull>(convex_hull(points, pick->name));
    INFO(pick->name << ": " << body.mass << " kg, " << points.size() << " mesh vertices, " << hull->vertices.size() << " on the hull");

    auto free = xtest::translate(mbx_test::free_parts("drop", {{body.mass, body.inertia, Vec3::Zero()}}));
    const sim::Model model = sim::build_model(*free->mechanism);
    REQUIRE(model.nv == 6);
    Shape shape;
    shape.kind = ShapeKind::Convex, shape.name = pick->name, shape.body = 1, shape.hull = hull;
    const double k = 1e5;
    ContactSettings cs = mbx_test::corner_contact(body.mass, k);
    ContactWorld world(model, {mbx_test::ground_plane(), shape}, cs);
    sim::Data d(model);
    // Tipped a little so it lands on an edge and must roll onto a face.
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 0).normalized()));
    double lowest = 1e300;
    for (const Eigen::Vector3d& v : hull->vertices) lowest = std::min(lowest, (q * v).z());
    d.q.head<3>() = Eigen::Vector3d(0, 0, 0.02 - lowest);
    d.q[3] = q.w(), d.q[4] = q.x(), d.q[5] = q.y(), d.q[6] = q.z();
    d.v.setZero();
    sim::IntegratorSettings s;
    s.kind = sim::IntegratorKind::Euler, s.step = 1e-4;
    for (int step = 0; step < 40000; ++step) world.step(model, d, s);

    const Eigen::Quaterniond at(d.q[3], d.q[4], d.q[5], d.q[6]);
    lowest = 1e300;
    for (const Eigen::Vector3d& v : hull->vertices) lowest = std::min(lowest, d.q[2] + (at.normalized() * v).z());
    const size_t touching = world.forces().size();
    MESSAGE(pick->name << " at rest on " << touching << " hull vertices, lowest " << lowest * 1e6 << " um below the plane; speed "
                       << d.v.norm());
    CHECK(d.v.norm() < 1e-4);
    REQUIRE(touching >= 3);  // on a face (or an edge and a vertex), not balanced on one vertex
    // Linear springs carry m g together: the deepest vertex sinks between
    // m g / (n k) (all equally deep) and m g / k (it alone carries the load).
    const double sink = -lowest;
    CHECK(sink >= body.mass * g / (double(touching) * k) * (1 - 1e-3));
    CHECK(sink <= body.mass * g / k * (1 + 1e-3));
}

TEST_CASE("default hulls: ergoCub's hulls at its CAD pose, pairs not joined by a joint") {
    auto t = ergocub();
    REQUIRE(t);
    const Mechanism& m = *t->mechanism;
    ContactSpec spec;
    spec.shapes.push_back(hull_default());
    std::vector<LibraryError> errors;
    const ResolvedContact rc = resolve_contact(spec, m, errors);
    REQUIRE(errors.empty());
    const sim::Model model = sim::build_model(m);
    std::vector<Shape> shapes;
    for (const ResolvedCollision& r : rc.shapes) {
        const std::vector<Eigen::Vector3d> points = part_points(*t, r.body, r.hull_part);
        if (points.empty()) continue;
        Shape s;
        s.kind = ShapeKind::Convex, s.name = r.name, s.body = model.body_of_source[size_t(r.body)];
        REQUIRE(s.body > 0);
        s.hull = std::make_shared<const ConvexHull>(convex_hull(points, r.name));
        shapes.push_back(s);
    }
    // Without the reference filter: the overlaps a plain joint filter leaves.
    Scene scene(model, shapes);
    sim::Data d(model);
    sim::update_positions(model, d);
    std::vector<Contact> contacts;
    scene.detect(d, contacts);
    std::set<std::pair<std::string, std::string>> pairs;
    double deepest = 0;
    for (const Contact& c : contacts) {
        pairs.insert({shapes[size_t(c.shape_a)].name, shapes[size_t(c.shape_b)].name});
        deepest = std::max(deepest, c.depth);
    }
    std::string list;
    for (const auto& [a, b] : pairs) list += "\n  " + a + " / " + b;
    MESSAGE("ergoCub at its CAD pose: " << shapes.size() << " hulls, " << scene.stats().candidate_pairs
                                        << " candidate pairs after the joint filter, " << pairs.size()
                                        << " overlapping, deepest " << deepest * 1e3 << " mm:" << list);
    CHECK(!pairs.empty());  // what the filter below is for
    // Independently of FCL: the deepest vertex of the second hull inside the
    // first (both in the world at the CAD pose), for each overlap. (MuJoCo's
    // own narrowphase gives the deepest pair the same 51.93 mm:
    // tests/export/mjcf_contact_test.cpp.)
    auto world_vertices = [&](const Shape& s) {
        std::vector<Eigen::Vector3d> out;
        for (const Eigen::Vector3d& v : s.hull->vertices) out.push_back(d.x_world[size_t(s.body)].apply(v));
        return out;
    };
    for (const Contact& c : contacts) {
        const Shape &a = shapes[size_t(c.shape_a)], &b = shapes[size_t(c.shape_b)];
        const std::vector<Eigen::Vector3d> va = world_vertices(a), vb = world_vertices(b);
        double inside = -1e300;  // largest depth of a vertex of b inside a (min over a's faces of -distance)
        for (const Eigen::Vector3d& x : vb) {
            double depth = 1e300;
            for (int f = 0; f < a.hull->face_count; ++f) {
                const Eigen::Vector3d& p0 = va[size_t(a.hull->faces[size_t(4 * f + 1)])];
                const Eigen::Vector3d n = (va[size_t(a.hull->faces[size_t(4 * f + 2)])] - p0).cross(va[size_t(a.hull->faces[size_t(4 * f + 3)])] - p0).normalized();
                depth = std::min(depth, -n.dot(x - p0));
            }
            inside = std::max(inside, depth);
        }
        // To part them, that vertex must leave the first hull: the
        // penetration depth is at least its depth.
        CHECK(c.depth >= inside - 1e-9);
    }
    // The default hulls skip exactly those pairs: none collides at the CAD
    // pose, and the pairs skipped are the overlapping ones.
    for (Shape& s : shapes) s.skip_if_overlapping_at_reference = true;
    Scene filtered(model, shapes);
    std::vector<Contact> left;
    filtered.detect(d, left);
    CHECK(left.empty());
    std::set<std::pair<std::string, std::string>> skipped;
    for (const auto& [a, b] : filtered.skipped_at_reference()) skipped.insert({shapes[size_t(a)].name, shapes[size_t(b)].name});
    CHECK(skipped == pairs);
}

TEST_CASE("default hulls: shapes overlapping at the reference pose never collide, the others still do") {
    // Three free unit-ish boxes as hulls at the reference pose: A and B
    // overlap there, C is apart. Moved, B into C still collides; A into B
    // does not, whatever the pose.
    const double m = 1, a = 0.1;
    auto t = xtest::translate(mbx_test::free_parts("three", {{m, (m * a * a / 6) * Mat3::Identity(), Vec3(0, 0, 0)},
                                                              {m, (m * a * a / 6) * Mat3::Identity(), Vec3(0.08, 0, 0)},
                                                              {m, (m * a * a / 6) * Mat3::Identity(), Vec3(0.5, 0, 0)}}));
    const sim::Model model = sim::build_model(*t->mechanism);
    REQUIRE(model.body_count() == 4);
    std::vector<Eigen::Vector3d> cube;
    for (int k = 0; k < 8; ++k) cube.emplace_back(k & 1 ? a / 2 : -a / 2, k & 2 ? a / 2 : -a / 2, k & 4 ? a / 2 : -a / 2);
    const auto hull = std::make_shared<const ConvexHull>(convex_hull(cube, "cube"));
    std::vector<Shape> shapes;
    for (int b = 1; b <= 3; ++b) {
        Shape s;
        s.kind = ShapeKind::Convex, s.name = "cube" + std::to_string(b), s.body = b, s.hull = hull;
        s.skip_if_overlapping_at_reference = true;
        shapes.push_back(s);
    }
    Scene scene(model, shapes);
    REQUIRE(scene.skipped_at_reference().size() == 1);
    CHECK(scene.skipped_at_reference()[0] == std::pair<int, int>(0, 1));
    sim::Data d(model);
    // Body 2 moved to overlap C by 1 cm: that pair collides; A and B, now
    // apart, are still skipped (a skip is for good, not for the overlap).
    d.q.segment<3>(model.joints[1].q_index) = Vec3(0.41, 0, 0);
    sim::update_positions(model, d);
    std::vector<Contact> contacts;
    scene.detect(d, contacts);
    REQUIRE(!contacts.empty());
    for (const Contact& c : contacts) CHECK(std::minmax(c.shape_a, c.shape_b) == std::minmax(1, 2));
    // Without the flag on one of them, A and B collide at the reference.
    shapes[0].skip_if_overlapping_at_reference = false;
    Scene plain(model, shapes);
    CHECK(plain.skipped_at_reference().empty());
    sim::Data reference(model);
    sim::update_positions(model, reference);
    contacts.clear();
    plain.detect(reference, contacts);
    CHECK(!contacts.empty());
}
}  // namespace MBX_UNITY_ID
