// Points, derivatives and parameters on STEP curves and surfaces against
// closed forms (a rational B-spline that is exactly a circle arc or a
// cylinder), and edges discretised within their tolerance.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "host_adapters/step/brep.h"
#include "host_adapters/step/evaluate.h"
#include "host_adapters/step/part21.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx_step;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

// A quarter of the unit circle about z as a rational quadratic B-spline.
BSpline quarter_circle() {
    BSpline s;
    s.degree_u = 2;
    s.rows = 1;
    s.columns = 3;
    s.points = {Vector3d(1, 0, 0), Vector3d(1, 1, 0), Vector3d(0, 1, 0)};
    s.weights = {1, std::sqrt(0.5), 1};
    s.knots_u = {0, 0, 0, 1, 1, 1};
    return s;
}

// That quarter circle swept 2 along z: a quarter of a unit cylinder (u around, v along z).
BSpline quarter_cylinder() {
    BSpline s;
    s.degree_u = 2;
    s.degree_v = 1;
    s.rows = 3;
    s.columns = 2;
    const BSpline c = quarter_circle();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 2; ++j) {
            s.points.push_back(c.points[size_t(i)] + Vector3d(0, 0, 2.0 * j));
            s.weights.push_back(c.weights[size_t(i)]);
        }
    s.knots_u = {0, 0, 0, 1, 1, 1};
    s.knots_v = {0, 0, 1, 1};
    return s;
}

Placement frame() {
    Placement p;
    p.origin = Vector3d(0.1, -0.2, 0.3);
    p.z = Vector3d(1, 2, 2).normalized();
    p.x = p.z.unitOrthogonal();
    p.y = p.z.cross(p.x);
    return p;
}

}  // namespace

TEST_CASE("step evaluate: a rational B-spline arc lies on its circle, with the derivative of its points") {
    const BSpline s = quarter_circle();
    Curve c;
    c.kind = Curve::Kind::BSpline;
    c.spline = s;
    for (int k = 0; k <= 50; ++k) {
        const double t = k / 50.0;
        const Vector3d p = spline_point(s, t);
        CHECK(p.norm() == mbx_test::relative(1.0, 1e-14));
        CHECK(std::abs(p.z()) == 0);
        CHECK(curve_parameter(c, p) == mbx_test::within(t, 1e-12, "Newton's method on the arc, to rounding"));
    }
    CHECK((spline_point(s, 0.0) - Vector3d(1, 0, 0)).norm() == 0);
    CHECK((spline_point(s, 1.0) - Vector3d(0, 1, 0)).norm() == 0);
}

TEST_CASE("step evaluate: a rational B-spline surface that is a quarter cylinder, its derivatives against differences") {
    const BSpline s = quarter_cylinder();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Surface surface;
    surface.kind = Surface::Kind::BSpline;
    surface.spline = s;
    for (int k = 0; k < 200; ++k) {
        const double u = unit(rng), v = unit(rng);
        const Vector3d p = spline_point(s, u, v);
        CHECK(p.head<2>().norm() == mbx_test::relative(1.0, 1e-14));
        CHECK(p.z() == mbx_test::within(2 * v, 1e-14, "linear along v, metres to rounding"));
        Vector3d du, dv;
        spline_derivatives(s, u, v, du, dv);
        const double h = 1e-6;
        const Vector3d fu = (spline_point(s, std::min(u + h, 1.0), v) - spline_point(s, std::max(u - h, 0.0), v)) /
                            (std::min(u + h, 1.0) - std::max(u - h, 0.0));
        CHECK((du - fu).norm() == mbx_test::within(0, 1e-6 * du.norm(), "a central difference at h = 1e-6"));
        CHECK((dv - Vector3d(0, 0, 2)).norm() == mbx_test::within(0, 1e-12, "exactly 2 along z"));
        const Vector2d back = surface_parameters(surface, p);
        CHECK((back - Vector2d(u, v)).norm() == mbx_test::within(0, 1e-10, "Newton's method on the patch"));
    }
}

