// Points on STEP curves and surfaces, parameters of points on them, and each
// edge turned into a polyline within a chord and an angle tolerance: what the
// tessellation meshes faces from. Parametrisations are ISO 10303-42's (a
// circle from its frame's x axis, a cone by the height along its axis, a
// torus's minor angle from the plane of its major circle).
#pragma once

#include <Eigen/Core>

#include <utility>
#include <vector>

#include "host_adapters/step/brep.h"
#include "host_adapters/step/geometry.h"

namespace mbx_step {

constexpr double kTwoPi = 2 * 3.14159265358979323846;

// The density of a mesh: no chord farther than `chord` from its curve or
// surface, no segment of an edge turning more than `angle`. A chord of 0
// means `relative_chord` of each solid's size (its bounding box's diagonal),
// so that a screw and an engine block get the same relative accuracy. The
// defaults give volumes within 1e-4 of the exact ones on the real parts of
// the tests.
struct Tolerance {
    double chord = 0;               // metres; 0: relative to the solid's size
    double relative_chord = 1e-5;   // of the solid's size, when chord is 0
    double angle = kTwoPi / 360;    // radians (1 degree)
    // What refining one face may add (memory stays bounded on a tolerance
    // far finer than a face needs); a face that would need more is meshed
    // coarser, with a finding.
    size_t face_triangle_budget = 4'000'000;

    // A fixed chord in metres and an angle in radians.
    static Tolerance absolute(double chord_m, double angle_rad) {
        Tolerance t;
        t.chord = chord_m;
        t.angle = angle_rad;
        return t;
    }
};

// B-splines (rational ones through their weights), at parameter u (and v).
Eigen::Vector3d spline_point(const BSpline& s, double u);
Eigen::Vector3d spline_point(const BSpline& s, double u, double v);
// The knot range of a surface along u (or v).
std::pair<double, double> spline_range(const BSpline& s, bool v = false);
// Sets a surface's extent, and its periods where the file calls it closed
// and its two ends meet (to 1e-7 of its extent): then it is evaluated with u
// (v) taken modulo its knot range, so that a face wrapping round it unrolls
// as on a cylinder.
void prepare_surface(BSpline& s);
// The surface's first derivatives along u and v at (u, v).
void spline_derivatives(const BSpline& s, double u, double v, Eigen::Vector3d& du, Eigen::Vector3d& dv);

// A curve's point at parameter t (a B-spline's knot parameter, a circle's
// angle, a line's length), and the parameter of the point of the curve
// nearest to q (for a B-spline: sampled, then refined by Newton's method).
Eigen::Vector3d curve_point(const Curve& c, double t);
double curve_parameter(const Curve& c, const Eigen::Vector3d& q);
// The period of a closed curve's parameter (2 pi for circles and ellipses), 0 otherwise.
double curve_period(const Curve& c);

// The edge as points from its start vertex to its end vertex (both exactly
// the vertices' points), dense enough for the tolerance. A closed edge (start
// and end the same vertex) goes once around its curve.
std::vector<Eigen::Vector3d> discretise(const Brep& b, const Edge& e, const Tolerance& tolerance);

// A surface's point at (u, v), and the (u, v) of the point nearest to q; u
// (and v, on a torus) periodic with period 2 pi on the surfaces of
// revolution, the result taken nearest to `near` when given.
Eigen::Vector3d surface_point(const Surface& s, double u, double v);
Eigen::Vector2d surface_parameters(const Surface& s, const Eigen::Vector3d& q, const Eigen::Vector2d* near = nullptr);
// The (u, v) of a point of the surface near q found from `start` without a
// global search (a B-spline's Newton steps, until a step moves less than
// `precision` metres; the others' closed form): its distance from q bounds
// q's distance from the surface from above.
Eigen::Vector2d surface_foot(const Surface& s, const Eigen::Vector3d& q, const Eigen::Vector2d& start, double precision);
// The periods of u and v (0: not periodic).
Eigen::Vector2d surface_periods(const Surface& s);

}  // namespace mbx_step
