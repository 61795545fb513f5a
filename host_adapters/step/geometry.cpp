#include "host_adapters/step/geometry.h"

#include "host_adapters/step/evaluate.h"  // (a closed B-spline surface is checked by evaluating it)

#include <cmath>

namespace mbx_step {

namespace {

enum T {
    kCartesianPoint,
    kDirection,
    kVector,
    kAxis1,
    kAxis2,
    kLine,
    kCircle,
    kEllipse,
    kPolyline,
    kTrimmedCurve,
    kSurfaceCurve,
    kSeamCurve,
    kBSplineCurve,
    kBSplineCurveWithKnots,
    kRationalBSplineCurve,
    kPlane,
    kCylinder,
    kCone,
    kSphere,
    kTorus,
    kDegenerateTorus,
    kRevolution,
    kExtrusion,
    kBSplineSurface,
    kBSplineSurfaceWithKnots,
    kRationalBSplineSurface,
    kRepresentationItem,
    kGeometricRepresentationItem,
    kTypeCount
};

const char* const kTypeNames[kTypeCount] = {
    "CARTESIAN_POINT",  "DIRECTION",     "VECTOR",           "AXIS1_PLACEMENT",
    "AXIS2_PLACEMENT_3D", "LINE",        "CIRCLE",           "ELLIPSE",
    "POLYLINE",         "TRIMMED_CURVE", "SURFACE_CURVE",    "SEAM_CURVE",
    "B_SPLINE_CURVE",   "B_SPLINE_CURVE_WITH_KNOTS", "RATIONAL_B_SPLINE_CURVE",
    "PLANE",            "CYLINDRICAL_SURFACE", "CONICAL_SURFACE", "SPHERICAL_SURFACE",
    "TOROIDAL_SURFACE", "DEGENERATE_TOROIDAL_SURFACE", "SURFACE_OF_REVOLUTION", "SURFACE_OF_LINEAR_EXTRUSION",
    "B_SPLINE_SURFACE", "B_SPLINE_SURFACE_WITH_KNOTS", "RATIONAL_B_SPLINE_SURFACE",
    "REPRESENTATION_ITEM", "GEOMETRIC_REPRESENTATION_ITEM",
};

static_assert(kTypeCount <= 40, "GeometryReader::types_ holds 40 ids");

}  // namespace

GeometryReader::GeometryReader(const File& f, const ContextUnits& units, std::vector<Problem>& problems)
    : f_(f), units_(units), problems_(problems) {
    for (int k = 0; k < kTypeCount; ++k) types_[k] = f.type_id(kTypeNames[k]);
}

void GeometryReader::problem(uint32_t entity, const std::string& message) {
    if (entity < f_.instances.size())
        problems_.push_back({int(f_.instances[entity].line), f_.instances[entity].id, message});
    else
        problems_.push_back({0, 0, message});
}

std::vector<const Value*> GeometryReader::attributes(uint32_t entity, std::initializer_list<uint32_t> order) const {
    std::vector<const Value*> out;
    if (entity >= f_.instances.size()) return out;
    const Instance& in = f_.instances[entity];
    if (in.record_count == 1) {
        const Record& r = f_.first_record(in);
        for (uint32_t k = 0; k < r.count; ++k) out.push_back(&f_.attribute(r, k));
        return out;
    }
    for (uint32_t type : order)
        if (const Record* r = f_.record(in, type))
            for (uint32_t k = 0; k < r->count; ++k) out.push_back(&f_.attribute(*r, k));
    return out;
}

double GeometryReader::number(const Value& v) const {
    const Value& x = v.kind == Kind::Typed ? f_.values[v.a] : v;
    if (x.kind == Kind::Real) return x.real;
    if (x.kind == Kind::Integer) return double(x.integer);
    return NAN;
}

double GeometryReader::length(const Value& v) const { return number(v) * units_.length; }

namespace {

bool is(const File& f, uint32_t entity, uint32_t type) {
    return entity < f.instances.size() && f.record(entity, type) != nullptr;
}

uint32_t ref(const Value* v) { return v && v->kind == Kind::Reference ? v->a : kUnresolved; }

}  // namespace

Eigen::Vector3d GeometryReader::point(uint32_t entity) {
    if (!is(f_, entity, types_[kCartesianPoint])) {
        problem(entity, "expected a CARTESIAN_POINT");
        return Eigen::Vector3d::Constant(NAN);
    }
    const Record& r = *f_.record(entity, types_[kCartesianPoint]);
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    if (r.count < 2 || f_.attribute(r, 1).kind != Kind::List) {
        problem(entity, "a CARTESIAN_POINT without coordinates");
        return Eigen::Vector3d::Constant(NAN);
    }
    const Value& list = f_.attribute(r, 1);
    for (uint32_t k = 0; k < 3 && k < uint32_t(list.count); ++k) p[k] = length(f_.element(list, k));
    if (!p.allFinite()) problem(entity, "a CARTESIAN_POINT with a coordinate that is not a number");
    return p;
}

std::vector<Eigen::Vector3d> GeometryReader::coordinates(uint32_t entity) {
    std::vector<Eigen::Vector3d> out;
    const Record* r = entity < f_.instances.size() ? f_.record(entity, f_.type_id("COORDINATES_LIST")) : nullptr;
    if (!r || r->count < 3 || f_.attribute(*r, 2).kind != Kind::List) {
        problem(entity, "expected a COORDINATES_LIST");
        return out;
    }
    const Value& list = f_.attribute(*r, 2);
    out.reserve(size_t(list.count));
    for (uint32_t k = 0; k < uint32_t(list.count); ++k) {
        const Value& xyz = f_.element(list, k);
        Eigen::Vector3d p = Eigen::Vector3d::Constant(NAN);
        if (xyz.kind == Kind::List && xyz.count == 3)
            for (uint32_t d = 0; d < 3; ++d) p[d] = length(f_.element(xyz, d));
        out.push_back(p);
    }
    for (const Eigen::Vector3d& p : out)
        if (!p.allFinite()) {
            problem(entity, "a COORDINATES_LIST with a point that is not three numbers");
            break;
        }
    return out;
}

Eigen::Vector3d GeometryReader::direction(uint32_t entity) {
    if (!is(f_, entity, types_[kDirection])) {
        problem(entity, "expected a DIRECTION");
        return Eigen::Vector3d::Constant(NAN);
    }
    const Record& r = *f_.record(entity, types_[kDirection]);
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    if (r.count >= 2 && f_.attribute(r, 1).kind == Kind::List) {
        const Value& list = f_.attribute(r, 1);
        for (uint32_t k = 0; k < 3 && k < uint32_t(list.count); ++k) d[k] = number(f_.element(list, k));
    }
    const double n = d.norm();
    if (!(n > 1e-300) || !std::isfinite(n)) {
        problem(entity, "a DIRECTION of zero length");
        return Eigen::Vector3d::Constant(NAN);
    }
    return d / n;
}

Placement GeometryReader::placement(uint32_t entity) {
    Placement p;
    if (!is(f_, entity, types_[kAxis2])) {
        problem(entity, "expected an AXIS2_PLACEMENT_3D");
        p.origin = Eigen::Vector3d::Constant(NAN);
        return p;
    }
    const Record& r = *f_.record(entity, types_[kAxis2]);
    if (r.count < 4) {
        problem(entity, "an AXIS2_PLACEMENT_3D with too few attributes");
        p.origin = Eigen::Vector3d::Constant(NAN);
        return p;
    }
    p.origin = point(ref(&f_.attribute(r, 1)));
    if (f_.attribute(r, 2).kind == Kind::Reference) p.z = direction(f_.attribute(r, 2).a);
    Eigen::Vector3d x = Eigen::Vector3d::UnitX();
    if (f_.attribute(r, 3).kind == Kind::Reference) {
        x = direction(f_.attribute(r, 3).a);
    } else if (std::abs(p.z.x()) > 0.9) {
        x = Eigen::Vector3d::UnitY();  // the default ref direction would be along the axis
    }
    // The ref direction projected square to the axis (ISO 10303-42's rule).
    x -= x.dot(p.z) * p.z;
    if (!(x.norm() > 1e-12)) {
        problem(entity, "an AXIS2_PLACEMENT_3D whose ref direction lies along its axis");
        x = p.z.unitOrthogonal();
    }
    p.x = x.normalized();
    p.y = p.z.cross(p.x);
    return p;
}

bool GeometryReader::bspline(uint32_t entity, bool surface, BSpline& s) {
    // Supertype order: REPRESENTATION_ITEM(name), B_SPLINE_*, *_WITH_KNOTS, RATIONAL_*.
    const uint32_t base = types_[surface ? kBSplineSurface : kBSplineCurve];
    const uint32_t knots = types_[surface ? kBSplineSurfaceWithKnots : kBSplineCurveWithKnots];
    const uint32_t rational = types_[surface ? kRationalBSplineSurface : kRationalBSplineCurve];
    const std::vector<const Value*> a =
        attributes(entity, {types_[kRepresentationItem], base, knots, rational});
    const bool is_rational = is(f_, entity, rational);
    // Curve: name, degree, points, form, closed, self, mults, knots, spec [, weights]
    // Surface: name, du, dv, points, form, uclosed, vclosed, self, umults, vmults, uknots, vknots, spec [, weights]
    const size_t expected = surface ? 13 : 9;
    if (a.size() < expected + (is_rational ? 1 : 0)) {
        problem(entity, std::string("a B-spline ") + (surface ? "surface" : "curve") + " with too few attributes");
        return false;
    }
    auto integer = [](const Value* v) { return v->kind == Kind::Integer ? int(v->integer) : -1; };
    auto expand = [&](const Value* mults, const Value* values, std::vector<double>& out) {
        if (mults->kind != Kind::List || values->kind != Kind::List || mults->count != values->count) return false;
        for (uint32_t k = 0; k < uint32_t(values->count); ++k) {
            const int m = integer(&f_.element(*mults, k));
            const double u = number(f_.element(*values, k));
            if (m < 1 || m > 64 || !std::isfinite(u) || (!out.empty() && u < out.back())) return false;
            out.insert(out.end(), size_t(m), u);
        }
        return true;
    };
    size_t i = 1;
    s.degree_u = integer(a[i++]);
    if (surface) s.degree_v = integer(a[i++]);
    const Value* pts = a[i++];
    ++i;  // form
    if (surface) {
        s.closed_u = a[i]->kind == Kind::Enumeration && f_.text(*a[i]) == "T";
        s.closed_v = a[i + 1]->kind == Kind::Enumeration && f_.text(*a[i + 1]) == "T";
        i += 2;
    } else {
        s.closed_u = a[i]->kind == Kind::Enumeration && f_.text(*a[i]) == "T";
        ++i;
    }
    ++i;  // self intersect
    bool ok = s.degree_u >= 1 && s.degree_u <= 32 && (!surface || (s.degree_v >= 1 && s.degree_v <= 32));
    if (ok && pts->kind == Kind::List) {
        if (surface) {
            s.rows = int(pts->count);
            for (uint32_t r = 0; ok && r < uint32_t(pts->count); ++r) {
                const Value& row = f_.element(*pts, r);
                if (row.kind != Kind::List || (r > 0 && int(row.count) != s.columns)) ok = false;
                s.columns = int(row.count);
                for (uint32_t c = 0; ok && c < uint32_t(row.count); ++c) s.points.push_back(point(ref(&f_.element(row, c))));
            }
        } else {
            s.rows = 1;
            s.columns = int(pts->count);
            for (uint32_t c = 0; c < uint32_t(pts->count); ++c) s.points.push_back(point(ref(&f_.element(*pts, c))));
        }
    } else {
        ok = false;
    }
    if (ok) {
        ok = expand(a[i], a[surface ? i + 2 : i + 1], s.knots_u);
        if (surface) ok = ok && expand(a[i + 1], a[i + 3], s.knots_v);
        i += surface ? 5 : 3;  // past mults, knots and the spec
    }
    // A valid B-spline has as many knots as points plus degree plus one, per direction.
    if (ok) ok = int(s.knots_u.size()) == (surface ? s.rows : s.columns) + s.degree_u + 1;
    if (ok && surface) ok = int(s.knots_v.size()) == s.columns + s.degree_v + 1;
    if (ok && is_rational) {
        const Value* w = a[i];
        if (surface) {
            ok = w->kind == Kind::List && int(w->count) == s.rows;
            for (uint32_t r = 0; ok && r < uint32_t(w->count); ++r) {
                const Value& row = f_.element(*w, r);
                ok = row.kind == Kind::List && int(row.count) == s.columns;
                for (uint32_t c = 0; ok && c < uint32_t(row.count); ++c) s.weights.push_back(number(f_.element(row, c)));
            }
        } else {
            ok = w->kind == Kind::List && int(w->count) == s.columns;
            for (uint32_t c = 0; ok && c < uint32_t(w->count); ++c) s.weights.push_back(number(f_.element(*w, c)));
        }
        for (double x : s.weights) ok = ok && std::isfinite(x) && x > 0;
    }
    for (const Eigen::Vector3d& p : s.points) ok = ok && p.allFinite();
    if (!ok) problem(entity, std::string("a malformed B-spline ") + (surface ? "surface" : "curve") +
                                 " (degrees, control points, knots, multiplicities or weights do not agree)");
    return ok;
}

Curve GeometryReader::curve(uint32_t entity) { return curve_at(entity, 0); }

Curve GeometryReader::curve_at(uint32_t entity, int depth) {
    Curve c;
    c.entity = entity;
    if (entity >= f_.instances.size()) {
        c.type = "(missing)";
        problem(entity, "a curve that the file does not have");
        return c;
    }
    const Instance& in = f_.instances[entity];
    c.type = in.record_count == 1 ? f_.type_name(f_.first_record(in).type) : "(complex)";
    if (depth > 8) {
        problem(entity, "curves nested more than 8 deep");
        return c;
    }
    if (const Record* r = f_.record(in, types_[kLine]); r && r->count >= 3) {
        c.kind = Curve::Kind::Line;
        c.frame.origin = point(ref(&f_.attribute(*r, 1)));
        const uint32_t v = ref(&f_.attribute(*r, 2));
        if (is(f_, v, types_[kVector]) && f_.record(v, types_[kVector])->count >= 2)
            c.frame.x = direction(ref(&f_.attribute(*f_.record(v, types_[kVector]), 1)));
        else
            problem(entity, "a LINE without a VECTOR");
        if (!c.frame.x.allFinite()) c.kind = Curve::Kind::Unsupported;
        return c;
    }
    if (const Record* r = f_.record(in, types_[kCircle]); r && r->count >= 3) {
        c.kind = Curve::Kind::Circle;
        c.frame = placement(ref(&f_.attribute(*r, 1)));
        c.radius = length(f_.attribute(*r, 2));
        if (!(c.radius > 0)) problem(entity, "a CIRCLE whose radius is not positive");
        return c;
    }
    if (const Record* r = f_.record(in, types_[kEllipse]); r && r->count >= 4) {
        c.kind = Curve::Kind::Ellipse;
        c.frame = placement(ref(&f_.attribute(*r, 1)));
        c.radius = length(f_.attribute(*r, 2));
        c.radius2 = length(f_.attribute(*r, 3));
        if (!(c.radius > 0 && c.radius2 > 0)) problem(entity, "an ELLIPSE whose semi-axes are not positive");
        return c;
    }
    if (const Record* r = f_.record(in, types_[kPolyline]); r && r->count >= 2 && f_.attribute(*r, 1).kind == Kind::List) {
        c.kind = Curve::Kind::Polyline;
        const Value& pts = f_.attribute(*r, 1);
        for (uint32_t k = 0; k < uint32_t(pts.count); ++k) c.polyline.push_back(point(ref(&f_.element(pts, k))));
        return c;
    }
    if (f_.record(in, types_[kBSplineCurveWithKnots]) || f_.record(in, types_[kBSplineCurve])) {
        c.kind = bspline(entity, false, c.spline) ? Curve::Kind::BSpline : Curve::Kind::Unsupported;
        if (in.record_count > 1) c.type = "B_SPLINE_CURVE_WITH_KNOTS";
        return c;
    }
    if (const Record* r = f_.record(in, types_[kSurfaceCurve]) ? f_.record(in, types_[kSurfaceCurve])
                                                                       : f_.record(in, types_[kSeamCurve]);
               r && r->count >= 2) {
        // The 3D curve is the edge's geometry; the pcurves are the faces' business.
        return curve_at(ref(&f_.attribute(*r, 1)), depth + 1);
        return c;
    }
    if (const Record* r = f_.record(in, types_[kTrimmedCurve]); r && r->count >= 2) {
        // An edge's vertices bound it; the trimmed curve's basis is its geometry.
        return curve_at(ref(&f_.attribute(*r, 1)), depth + 1);
        return c;
    }
    {
        problem(entity, "a curve of a type mbx does not read: " + c.type);
    }
    return c;
}

Surface GeometryReader::surface(uint32_t entity) {
    Surface s;
    s.entity = entity;
    if (entity >= f_.instances.size()) {
        s.type = "(missing)";
        problem(entity, "a surface that the file does not have");
        return s;
    }
    const Instance& in = f_.instances[entity];
    s.type = in.record_count == 1 ? f_.type_name(f_.first_record(in).type) : "(complex)";
    // (each branch sets the kind first; a frame that does not read unsets it)
    auto placed = [&](const Record& r) {
        s.frame = placement(ref(&f_.attribute(r, 1)));
        if (!s.frame.origin.allFinite() || !s.frame.z.allFinite()) s.kind = Surface::Kind::Unsupported;
    };
    if (const Record* r = f_.record(in, types_[kPlane]); r && r->count >= 2) {
        s.kind = Surface::Kind::Plane;
        placed(*r);
        return s;
    }
    if (const Record* r = f_.record(in, types_[kCylinder]); r && r->count >= 3) {
        s.kind = Surface::Kind::Cylinder;
        placed(*r);
        s.radius = length(f_.attribute(*r, 2));
        if (!(s.radius > 0)) problem(entity, "a CYLINDRICAL_SURFACE whose radius is not positive");
        return s;
    }
    if (const Record* r = f_.record(in, types_[kCone]); r && r->count >= 4) {
        s.kind = Surface::Kind::Cone;
        placed(*r);
        s.radius = length(f_.attribute(*r, 2));
        s.semi_angle = number(f_.attribute(*r, 3)) * units_.plane_angle;
        if (!(s.radius >= 0) || !(s.semi_angle > 0 && s.semi_angle < M_PI / 2))
            problem(entity, "a CONICAL_SURFACE with a negative radius or a semi-angle outside (0, 90) degrees");
        return s;
    }
    if (const Record* r = f_.record(in, types_[kSphere]); r && r->count >= 3) {
        s.kind = Surface::Kind::Sphere;
        placed(*r);
        s.radius = length(f_.attribute(*r, 2));
        if (!(s.radius > 0)) problem(entity, "a SPHERICAL_SURFACE whose radius is not positive");
        return s;
    }
    if (const Record* r = f_.record(in, types_[kTorus]) ? f_.record(in, types_[kTorus])
                                                                : f_.record(in, types_[kDegenerateTorus]);
               r && r->count >= 4) {
        s.kind = Surface::Kind::Torus;
        placed(*r);
        s.radius = length(f_.attribute(*r, 2));
        s.minor_radius = length(f_.attribute(*r, 3));
        if (!(s.minor_radius > 0) || !std::isfinite(s.radius))
            problem(entity, "a toroidal surface whose minor radius is not positive");
        return s;
    }
    if (const Record* r = f_.record(in, types_[kRevolution]); r && r->count >= 3) {
        s.kind = Surface::Kind::Revolution;
        s.swept.push_back(curve(ref(&f_.attribute(*r, 1))));
        const uint32_t axis = ref(&f_.attribute(*r, 2));
        if (is(f_, axis, types_[kAxis1]) && f_.record(axis, types_[kAxis1])->count >= 3) {
            const Record& ax = *f_.record(axis, types_[kAxis1]);
            s.axis_point = point(ref(&f_.attribute(ax, 1)));
            if (f_.attribute(ax, 2).kind == Kind::Reference) s.axis = direction(f_.attribute(ax, 2).a);
        } else {
            problem(entity, "a SURFACE_OF_REVOLUTION without an AXIS1_PLACEMENT");
            s.kind = Surface::Kind::Unsupported;
        }
        if (s.swept[0].kind == Curve::Kind::Unsupported) s.kind = Surface::Kind::Unsupported;
        return s;
    }
    if (const Record* r = f_.record(in, types_[kExtrusion]); r && r->count >= 3) {
        s.kind = Surface::Kind::Extrusion;
        s.swept.push_back(curve(ref(&f_.attribute(*r, 1))));
        const uint32_t v = ref(&f_.attribute(*r, 2));
        if (is(f_, v, types_[kVector]) && f_.record(v, types_[kVector])->count >= 3) {
            const Record& vec = *f_.record(v, types_[kVector]);
            s.axis = direction(ref(&f_.attribute(vec, 1))) * length(f_.attribute(vec, 2));
        } else {
            problem(entity, "a SURFACE_OF_LINEAR_EXTRUSION without a VECTOR");
            s.kind = Surface::Kind::Unsupported;
        }
        if (s.swept[0].kind == Curve::Kind::Unsupported) s.kind = Surface::Kind::Unsupported;
        return s;
    }
    if (f_.record(in, types_[kBSplineSurfaceWithKnots]) || f_.record(in, types_[kBSplineSurface])) {
        s.kind = bspline(entity, true, s.spline) ? Surface::Kind::BSpline : Surface::Kind::Unsupported;
        if (s.kind == Surface::Kind::BSpline) prepare_surface(s.spline);
        if (in.record_count > 1) s.type = "B_SPLINE_SURFACE_WITH_KNOTS";
        return s;
    }
    {
        problem(entity, "a surface of a type mbx does not read: " + s.type);
    }
    return s;
}

}  // namespace mbx_step
