// STEP files of solids whose volume is known exactly, written by the tests
// (a box, a tube, a sphere, a torus, a cone frustum, and B-spline surfaces
// that are exactly a plane and a cylinder), in any length unit: the Part 21
// text a CAD exporter would write for them, B-rep topology and all.
// Coordinates are given in metres and written in the chosen unit.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mbx_test {

// The length unit a file is written in.
enum class StepUnit { Millimetre, Metre, Inch, OnshapeMetre };

class StepSolidWriter {
public:
    explicit StepSolidWriter(StepUnit unit = StepUnit::Millimetre, bool degrees = false)
        : unit_(unit), degrees_(degrees) {}

    double metres_per_unit() const {
        switch (unit_) {
            case StepUnit::Millimetre: return 1e-3;
            case StepUnit::Inch: return 0.0254;
            default: return 1.0;
        }
    }

    // A rectangular box from `lo` to `hi`; with `spline_top` its top face lies
    // on a bicubic B-spline surface that is exactly its plane.
    void box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, bool spline_top = false) {
        std::vector<int> v(8);
        for (int k = 0; k < 8; ++k)
            v[size_t(k)] = vertex(Eigen::Vector3d(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z()));
        // Each face's corners counter-clockwise seen from outside, and its outward normal.
        const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        const Eigen::Vector3d normals[6] = {-Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitY(),
                                            Eigen::Vector3d::UnitY(),  -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitX()};
        std::vector<int> face_ids;
        for (int f = 0; f < 6; ++f) {
            std::vector<std::pair<int, bool>> loop;
            for (int k = 0; k < 4; ++k) loop.push_back(line_edge(v[size_t(faces[f][k])], v[size_t(faces[f][(k + 1) % 4])]));
            const Eigen::Vector3d centre = 0.5 * (lo + hi);
            Eigen::Vector3d origin = centre;
            for (int d = 0; d < 3; ++d)
                if (normals[f][d] != 0) origin[d] = normals[f][d] > 0 ? hi[d] : lo[d];
            int surface;
            if (spline_top && f == 1)
                surface = spline_plane(lo, hi, hi.z());
            else
                surface = add("PLANE('',#" + std::to_string(axis(origin, normals[f], any_perpendicular(normals[f]))) + ")");
            face_ids.push_back(face({{loop, true}}, surface, true));
        }
        solid(face_ids);
    }

    // A tube along z: outer radius R, a coaxial hole of radius r, from z0 to z1.
    // Its round faces are bounded by whole circles (no seam edge).
    void tube(double R, double r, double z0, double z1) {
        const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
        const int ob = circle_edge(R, z0), ot = circle_edge(R, z1), ib = circle_edge(r, z0), it = circle_edge(r, z1);
        const int bottom = add("PLANE('',#" + std::to_string(axis({0, 0, z0}, -z, Eigen::Vector3d::UnitX())) + ")");
        const int top = add("PLANE('',#" + std::to_string(axis({0, 0, z1}, z, Eigen::Vector3d::UnitX())) + ")");
        const int outer = add("CYLINDRICAL_SURFACE('',#" + std::to_string(axis({0, 0, 0}, z, Eigen::Vector3d::UnitX())) +
                              "," + length(R) + ")");
        const int inner = add("CYLINDRICAL_SURFACE('',#" + std::to_string(axis({0, 0, 0}, z, Eigen::Vector3d::UnitX())) +
                              "," + length(r) + ")");
        // Circles run counter-clockwise about +z: the bottom face (normal -z)
        // has its outer circle reversed, its hole forward; the top the other way.
        std::vector<int> faces;
        faces.push_back(face({{{{ob, false}}, true}, {{{ib, true}}, false}}, bottom, true));
        faces.push_back(face({{{{ot, true}}, true}, {{{it, false}}, false}}, top, true));
        // The outer mantle (normal out): bottom circle forward, top circle back.
        faces.push_back(face({{{{ob, true}}, true}, {{{ot, false}}, false}}, outer, true));
        // The hole's mantle faces the axis: against its surface's normal.
        faces.push_back(face({{{{ib, false}}, true}, {{{it, true}}, false}}, inner, false));
        solid(faces);
    }

    // A sphere of radius R about `centre`, as two hemispheres meeting at the equator.
    void sphere(double R, const Eigen::Vector3d& centre) {
        const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
        const int start = vertex(centre + R * Eigen::Vector3d::UnitX());
        const int equator = add("EDGE_CURVE('',#" + std::to_string(start) + ",#" + std::to_string(start) + ",#" +
                                std::to_string(add("CIRCLE('',#" + std::to_string(axis(centre, z, Eigen::Vector3d::UnitX())) +
                                                   "," + length(R) + ")")) + ",.T.)");
        const int surface = add("SPHERICAL_SURFACE('',#" + std::to_string(axis(centre, z, Eigen::Vector3d::UnitX())) + "," +
                                length(R) + ")");
        solid({face({{{{equator, true}}, true}}, surface, true), face({{{{equator, false}}, true}}, surface, true)});
    }

    // A torus about z: major radius R, minor r, as the halves above and below
    // its middle plane (each bounded by the outer and the inner equator).
    void torus(double R, double r) {
        const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
        const int outer = circle_edge(R + r, 0), inner = circle_edge(R - r, 0);
        const int surface = add("TOROIDAL_SURFACE('',#" + std::to_string(axis({0, 0, 0}, z, Eigen::Vector3d::UnitX())) +
                                "," + length(R) + "," + length(r) + ")");
        // Seen from outside, the upper half has the outer equator running
        // clockwise about +z... viewed from above the face lies inside it:
        // outer circle counter-clockwise, inner circle clockwise.
        solid({face({{{{outer, true}}, true}, {{{inner, false}}, false}}, surface, true),
               face({{{{outer, false}}, true}, {{{inner, true}}, false}}, surface, true)});
    }

    // A cone frustum along z: radius r0 at z = 0, r1 at z = h (r0 > r1).
    // The cone's semi-angle is written in the file's angle unit.
    void frustum(double r0, double r1, double h) {
        const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
        const int bottom_edge = circle_edge(r0, 0), top_edge = circle_edge(r1, h);
        const double semi = std::atan2(r0 - r1, h);  // radius shrinks upwards: axis pointing down the cone
        // The cone's axis points from the wide end up (radius grows along it
        // when the angle is positive): here along -z from the top circle.
        const int cone = add("CONICAL_SURFACE('',#" + std::to_string(axis({0, 0, h}, -z, Eigen::Vector3d::UnitX())) + "," +
                             length(r1) + "," + angle(semi) + ")");
        const int bottom = add("PLANE('',#" + std::to_string(axis({0, 0, 0}, -z, Eigen::Vector3d::UnitX())) + ")");
        const int top = add("PLANE('',#" + std::to_string(axis({0, 0, h}, z, Eigen::Vector3d::UnitX())) + ")");
        solid({face({{{{bottom_edge, false}}, true}}, bottom, true), face({{{{top_edge, true}}, true}}, top, true),
               face({{{{bottom_edge, true}}, true}, {{{top_edge, false}}, false}}, cone, true)});
    }

    // A cylinder along z whose mantle is a rational B-spline surface (a
    // quadratic NURBS circle swept linearly): exactly the cylinder.
    void spline_cylinder(double R, double h) {
        const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
        const int b = circle_edge(R, 0), t = circle_edge(R, h);
        const int bottom = add("PLANE('',#" + std::to_string(axis({0, 0, 0}, -z, Eigen::Vector3d::UnitX())) + ")");
        const int top = add("PLANE('',#" + std::to_string(axis({0, 0, h}, z, Eigen::Vector3d::UnitX())) + ")");
        // Nine control points round the circle (corners weighted 1/sqrt 2), two rows along z.
        const double w = std::sqrt(0.5);
        const double xs[9] = {1, 1, 0, -1, -1, -1, 0, 1, 1}, ys[9] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
        std::string rows, weights;
        for (int i = 0; i < 9; ++i) {
            rows += std::string(i ? "," : "") + "(#" + std::to_string(point(Eigen::Vector3d(R * xs[i], R * ys[i], 0))) +
                    ",#" + std::to_string(point(Eigen::Vector3d(R * xs[i], R * ys[i], h))) + ")";
            const std::string wi = i % 2 ? number(w) : "1.";
            weights += std::string(i ? "," : "") + "(" + wi + "," + wi + ")";
        }
        const int mantle = add("(BOUNDED_SURFACE()B_SPLINE_SURFACE(2,1,(" + rows +
                               "),.UNSPECIFIED.,.T.,.F.,.F.)B_SPLINE_SURFACE_WITH_KNOTS((3,2,2,2,3),(2,2),"
                               "(0.,0.25,0.5,0.75,1.),(0.,1.),.UNSPECIFIED.)GEOMETRIC_REPRESENTATION_ITEM()"
                               "RATIONAL_B_SPLINE_SURFACE((" + weights + "))REPRESENTATION_ITEM('')SURFACE())");
        solid({face({{{{b, false}}, true}}, bottom, true), face({{{{t, true}}, true}}, top, true),
               face({{{{b, true}}, true}, {{{t, false}}, false}}, mantle, true)});
    }

    // A ring about z swept by a SURFACE_OF_REVOLUTION of a circle (radius r,
    // centred R from the axis): a torus, as the halves above and below.
    void revolved_ring(double R, double r) {
        const int outer = circle_edge(R + r, 0), inner = circle_edge(R - r, 0);
        // The profile in the xz plane, running from the outside up over the top.
        const int profile = add("CIRCLE('',#" + std::to_string(axis({R, 0, 0}, -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX())) +
                                "," + length(r) + ")");
        const int about = add("AXIS1_PLACEMENT('',#" + std::to_string(point({0, 0, 0})) + ",#" +
                              std::to_string(direction(Eigen::Vector3d::UnitZ())) + ")");
        const int surface = add("SURFACE_OF_REVOLUTION('',#" + std::to_string(profile) + ",#" + std::to_string(about) + ")");
        solid({face({{{{outer, true}}, true}, {{{inner, false}}, false}}, surface, true),
               face({{{{outer, false}}, true}, {{{inner, true}}, false}}, surface, true)});
    }

    // A cylinder along z whose mantle is a SURFACE_OF_LINEAR_EXTRUSION of its base circle.
    void extruded_cylinder(double R, double h) {
        const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
        const int b = circle_edge(R, 0), t = circle_edge(R, h);
        const int base = add("CIRCLE('',#" + std::to_string(axis({0, 0, 0}, z, Eigen::Vector3d::UnitX())) + "," + length(R) + ")");
        const int sweep = add("VECTOR('',#" + std::to_string(direction(z)) + "," + length(h) + ")");
        const int mantle = add("SURFACE_OF_LINEAR_EXTRUSION('',#" + std::to_string(base) + ",#" + std::to_string(sweep) + ")");
        const int bottom = add("PLANE('',#" + std::to_string(axis({0, 0, 0}, -z, Eigen::Vector3d::UnitX())) + ")");
        const int top = add("PLANE('',#" + std::to_string(axis({0, 0, h}, z, Eigen::Vector3d::UnitX())) + ")");
        solid({face({{{{b, false}}, true}}, bottom, true), face({{{{t, true}}, true}}, top, true),
               face({{{{b, true}}, true}, {{{t, false}}, false}}, mantle, true)});
    }

    // The whole file: the solids written so far in one shape representation.
    std::string file() const {
        std::string units;
        int length_unit = 0;
        std::string extra;
        int n = next_;
        auto entity = [&](const std::string& text) {
            extra += "#" + std::to_string(n) + "=" + text + ";\n";
            return n++;
        };
        const int mm = entity("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
        const int metre = entity("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT($,.METRE.))");
        const int exponents = entity("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)");
        switch (unit_) {
            case StepUnit::Millimetre: length_unit = mm; break;
            case StepUnit::Metre: length_unit = metre; break;
            case StepUnit::Inch: {
                const int m = entity("LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#" + std::to_string(mm) + ")");
                length_unit = entity("(CONVERSION_BASED_UNIT('INCH',#" + std::to_string(m) + ")LENGTH_UNIT()NAMED_UNIT(#" +
                                     std::to_string(exponents) + "))");
                break;
            }
            case StepUnit::OnshapeMetre: {
                const int m = entity("LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.),#" + std::to_string(metre) + ")");
                length_unit = entity("(CONVERSION_BASED_UNIT('METRE',#" + std::to_string(m) + ")LENGTH_UNIT()NAMED_UNIT(#" +
                                     std::to_string(exponents) + "))");
                break;
            }
        }
        const int radian = entity("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))");
        int angle_unit = radian;
        if (degrees_) {
            const int angle_exponents = entity("DIMENSIONAL_EXPONENTS(0.,0.,0.,0.,0.,0.,0.)");
            const int m = entity("PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(0.0174532925199433),#" +
                                 std::to_string(radian) + ")");
            angle_unit = entity("(CONVERSION_BASED_UNIT('DEGREE',#" + std::to_string(m) + ")NAMED_UNIT(#" +
                                std::to_string(angle_exponents) + ")PLANE_ANGLE_UNIT())");
        }
        const int steradian = entity("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())");
        const int context = entity("(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#" +
                                   std::to_string(length_unit) + ",#" + std::to_string(angle_unit) + ",#" +
                                   std::to_string(steradian) + "))REPRESENTATION_CONTEXT('',''))");
        std::string items;
        for (int s : solids_) items += (items.empty() ? "#" : ",#") + std::to_string(s);
        entity("ADVANCED_BREP_SHAPE_REPRESENTATION('',(" + items + "),#" + std::to_string(context) + ")");
        return "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('','',(''),(''),'','','');\n"
               "FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n" +
               data_ + extra + "ENDSEC;\nEND-ISO-10303-21;\n";
    }

private:
    int add(const std::string& text) {
        data_ += "#" + std::to_string(next_) + "=" + text + ";\n";
        return next_++;
    }

    static std::string number(double x) {
        char buffer[40];
        std::snprintf(buffer, sizeof buffer, "%.17G", x);
        std::string s = buffer;
        if (s.find('.') == std::string::npos && s.find('E') == std::string::npos) s += ".";
        if (s.find('.') == std::string::npos) s.insert(s.find('E'), ".");
        return s;
    }
    std::string length(double metres) const { return number(metres / metres_per_unit()); }
    std::string angle(double radians) const { return number(degrees_ ? radians * 180 / M_PI : radians); }

    int point(const Eigen::Vector3d& p) {
        return add("CARTESIAN_POINT('',(" + length(p.x()) + "," + length(p.y()) + "," + length(p.z()) + "))");
    }
    int direction(const Eigen::Vector3d& d) {
        return add("DIRECTION('',(" + number(d.x()) + "," + number(d.y()) + "," + number(d.z()) + "))");
    }
    int axis(const Eigen::Vector3d& origin, const Eigen::Vector3d& z, const Eigen::Vector3d& x) {
        return add("AXIS2_PLACEMENT_3D('',#" + std::to_string(point(origin)) + ",#" + std::to_string(direction(z)) + ",#" +
                   std::to_string(direction(x)) + ")");
    }
    static Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& n) {
        return std::abs(n.x()) > 0.5 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
    }

    int vertex(const Eigen::Vector3d& p) {
        const int v = add("VERTEX_POINT('',#" + std::to_string(point(p)) + ")");
        where_.resize(size_t(next_));
        where_[size_t(v)] = p;
        return v;
    }

    // The line edge between two vertices (made once), and whether a loop
    // from a to b runs along it.
    std::pair<int, bool> line_edge(int a, int b) {
        for (const auto& [edge, ends] : lines_) {
            if (ends.first == a && ends.second == b) return {edge, true};
            if (ends.first == b && ends.second == a) return {edge, false};
        }
        const Eigen::Vector3d pa = where_[size_t(a)], pb = where_[size_t(b)];
        const int dir = direction((pb - pa).normalized());
        const int vec = add("VECTOR('',#" + std::to_string(dir) + "," + length((pb - pa).norm()) + ")");
        const int line = add("LINE('',#" + std::to_string(point(pa)) + ",#" + std::to_string(vec) + ")");
        const int edge = add("EDGE_CURVE('',#" + std::to_string(a) + ",#" + std::to_string(b) + ",#" + std::to_string(line) + ",.T.)");
        lines_.push_back({edge, {a, b}});
        return {edge, true};
    }

    // A whole circle of radius r about the z axis at height z, counter-clockwise about +z.
    int circle_edge(double r, double z) {
        const int v = vertex(Eigen::Vector3d(r, 0, z));
        const int circle = add("CIRCLE('',#" + std::to_string(axis({0, 0, z}, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX())) +
                               "," + length(r) + ")");
        return add("EDGE_CURVE('',#" + std::to_string(v) + ",#" + std::to_string(v) + ",#" + std::to_string(circle) + ",.T.)");
    }

    // A face from bounds: each a loop of (edge, forward) and whether it is the outer bound.
    int face(const std::vector<std::pair<std::vector<std::pair<int, bool>>, bool>>& bounds, int surface, bool same_sense) {
        std::string list;
        for (const auto& [edges, outer] : bounds) {
            std::string oriented;
            for (const auto& [edge, forward] : edges)
                oriented += (oriented.empty() ? "#" : ",#") +
                            std::to_string(add("ORIENTED_EDGE('',*,*,#" + std::to_string(edge) + (forward ? ",.T.)" : ",.F.)")));
            const int loop = add("EDGE_LOOP('',(" + oriented + "))");
            const int bound = add(std::string(outer ? "FACE_OUTER_BOUND" : "FACE_BOUND") + "('',#" + std::to_string(loop) + ",.T.)");
            list += (list.empty() ? "#" : ",#") + std::to_string(bound);
        }
        return add("ADVANCED_FACE('',(" + list + "),#" + std::to_string(surface) + (same_sense ? ",.T.)" : ",.F.)"));
    }

    void solid(const std::vector<int>& faces) {
        std::string list;
        for (int f : faces) list += (list.empty() ? "#" : ",#") + std::to_string(f);
        const int shell = add("CLOSED_SHELL('',(" + list + "))");
        solids_.push_back(add("MANIFOLD_SOLID_BREP('',#" + std::to_string(shell) + ")"));
    }

    // A bicubic B-spline surface over the box's top, flat at height z.
    int spline_plane(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double z) {
        std::string rows;
        for (int i = 0; i < 4; ++i) {
            rows += std::string(i ? "," : "") + "(";
            for (int j = 0; j < 4; ++j) {
                // Unevenly spaced along each row, so the parametrisation is not the plane's own.
                const double s = std::pow(i / 3.0, 1.3), t = std::pow(j / 3.0, 0.8);
                const double x = lo.x() - 0.1 * (hi.x() - lo.x()) + 1.2 * (hi.x() - lo.x()) * s;
                const double y = lo.y() - 0.1 * (hi.y() - lo.y()) + 1.2 * (hi.y() - lo.y()) * t;
                rows += std::string(j ? "," : "") + "#" + std::to_string(point(Eigen::Vector3d(x, y, z)));
            }
            rows += ")";
        }
        return add("B_SPLINE_SURFACE_WITH_KNOTS('',3,3,(" + rows +
                   "),.UNSPECIFIED.,.F.,.F.,.F.,(4,4),(4,4),(0.,1.),(0.,1.),.UNSPECIFIED.)");
    }

    StepUnit unit_;
    bool degrees_;
    std::string data_;
    int next_ = 1;
    std::vector<Eigen::Vector3d> where_;
    std::vector<std::pair<int, std::pair<int, int>>> lines_;
    std::vector<int> solids_;
};

}  // namespace mbx_test
