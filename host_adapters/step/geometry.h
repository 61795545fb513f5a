// STEP's geometric entities read from the Part 21 table into plain structs in
// SI units (metres, radians): placements, the curves an edge follows and the
// surfaces a face lies on. What mbx does not read (an offset surface, a
// curve on a pcurve only) comes back as Unsupported with the entity named,
// so the face that needs it becomes a finding, never a silent hole.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

#include "host_adapters/step/part21.h"
#include "host_adapters/step/units.h"

namespace mbx_step {

// A right-handed frame: origin, x (ref direction), y, z (axis).
struct Placement {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
};

// A B-spline (curve: one row of control points; surface: rows along u, each
// along v), with its knots expanded by their multiplicities. Weights empty
// when not rational.
struct BSpline {
    int degree_u = 0, degree_v = 0;
    int rows = 0, columns = 0;               // control points: rows x columns (a curve: 1 x n)
    std::vector<Eigen::Vector3d> points;     // row-major
    std::vector<double> weights;             // row-major, or empty
    std::vector<double> knots_u, knots_v;    // expanded
    bool closed_u = false, closed_v = false;
    // A surface closed in a direction (the file says so and its two ends
    // meet) is periodic there with its knot range as the period; 0 otherwise.
    double period_u = 0, period_v = 0;
    double extent = 0;  // a surface's control points' bounding-box diagonal
};

struct Curve {
    enum class Kind { Line, Circle, Ellipse, BSpline, Polyline, Unsupported } kind = Kind::Unsupported;
    Placement frame;                   // Circle, Ellipse: centre and plane; Line: origin at its point, x along it
    double radius = 0, radius2 = 0;    // Circle: radius; Ellipse: semi-axes along x and y
    BSpline spline;
    std::vector<Eigen::Vector3d> polyline;
    uint32_t entity = kUnresolved;     // the curve's instance (for Unsupported: the one mbx cannot read)
    std::string type;                  // its STEP type name
};

struct Surface {
    enum class Kind { Plane, Cylinder, Cone, Sphere, Torus, BSpline, Revolution, Extrusion, Unsupported } kind =
        Kind::Unsupported;
    Placement frame;
    double radius = 0;        // Cylinder, Sphere; Cone: radius at the frame's origin; Torus: major radius
    double minor_radius = 0;  // Torus
    double semi_angle = 0;    // Cone, radians
    BSpline spline;
    std::vector<Curve> swept;           // Revolution, Extrusion: the profile (one)
    Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();  // Revolution: a point on the axis
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();       // Revolution: the axis; Extrusion: the sweep vector (length included)
    uint32_t entity = kUnresolved;
    std::string type;
};

// Reads entities of one representation context (its units). Problems (a
// degenerate placement, a malformed B-spline) are reported with the entity.
class GeometryReader {
public:
    GeometryReader(const File& f, const ContextUnits& units, std::vector<Problem>& problems);

    Eigen::Vector3d point(uint32_t cartesian_point);   // metres
    Eigen::Vector3d direction(uint32_t direction);     // unit length
    Placement placement(uint32_t axis2_placement_3d);
    Curve curve(uint32_t entity);
    Surface surface(uint32_t entity);
    // A COORDINATES_LIST's points (AP242's tessellated geometry), in metres.
    std::vector<Eigen::Vector3d> coordinates(uint32_t coordinates_list);

    const File& file() const { return f_; }

private:
    void problem(uint32_t entity, const std::string& message);
    // The attributes of an instance in supertype order: a simple instance's
    // own record, or a complex one's partial records concatenated in the
    // order `order` names them.
    std::vector<const Value*> attributes(uint32_t entity, std::initializer_list<uint32_t> order) const;
    double length(const Value& v) const;
    double number(const Value& v) const;
    bool bspline(uint32_t entity, bool surface, BSpline& out);
    Curve curve_at(uint32_t entity, int depth);

    const File& f_;
    ContextUnits units_;
    std::vector<Problem>& problems_;
    uint32_t types_[40];  // interned ids of the entity types read here (geometry.cpp's enum T)
};

}  // namespace mbx_step