TEST_CASE("step evaluate: every analytic surface gives back the parameters of its own points") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> angle(-3.0, 3.0), height(-0.5, 0.5), latitude(-1.4, 1.4);
    std::vector<Surface> surfaces(5);
    surfaces[0].kind = Surface::Kind::Plane;
    surfaces[1].kind = Surface::Kind::Cylinder, surfaces[1].radius = 0.07;
    surfaces[2].kind = Surface::Kind::Cone, surfaces[2].radius = 0.05, surfaces[2].semi_angle = 0.3;
    surfaces[3].kind = Surface::Kind::Sphere, surfaces[3].radius = 0.2;
    surfaces[4].kind = Surface::Kind::Torus, surfaces[4].radius = 0.3, surfaces[4].minor_radius = 0.05;
    for (Surface& s : surfaces) {
        s.frame = frame();
        CAPTURE(int(s.kind));
        for (int k = 0; k < 100; ++k) {
            Vector2d uv(angle(rng), s.kind == Surface::Kind::Sphere ? latitude(rng) : height(rng));
            if (s.kind == Surface::Kind::Torus) uv.y() = angle(rng);
            // (a cone's points are those of positive radius: beyond its apex is the other nappe)
            if (s.kind == Surface::Kind::Cone) uv.y() = 0.5 * height(rng) + 0.1;
            const Vector3d p = surface_point(s, uv.x(), uv.y());
            const Vector2d back = surface_parameters(s, p, &uv);
            CHECK((back - uv).norm() == mbx_test::within(0, 1e-12, "closed-form inversion, to rounding"));
            // Far from its own period: brought to the one nearest `near`.
            const Vector2d shifted = uv + Vector2d(surface_periods(s).x() * 3, 0);
            CHECK((surface_parameters(s, p, &shifted) - shifted).norm() == mbx_test::within(0, 1e-11, "to rounding"));
        }
    }
    // A cone's radius grows by tan(semi-angle) per unit of height.
    const Surface& cone = surfaces[2];
    const Vector3d p = surface_point(cone, 0.0, 0.1);
    const Vector3d axis_point = cone.frame.origin + 0.1 * cone.frame.z;
    CHECK((p - axis_point).norm() == mbx_test::relative(0.05 + 0.1 * std::tan(0.3), 1e-14));
}

TEST_CASE("step evaluate: a circle and a B-spline arc as edges: endpoints exact, every chord within the tolerance") {
    Brep b;
    b.vertices = {{Vector3d(1, 0, 0), 0}, {Vector3d(0, 1, 0), 1}};
    Edge circle;
    circle.curve.kind = Curve::Kind::Circle;
    circle.curve.radius = 1;
    circle.start = circle.end = 0;
    Edge arc;
    arc.curve.kind = Curve::Kind::BSpline;
    arc.curve.spline = quarter_circle();
    arc.start = 0, arc.end = 1;
    for (const double chord : {1e-3, 1e-5}) {
        CAPTURE(chord);
        const Tolerance tol = Tolerance::absolute(chord, M_PI / 36);
        const std::vector<Vector3d> ring = discretise(b, circle, tol);
        // ceil(2 pi / min(5 deg, 2 acos(1 - chord))) segments, closing on the start.
        const double step = std::min(M_PI / 36, 2 * std::acos(1 - chord));
        CHECK(ring.size() == size_t(std::ceil(2 * M_PI / step)) + 1);
        CHECK((ring.front() - b.vertices[0].point).norm() == 0);
        CHECK((ring.back() - b.vertices[0].point).norm() == 0);
        for (bool same_sense : {true, false}) {
            // Against the curve's sense, the edge starts where the curve ends.
            arc.same_sense = same_sense;
            arc.start = same_sense ? 0 : 1, arc.end = same_sense ? 1 : 0;
            const std::vector<Vector3d> pts = discretise(b, arc, tol);
            CHECK((pts.front() - b.vertices[arc.start].point).norm() == 0);
            CHECK((pts.back() - b.vertices[arc.end].point).norm() == 0);
            CHECK(pts.size() >= 4);
            double worst = 0;
            for (size_t k = 0; k + 1 < pts.size(); ++k) {
                worst = std::max(worst, 1 - (0.5 * (pts[k] + pts[k + 1])).norm());  // the chord's sag
                CHECK(pts[k].norm() == mbx_test::relative(1.0, 1e-13));
            }
            CHECK(worst <= chord);
            // From its start vertex along the arc.
            CHECK((pts[1] - b.vertices[arc.start].point).norm() < 0.1);
        }
    }
}

TEST_CASE("step evaluate: every edge of the real solids discretised, starting and ending on its vertices") {
    for (const std::string& path : {mbx_test::shared_data("step/dfki_double_pendulum/lever_200.STEP"),
                                    mbx_test::shared_data("step/nist_ctc_02/nist_ctc_02_asme1_ap242-1.stp")}) {
        CAPTURE(path);
        const Brep b = read_breps(read_part21_file(path));
        const Tolerance tol = Tolerance::absolute(1e-5, M_PI / 36);
        size_t points = 0;
        for (const Edge& e : b.edges) {
            const std::vector<Vector3d> pts = discretise(b, e, tol);
            REQUIRE(pts.size() >= 2);
            CHECK((pts.front() - b.vertices[e.start].point).norm() == 0);
            CHECK((pts.back() - b.vertices[e.end].point).norm() == 0);
            for (const Vector3d& p : pts) CHECK(p.allFinite());
            // Every point lies on the edge's curve.
            for (size_t k = 1; k + 1 < pts.size(); ++k) {
                const Vector3d on = curve_point(e.curve, curve_parameter(e.curve, pts[k]));
                CHECK((on - pts[k]).norm() == mbx_test::within(0, 1e-9, "a sample of the curve itself, metres"));
            }
            points += pts.size();
        }
        MESSAGE(path << ": " << b.edges.size() << " edges, " << points << " points at 0.01 mm / 5 deg");
    }
}

}  // namespace MBX_UNITY_ID
