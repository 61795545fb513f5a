#include "host_adapters/step/evaluate.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace mbx_step {

using Eigen::Vector2d;

namespace {


// The knot span holding u (The NURBS Book, A2.1), clamped to the curve's range.
int find_span(const std::vector<double>& U, int p, int n, double u) {
    if (u >= U[size_t(n) + 1]) return n;
    if (u <= U[size_t(p)]) return p;
    const auto it = std::upper_bound(U.begin() + p, U.begin() + n + 1, u);
    return int(it - U.begin()) - 1;
}

// The p + 1 non-zero basis functions at u and their first derivatives (A2.2,
// with the derivative of A2.3 for one order).
void basis(const std::vector<double>& U, int span, double u, int p, double* N, double* dN) {
    double left[33], right[33], ndu[33][33];
    ndu[0][0] = 1;
    for (int j = 1; j <= p; ++j) {
        left[j] = u - U[size_t(span + 1 - j)];
        right[j] = U[size_t(span + j)] - u;
        double saved = 0;
        for (int r = 0; r < j; ++r) {
            ndu[j][r] = right[r + 1] + left[j - r];
            const double temp = ndu[j][r] != 0 ? ndu[r][j - 1] / ndu[j][r] : 0;
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for (int j = 0; j <= p; ++j) N[j] = ndu[j][p];
    if (!dN) return;
    for (int r = 0; r <= p; ++r) {
        // d/du N_{span-p+r,p} = p (N_{.,p-1}/(U_{i+p}-U_i) - N_{.+1,p-1}/(U_{i+p+1}-U_{i+1}))
        double d = 0;
        if (r >= 1 && ndu[p][r - 1] != 0) d += ndu[r - 1][p - 1] / ndu[p][r - 1];
        if (r <= p - 1 && ndu[p][r] != 0) d -= ndu[r][p - 1] / ndu[p][r];
        dN[r] = p * d;
    }
}

double wrap_positive(double a) {  // into (0, 2 pi]
    a = std::fmod(a, kTwoPi);
    if (a <= 0) a += kTwoPi;
    return a;
}

double nearest_period(double value, double period, double near) {
    return period > 0 ? value + period * std::round((near - value) / period) : value;
}

// A curve point and its derivative along t.
void curve_with_derivative(const Curve& c, double t, Eigen::Vector3d& p, Eigen::Vector3d& d) {
    switch (c.kind) {
        case Curve::Kind::Line:
            p = c.frame.origin + t * c.frame.x;
            d = c.frame.x;
            return;
        case Curve::Kind::Circle:
        case Curve::Kind::Ellipse: {
            const double a = c.radius, b = c.kind == Curve::Kind::Circle ? c.radius : c.radius2;
            p = c.frame.origin + a * std::cos(t) * c.frame.x + b * std::sin(t) * c.frame.y;
            d = -a * std::sin(t) * c.frame.x + b * std::cos(t) * c.frame.y;
            return;
        }
        case Curve::Kind::BSpline: {
            const BSpline& s = c.spline;
            const int p_ = s.degree_u, n = s.columns - 1;
            const int span = find_span(s.knots_u, p_, n, t);
            double N[33], dN[33];
            basis(s.knots_u, span, t, p_, N, dN);
            Eigen::Vector3d A = Eigen::Vector3d::Zero(), dA = Eigen::Vector3d::Zero();
            double w = 0, dw = 0;
            for (int j = 0; j <= p_; ++j) {
                const int k = span - p_ + j;
                const double wk = s.weights.empty() ? 1.0 : s.weights[size_t(k)];
                A += N[j] * wk * s.points[size_t(k)];
                dA += dN[j] * wk * s.points[size_t(k)];
                w += N[j] * wk;
                dw += dN[j] * wk;
            }
            p = A / w;
            d = (dA - dw * p) / w;
            return;
        }
        case Curve::Kind::Polyline: {
            // Parameter k + f on segment k.
            const int n = int(c.polyline.size()) - 1;
            const int k = std::clamp(int(std::floor(t)), 0, std::max(n - 1, 0));
            if (n < 1) {
                p = c.polyline.empty() ? Eigen::Vector3d::Zero() : c.polyline[0];
                d = Eigen::Vector3d::Zero();
                return;
            }
            d = c.polyline[size_t(k) + 1] - c.polyline[size_t(k)];
            p = c.polyline[size_t(k)] + (t - k) * d;
            return;
        }
        case Curve::Kind::Unsupported:
            break;
    }
    p = Eigen::Vector3d::Constant(NAN);
    d = Eigen::Vector3d::Constant(NAN);
}

}  // namespace

std::pair<double, double> spline_range(const BSpline& s, bool v) {
    const std::vector<double>& U = v ? s.knots_v : s.knots_u;
    const int p = v ? s.degree_v : s.degree_u;
    const int n = (v ? s.columns : (s.rows == 1 ? s.columns : s.rows)) - 1;
    return {U[size_t(p)], U[size_t(n) + 1]};
}

namespace {

// A periodic direction's parameter brought into the knot range.
double wrap(double t, double period, double start) {
    if (!(period > 0)) return t;
    const double r = std::fmod(t - start, period);
    return start + (r < 0 ? r + period : r);
}

}  // namespace

Eigen::Vector3d spline_point(const BSpline& s, double u) {
    Curve c;
    c.kind = Curve::Kind::BSpline;
    c.spline = s;
    return curve_point(c, u);
}

namespace {

// Homogeneous sums of a surface at (u, v), with their derivatives.
void surface_sums(const BSpline& s, double u, double v, Eigen::Vector3d& A, double& w, Eigen::Vector3d* Au,
                  double* wu, Eigen::Vector3d* Av, double* wv) {
    if (s.period_u > 0) u = wrap(u, s.period_u, spline_range(s, false).first);
    if (s.period_v > 0) v = wrap(v, s.period_v, spline_range(s, true).first);
    const int pu = s.degree_u, pv = s.degree_v;
    const int su = find_span(s.knots_u, pu, s.rows - 1, u), sv = find_span(s.knots_v, pv, s.columns - 1, v);
    double Nu[33], dNu[33], Nv[33], dNv[33];
    basis(s.knots_u, su, u, pu, Nu, dNu);
    basis(s.knots_v, sv, v, pv, Nv, dNv);
    A.setZero();
    w = 0;
    if (Au) Au->setZero(), Av->setZero(), *wu = 0, *wv = 0;
    for (int i = 0; i <= pu; ++i)
        for (int j = 0; j <= pv; ++j) {
            const size_t k = size_t(su - pu + i) * size_t(s.columns) + size_t(sv - pv + j);
            const double wk = s.weights.empty() ? 1.0 : s.weights[k];
            A += Nu[i] * Nv[j] * wk * s.points[k];
            w += Nu[i] * Nv[j] * wk;
            if (Au) {
                *Au += dNu[i] * Nv[j] * wk * s.points[k];
                *Av += Nu[i] * dNv[j] * wk * s.points[k];
                *wu += dNu[i] * Nv[j] * wk;
                *wv += Nu[i] * dNv[j] * wk;
            }
        }
}

}  // namespace

Eigen::Vector3d spline_point(const BSpline& s, double u, double v) {
    Eigen::Vector3d A;
    double w;
    surface_sums(s, u, v, A, w, nullptr, nullptr, nullptr, nullptr);
    return A / w;
}

void prepare_surface(BSpline& s) {
    s.period_u = s.period_v = 0;
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3d& p : s.points) box.extend(p);
    s.extent = s.points.empty() ? 0.0 : box.diagonal().norm();
    if (s.points.empty() || s.columns < 2 || s.rows < 2) return;
    const double gap = 1e-7 * std::max(s.extent, 1e-12);
    const double u0 = spline_range(s, false).first, u1 = spline_range(s, false).second;
    const double v0 = spline_range(s, true).first, v1 = spline_range(s, true).second;
    auto meets = [&](bool along_v) {
        for (int k = 0; k <= 8; ++k) {
            const double t = along_v ? u0 + (u1 - u0) * k / 8 : v0 + (v1 - v0) * k / 8;
            const Eigen::Vector3d a = along_v ? spline_point(s, t, v0) : spline_point(s, u0, t);
            const Eigen::Vector3d b = along_v ? spline_point(s, t, v1) : spline_point(s, u1, t);
            if (!((a - b).norm() <= gap)) return false;
        }
        return true;
    };
    const bool periodic_u = s.closed_u && meets(false), periodic_v = s.closed_v && meets(true);
    if (periodic_u) s.period_u = u1 - u0;
    if (periodic_v) s.period_v = v1 - v0;
}

void spline_derivatives(const BSpline& s, double u, double v, Eigen::Vector3d& du, Eigen::Vector3d& dv) {
    Eigen::Vector3d A, Au, Av;
    double w, wu, wv;
    surface_sums(s, u, v, A, w, &Au, &wu, &Av, &wv);
    const Eigen::Vector3d p = A / w;
    du = (Au - wu * p) / w;
    dv = (Av - wv * p) / w;
}

Eigen::Vector3d curve_point(const Curve& c, double t) {
    Eigen::Vector3d p, d;
    curve_with_derivative(c, t, p, d);
    return p;
}

double curve_period(const Curve& c) {
    return c.kind == Curve::Kind::Circle || c.kind == Curve::Kind::Ellipse ? kTwoPi : 0.0;
}

double curve_parameter(const Curve& c, const Eigen::Vector3d& q) {
    switch (c.kind) {
        case Curve::Kind::Line:
            return (q - c.frame.origin).dot(c.frame.x);
        case Curve::Kind::Circle:
        case Curve::Kind::Ellipse: {
            const Eigen::Vector3d d = q - c.frame.origin;
            const double a = c.radius, b = c.kind == Curve::Kind::Circle ? c.radius : c.radius2;
            // (exact for a circle; for an ellipse the eccentric angle of the projected point)
            double t = std::atan2(d.dot(c.frame.y) / b, d.dot(c.frame.x) / a);
            if (t < 0) t += kTwoPi;
            if (c.kind == Curve::Kind::Ellipse) {
                for (int k = 0; k < 8; ++k) {
                    Eigen::Vector3d p, dp;
                    curve_with_derivative(c, t, p, dp);
                    const double second = -(p - c.frame.origin).dot(p - q) + dp.squaredNorm();
                    if (!(std::abs(second) > 0)) break;
                    t -= dp.dot(p - q) / second;
                }
            }
            return t;
        }
        case Curve::Kind::Polyline: {
            double best = 0, best_d = INFINITY;
            for (size_t k = 0; k + 1 < c.polyline.size(); ++k) {
                const Eigen::Vector3d a = c.polyline[k], d = c.polyline[k + 1] - a;
                const double f = d.squaredNorm() > 0 ? std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
                const double dist = (a + f * d - q).squaredNorm();
                if (dist < best_d) best_d = dist, best = double(k) + f;
            }
            return best;
        }
        case Curve::Kind::BSpline: {
            const auto [t0, t1] = spline_range(c.spline);
            // Nearest of samples (eight per knot span), then Gauss-Newton.
            const int samples = std::max(16, 8 * c.spline.columns);
            double best = t0, best_d = INFINITY;
            for (int k = 0; k <= samples; ++k) {
                const double t = t0 + (t1 - t0) * k / samples;
                const double dist = (curve_point(c, t) - q).squaredNorm();
                if (dist < best_d) best_d = dist, best = t;
            }
            for (int k = 0; k < 20; ++k) {
                Eigen::Vector3d p, d;
                curve_with_derivative(c, best, p, d);
                if (!(d.squaredNorm() > 0)) break;
                const double step = d.dot(p - q) / d.squaredNorm();
                best = std::clamp(best - step, t0, t1);
                if (std::abs(step) < 1e-15 * std::max(1.0, std::abs(t1 - t0))) break;
            }
            return best;
        }
        case Curve::Kind::Unsupported:
            break;
    }
    return NAN;
}

std::vector<Eigen::Vector3d> discretise(const Brep& b, const Edge& e, const Tolerance& tol) {
    const Eigen::Vector3d a = b.vertices[e.start].point, z = b.vertices[e.end].point;
    const Curve& c = e.curve;
    const bool closed = e.start == e.end;
    std::vector<Eigen::Vector3d> out{a};
    auto finish = [&] {
        out.push_back(z);
        return out;
    };
    switch (c.kind) {
        case Curve::Kind::Line:
        case Curve::Kind::Unsupported:
            return finish();
        case Curve::Kind::Polyline: {
            std::vector<Eigen::Vector3d> inner(c.polyline.begin() + (c.polyline.empty() ? 0 : 1),
                                               c.polyline.end() - (c.polyline.size() < 2 ? 0 : 1));
            if (!e.same_sense) std::reverse(inner.begin(), inner.end());
            out.insert(out.end(), inner.begin(), inner.end());
            return finish();
        }
        case Curve::Kind::Circle:
        case Curve::Kind::Ellipse: {
            const double t0 = curve_parameter(c, a), t1 = curve_parameter(c, z);
            double sweep = closed ? kTwoPi : wrap_positive(e.same_sense ? t1 - t0 : t0 - t1);
            if (!e.same_sense) sweep = -sweep;
            const double r = std::max(c.radius, c.kind == Curve::Kind::Ellipse ? c.radius2 : 0.0);
            double step = tol.angle;
            if (tol.chord < r) step = std::min(step, 2 * std::acos(1 - tol.chord / r));
            // (NaN from a point that is not one, or a count past any real edge's:
            // bounded, so a malformed file cannot ask for billions of points)
            const double segments = std::ceil(std::abs(sweep) / step - 1e-9);
            const int n = std::max(closed ? 3 : 1, std::isfinite(segments) ? int(std::min(segments, 100000.0)) : 1);
            for (int k = 1; k < n; ++k) out.push_back(curve_point(c, t0 + sweep * k / n));
            return finish();
        }
        case Curve::Kind::BSpline: {
            const auto [lo, hi] = spline_range(c.spline);
            double t0 = curve_parameter(c, a), t1 = curve_parameter(c, z);
            if (closed) t0 = lo, t1 = hi;
            // Knots inside (t0, t1) start the subdivision, so no span is skipped.
            std::vector<double> ts{std::min(t0, t1)};
            for (double k : c.spline.knots_u)
                if (k > ts.back() + 1e-14 && k < std::max(t0, t1) - 1e-14) ts.push_back(k);
            ts.push_back(std::max(t0, t1));
            std::vector<Eigen::Vector3d> pts{curve_point(c, ts[0])};
            struct Span {
                double t0, t1;
                int depth;
            };
            for (size_t k = 0; k + 1 < ts.size(); ++k) {
                std::vector<Span> stack{{ts[k], ts[k + 1], 0}};
                // Depth first, right half pushed first, so points come out in order.
                while (!stack.empty()) {
                    const Span s = stack.back();
                    stack.pop_back();
                    const Eigen::Vector3d p0 = curve_point(c, s.t0), p1 = curve_point(c, s.t1);
                    const double tm = 0.5 * (s.t0 + s.t1);
                    const Eigen::Vector3d pm = curve_point(c, tm);
                    const Eigen::Vector3d chord = p1 - p0;
                    const double deviation = chord.squaredNorm() > 0
                                                 ? (pm - p0).cross(chord).norm() / chord.norm()
                                                 : (pm - p0).norm();
                    const Eigen::Vector3d h0 = pm - p0, h1 = p1 - pm;
                    const double turn = h0.norm() > 0 && h1.norm() > 0
                                            ? std::acos(std::clamp(h0.dot(h1) / (h0.norm() * h1.norm()), -1.0, 1.0))
                                            : 0.0;
                    if (s.depth < 24 && (s.depth < 1 || deviation > tol.chord || turn > 0.5 * tol.angle)) {
                        stack.push_back({tm, s.t1, s.depth + 1});
                        stack.push_back({s.t0, tm, s.depth + 1});
                    } else {
                        pts.push_back(p1);
                    }
                }
            }
            // Sampled along the curve; the edge runs from its start vertex (for a
            // closed edge: along the curve when same_sense).
            if (closed ? !e.same_sense : t0 > t1) std::reverse(pts.begin(), pts.end());
            out.insert(out.end(), pts.begin() + 1, pts.end() - 1);
            return finish();
        }
    }
    return finish();
}

Eigen::Vector3d surface_point(const Surface& s, double u, double v) {
    const Placement& f = s.frame;
    const Eigen::Vector3d radial = std::cos(u) * f.x + std::sin(u) * f.y;
    switch (s.kind) {
        case Surface::Kind::Plane:
            return f.origin + u * f.x + v * f.y;
        case Surface::Kind::Cylinder:
            return f.origin + s.radius * radial + v * f.z;
        case Surface::Kind::Cone:
            return f.origin + (s.radius + v * std::tan(s.semi_angle)) * radial + v * f.z;
        case Surface::Kind::Sphere:
            return f.origin + s.radius * (std::cos(v) * radial + std::sin(v) * f.z);
        case Surface::Kind::Torus:
            return f.origin + (s.radius + s.minor_radius * std::cos(v)) * radial + s.minor_radius * std::sin(v) * f.z;
        case Surface::Kind::BSpline:
            return spline_point(s.spline, u, v);
        case Surface::Kind::Revolution: {
            const Eigen::Vector3d p = curve_point(s.swept[0], v);
            return s.axis_point + Eigen::AngleAxisd(u, s.axis) * (p - s.axis_point);
        }
        case Surface::Kind::Extrusion:
            return curve_point(s.swept[0], u) + v * s.axis;
        case Surface::Kind::Unsupported:
            break;
    }
    return Eigen::Vector3d::Constant(NAN);
}

Eigen::Vector2d surface_periods(const Surface& s) {
    switch (s.kind) {
        case Surface::Kind::Cylinder:
        case Surface::Kind::Cone:
        case Surface::Kind::Sphere:
        case Surface::Kind::Revolution:
            return {kTwoPi, (s.swept.empty() ? 0.0 : curve_period(s.swept[0]))};  // (a circle swept round: a torus, periodic both ways)
        case Surface::Kind::Torus:
            return {kTwoPi, kTwoPi};
        case Surface::Kind::BSpline:
            return {s.spline.period_u, s.spline.period_v};
        case Surface::Kind::Extrusion:
            return {(s.swept.empty() ? 0.0 : curve_period(s.swept[0])), 0};
        default:
            return {0, 0};
    }
}

namespace {

// Newton's method for the foot of q on a B-spline surface from t: the
// parameters clamped to the knot range where the surface is not periodic.
Vector2d spline_foot(const BSpline& b, const Eigen::Vector3d& q, Vector2d t, int iterations, double precision = 0) {
    const double u0 = spline_range(b, false).first, u1 = spline_range(b, false).second;
    const double v0 = spline_range(b, true).first, v1 = spline_range(b, true).second;
    for (int k = 0; k < iterations; ++k) {
        Eigen::Vector3d du, dv;
        spline_derivatives(b, t.x(), t.y(), du, dv);
        const Eigen::Vector3d r = spline_point(b, t.x(), t.y()) - q;
        Eigen::Matrix2d J;
        J << du.dot(du), du.dot(dv), du.dot(dv), dv.dot(dv);
        const Vector2d g(du.dot(r), dv.dot(r));
        if (!(std::abs(J.determinant()) > 0)) break;
        const Vector2d step = J.ldlt().solve(g);
        t -= step;
        if (!(b.period_u > 0)) t.x() = std::clamp(t.x(), u0, u1);
        if (!(b.period_v > 0)) t.y() = std::clamp(t.y(), v0, v1);
        if (step.norm() < 1e-15 * std::max(1.0, std::max(u1 - u0, v1 - v0))) break;
        if ((du * step.x() + dv * step.y()).norm() < precision) break;
    }
    return t;
}

}  // namespace

Eigen::Vector2d surface_foot(const Surface& s, const Eigen::Vector3d& q, const Eigen::Vector2d& start, double precision) {
    if (s.kind == Surface::Kind::BSpline) return spline_foot(s.spline, q, start, 8, precision);
    return surface_parameters(s, q, &start);
}

Eigen::Vector2d surface_parameters(const Surface& s, const Eigen::Vector3d& q, const Eigen::Vector2d* near) {
    const Placement& f = s.frame;
    const Eigen::Vector3d d = q - f.origin;
    const double x = d.dot(f.x), y = d.dot(f.y), z = d.dot(f.z);
    Eigen::Vector2d uv(NAN, NAN);
    switch (s.kind) {
        case Surface::Kind::Plane:
            uv = {x, y};
            break;
        case Surface::Kind::Cylinder:
            uv = {std::atan2(y, x), z};
            break;
        case Surface::Kind::Cone:
            // Beyond the apex the radius R + v tan(a) is negative: the point is
            // on the far side of the axis from u.
            uv = {std::atan2(y, x) + (s.radius + z * std::tan(s.semi_angle) < 0 ? M_PI : 0.0), z};
            break;
        case Surface::Kind::Sphere:
            uv = {std::atan2(y, x), std::atan2(z, std::hypot(x, y))};
            break;
        case Surface::Kind::Torus: {
            // A torus whose major radius is smaller than its minor one passes
            // through its axis: a point may lie where R + r cos(v) < 0, on the
            // far side of the axis from u. The candidate on the surface wins
            // (the one nearest `near` where both are).
            const double rho = std::hypot(x, y), u = std::atan2(y, x);
            const Vector2d a(u, std::atan2(z, rho - s.radius)), b(u + M_PI, std::atan2(z, -rho - s.radius));
            const double da = (surface_point(s, a.x(), a.y()) - q).norm(), db = (surface_point(s, b.x(), b.y()) - q).norm();
            const double tie = 1e-9 * (s.radius + s.minor_radius);
            if (std::abs(da - db) > tie || !near) {
                uv = da <= db ? a : b;
            } else {
                const Vector2d periods = surface_periods(s);
                Vector2d na = a, nb = b;
                for (int k = 0; k < 2; ++k) {
                    na[k] = nearest_period(na[k], periods[k], (*near)[k]);
                    nb[k] = nearest_period(nb[k], periods[k], (*near)[k]);
                }
                uv = (na - *near).norm() <= (nb - *near).norm() ? na : nb;
            }
            break;
        }
        case Surface::Kind::Revolution: {
            // u: the turn about the axis from the profile's own half-plane.
            const Curve& c = s.swept[0];
            const Eigen::Vector3d a = s.axis.normalized();
            Eigen::Vector3d ref = curve_point(c, curve_parameter(c, q)) - s.axis_point;
            ref -= ref.dot(a) * a;
            Eigen::Vector3d r = q - s.axis_point;
            r -= r.dot(a) * a;
            double u = 0;
            if (ref.norm() > 0 && r.norm() > 0) u = std::atan2(ref.cross(r).dot(a), ref.dot(r));
            const Eigen::Vector3d back = s.axis_point + Eigen::AngleAxisd(-u, a) * (q - s.axis_point);
            uv = {u, curve_parameter(c, back)};
            break;
        }
        case Surface::Kind::Extrusion: {
            const double len2 = s.axis.squaredNorm();
            double u = curve_parameter(s.swept[0], q);
            double v = len2 > 0 ? (q - curve_point(s.swept[0], u)).dot(s.axis) / len2 : 0;
            for (int k = 0; k < 4; ++k) {
                u = curve_parameter(s.swept[0], q - v * s.axis);
                v = len2 > 0 ? (q - curve_point(s.swept[0], u)).dot(s.axis) / len2 : 0;
            }
            uv = {u, v};
            break;
        }
        case Surface::Kind::BSpline: {
            const BSpline& b = s.spline;
            // (plain doubles: a lambda may not capture structured bindings in C++17)
            const double u0 = spline_range(b, false).first, u1 = spline_range(b, false).second;
            const double v0 = spline_range(b, true).first, v1 = spline_range(b, true).second;
            auto newton = [&](const Vector2d& t) { return spline_foot(b, q, t, 30); };
            // From the neighbour's parameters first (a loop's next point is
            // close); the grid search only when that does not land on q.
            if (near) {
                const Vector2d t = newton(*near);
                Eigen::Vector3d du, dv;
                spline_derivatives(b, t.x(), t.y(), du, dv);
                const Eigen::Vector3d r = spline_point(b, t.x(), t.y()) - q;
                const double miss = r.norm(), size = std::max(b.extent, 1e-12);
                // Edge points lie only within the exporter's tolerance of the
                // surface, so Newton's foot point a little off q is the answer:
                // where it lands on q, or q lies off the surface along its
                // normal there (a true foot point) and not far.
                const bool foot = std::abs(du.dot(r)) <= 1e-6 * du.norm() * miss + 1e-300 &&
                                  std::abs(dv.dot(r)) <= 1e-6 * dv.norm() * miss + 1e-300;
                if (miss <= 1e-5 * size || (foot && miss <= 1e-3 * size)) return t;
            }
            auto near_periods = [&](Vector2d t) {
                if (near) t = {nearest_period(t.x(), b.period_u, near->x()), nearest_period(t.y(), b.period_v, near->y())};
                return t;
            };
            const int nu = std::max(8, 4 * b.rows), nv = std::max(8, 4 * b.columns);
            double best = INFINITY;
            for (int i = 0; i <= nu; ++i)
                for (int j = 0; j <= nv; ++j) {
                    const Vector2d t(u0 + (u1 - u0) * i / nu, v0 + (v1 - v0) * j / nv);
                    const double dist = (spline_point(b, t.x(), t.y()) - q).squaredNorm();
                    if (dist < best) best = dist, uv = t;
                }
            return near_periods(newton(uv));
        }
        case Surface::Kind::Unsupported:
            return uv;
    }
    if (near) {
        const Eigen::Vector2d periods = surface_periods(s);
        uv.x() = nearest_period(uv.x(), periods.x(), near->x());
        uv.y() = nearest_period(uv.y(), periods.y(), near->y());
    }
    return uv;
}

}  // namespace mbx_step
