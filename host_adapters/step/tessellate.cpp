#include "host_adapters/step/tessellate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace mbx_step {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;


double cross2(const Vector2d& a, const Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// A point of a face's parameter-plane polygon: its uv and the mesh point it is.
struct UvPoint {
    Vector2d uv;
    uint32_t point;
};

double signed_area(const std::vector<UvPoint>& poly) {
    double a = 0;
    for (size_t k = 0; k < poly.size(); ++k) a += cross2(poly[k].uv, poly[(k + 1) % poly.size()].uv);
    return 0.5 * a;
}

bool segments_cross(const Vector2d& a, const Vector2d& b, const Vector2d& c, const Vector2d& d) {
    const double d1 = cross2(b - a, c - a), d2 = cross2(b - a, d - a);
    const double d3 = cross2(d - c, a - c), d4 = cross2(d - c, b - c);
    return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

// One polygon from an outer loop (counter-clockwise) and holes (clockwise),
// each hole joined to what is already joined by a bridge from its rightmost
// point to the nearest point it sees (the bridge walked there and back).
std::vector<UvPoint> bridge_holes(std::vector<UvPoint> outer, std::vector<std::vector<UvPoint>> holes) {
    std::sort(holes.begin(), holes.end(), [](const auto& a, const auto& b) {
        auto right = [](const std::vector<UvPoint>& h) {
            double x = -INFINITY;
            for (const UvPoint& p : h) x = std::max(x, p.uv.x());
            return x;
        };
        return right(a) > right(b);
    });
    for (size_t h = 0; h < holes.size(); ++h) {
        const std::vector<UvPoint>& hole = holes[h];
        if (hole.empty()) continue;
        size_t m = 0;
        for (size_t k = 1; k < hole.size(); ++k)
            if (hole[k].uv.x() > hole[m].uv.x()) m = k;
        const Vector2d M = hole[m].uv;
        // Candidates by distance; the first whose bridge crosses no edge.
        std::vector<size_t> order(outer.size());
        for (size_t k = 0; k < order.size(); ++k) order[k] = k;
        std::sort(order.begin(), order.end(),
                  [&](size_t a, size_t b) { return (outer[a].uv - M).squaredNorm() < (outer[b].uv - M).squaredNorm(); });
        size_t chosen = order.empty() ? 0 : order[0];
        for (size_t c : order) {
            const Vector2d P = outer[c].uv;
            bool blocked = false;
            auto check = [&](const std::vector<UvPoint>& poly) {
                for (size_t k = 0; k < poly.size() && !blocked; ++k)
                    blocked = segments_cross(M, P, poly[k].uv, poly[(k + 1) % poly.size()].uv);
            };
            check(outer);
            for (size_t o = h; o < holes.size() && !blocked; ++o) check(holes[o]);
            if (!blocked) {
                chosen = c;
                break;
            }
        }
        std::vector<UvPoint> merged(outer.begin(), outer.begin() + long(chosen) + 1);
        for (size_t k = 0; k <= hole.size(); ++k) merged.push_back(hole[(m + k) % hole.size()]);
        merged.insert(merged.end(), outer.begin() + long(chosen), outer.end());
        outer = std::move(merged);
    }
    return outer;
}

bool inside_triangle(const Vector2d& p, const Vector2d& a, const Vector2d& b, const Vector2d& c) {
    return cross2(b - a, p - a) >= 0 && cross2(c - b, p - b) >= 0 && cross2(a - c, p - c) >= 0;
}

// Ear clipping of a counter-clockwise polygon (which may touch itself along
// bridges), walking round it and cutting the first ear found; the Delaunay
// flips afterwards give the triangles their shape. Only vertices that are not
// strictly convex can lie inside an ear, and those only become fewer as ears
// go, so they sit in a grid built once: each test looks at a few cells.
bool ear_clip(const std::vector<UvPoint>& poly, std::vector<std::array<uint32_t, 3>>& out) {
    // (out: triangles of positions in `poly`)
    const size_t n = poly.size();
    if (n < 3) return false;
    std::vector<size_t> prev(n), next(n);
    for (size_t k = 0; k < n; ++k) prev[k] = (k + n - 1) % n, next[k] = (k + 1) % n;
    std::vector<char> alive(n, 1);
    Eigen::AlignedBox2d box;
    for (const UvPoint& p : poly) box.extend(p.uv);
    const double extent = std::max(box.sizes().maxCoeff(), 1e-300);
    const double eps = 1e-14 * extent * extent;
    auto area = [&](size_t k) {
        const Vector2d &a = poly[prev[k]].uv, &b = poly[k].uv, &c = poly[next[k]].uv;
        return cross2(b - a, c - b);
    };
    const int cells = std::max(1, int(std::sqrt(double(n))));
    const Vector2d cell = box.sizes() / cells;
    auto cell_of = [&](const Vector2d& p) {
        Eigen::Vector2i c;
        for (int d = 0; d < 2; ++d)
            c[d] = cell[d] > 0 ? std::clamp(int((p[d] - box.min()[d]) / cell[d]), 0, cells - 1) : 0;
        return c;
    };
    std::vector<std::vector<uint32_t>> grid(size_t(cells) * size_t(cells));
    for (size_t k = 0; k < n; ++k)
        if (!(area(k) > eps)) {
            const Eigen::Vector2i c = cell_of(poly[k].uv);
            grid[size_t(c.y()) * size_t(cells) + size_t(c.x())].push_back(uint32_t(k));
        }
    auto is_ear = [&](size_t k, bool degenerate) {
        const double a2 = area(k);
        if (degenerate ? !(a2 >= -eps) : !(a2 > eps)) return false;
        const size_t pk = prev[k], nk = next[k];
        const Vector2d &a = poly[pk].uv, &b = poly[k].uv, &c = poly[nk].uv;
        Eigen::AlignedBox2d tb;
        tb.extend(a), tb.extend(b), tb.extend(c);
        const Eigen::Vector2i lo = cell_of(tb.min()), hi = cell_of(tb.max());
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x)
                for (uint32_t j : grid[size_t(y) * size_t(cells) + size_t(x)]) {
                    if (!alive[j] || j == k || j == pk || j == nk) continue;
                    const Vector2d& p = poly[j].uv;
                    if (p == a || p == b || p == c) continue;
                    if (inside_triangle(p, a, b, c)) return false;
                }
        return true;
    };
    size_t remaining = n, k = 0, since = 0;
    bool degenerate = false;
    while (remaining > 3) {
        if (is_ear(k, degenerate)) {
            out.push_back({uint32_t(prev[k]), uint32_t(k), uint32_t(next[k])});
            alive[k] = 0;
            next[prev[k]] = next[k];
            prev[next[k]] = prev[k];
            k = prev[k];
            --remaining;
            since = 0;
            degenerate = false;
            continue;
        }
        k = next[k];
        if (++since > remaining) {
            if (degenerate) return false;  // not even a flat ear: the polygon crosses itself
            degenerate = true;
            since = 0;
        }
    }
    out.push_back({uint32_t(prev[k]), uint32_t(k), uint32_t(next[k])});
    return true;
}

class SolidTessellator {
public:
    SolidTessellator(const Brep& b, const Tolerance& tol, SolidMesh& out) : b_(b), tol_(tol), out_(out) {}

    void face(const Face& f, bool reversed) {
        const Surface& s = f.surface;
        if (s.kind == Surface::Kind::Unsupported) {
            fail(f, "its surface (" + s.type + ") is not one mbx reads");
            return;
        }
        if (f.bounds.empty()) {
            fail(f, "it has no bound");
            return;
        }
        const Vector2d periods = surface_periods(s);
        // Each bound as uv points, unrolled along the loop; a loop that winds
        // round a periodic direction, or a vertex loop (a pole), is open in uv.
        std::vector<std::vector<UvPoint>> closed_loops, wrapping;
        std::vector<UvPoint> poles;
        for (const Loop& l : f.bounds) {
            if (l.kind == Loop::Kind::Vertex) {
                poles.push_back({surface_parameters(s, b_.vertices[l.vertex].point), point_of_vertex(l.vertex)});
                continue;
            }
            std::vector<uint32_t> pts = loop_points(l);
            if (pts.size() < 2) continue;
            std::vector<UvPoint> uv = unroll(s, pts);
            const Vector2d turn = uv.size() > 1 ? Vector2d(uv.back().uv - uv.front().uv) : Vector2d::Zero();
            // Closing point back onto the first: dropped (the loop closes on itself).
            const bool winds_u = periods.x() > 0 && std::abs(std::abs(turn.x()) - periods.x()) < 0.5 * periods.x();
            const bool winds_v = periods.y() > 0 && std::abs(std::abs(turn.y()) - periods.y()) < 0.5 * periods.y();
            if (winds_u || winds_v) {
                wrapping.push_back(uv);  // keeps its closing point: the seam joins the two copies
            } else {
                uv.pop_back();
                closed_loops.push_back(uv);
            }
        }
        std::vector<UvPoint> outer;
        std::vector<std::vector<UvPoint>> holes;
        if (!wrapping.empty()) {
            // A band round the surface: the first wrapping loop, a seam to the
            // other wrapping loop (or to the pole), that loop the other way, the
            // seam back. Both seams are one curve on the surface.
            const std::vector<UvPoint>& a = wrapping[0];
            std::vector<UvPoint> band(a.begin(), a.end());
            const Vector2d shift = a.back().uv - a.front().uv;
            if (wrapping.size() >= 2) {
                std::vector<UvPoint> other = wrapping[1];
                // The other loop traversed against the first, starting at its
                // point nearest the first's end.
                const Vector2d other_turn = other.back().uv - other.front().uv;
                if (other_turn.dot(shift) > 0) std::reverse(other.begin(), other.end());
                other.pop_back();
                size_t start = 0;
                for (size_t k = 1; k < other.size(); ++k)
                    if ((other[k].uv - a.back().uv).norm() < (other[start].uv - a.back().uv).norm()) start = k;
                std::rotate(other.begin(), other.begin() + long(start), other.end());
                // Bring it next to the first loop's end (whole periods only).
                Vector2d offset = a.back().uv - other[0].uv;
                for (int d = 0; d < 2; ++d)
                    offset[d] = periods[d] > 0 ? periods[d] * std::round(offset[d] / periods[d]) : 0;
                for (UvPoint& p : other) p.uv += offset;
                for (const UvPoint& p : other) band.push_back(p);
                UvPoint closing = other[0];
                closing.uv -= shift;  // the other loop's first point again, a period on
                band.push_back(closing);  // the seam back to a's first point closes the polygon
                for (size_t w = 2; w < wrapping.size(); ++w) holes.push_back(wrapping[w]);
            } else if (!poles.empty()) {
                UvPoint pole = poles[0];
                band.push_back({Vector2d(a.back().uv.x(), pole.uv.y()), pole.point});
                band.push_back({Vector2d(a.front().uv.x(), pole.uv.y()), pole.point});
            } else {
                // Wrapping once with nothing to close against: a pole of the
                // surface itself (a sphere's cap bounded by one circle).
                const double v_pole = pole_v(s, a);
                if (std::isnan(v_pole)) {
                    fail(f, "a bound winds round the surface and nothing closes it");
                    return;
                }
                const uint32_t apex = add_point(surface_point(s, a.front().uv.x(), v_pole));
                band.push_back({Vector2d(a.back().uv.x(), v_pole), apex});
                band.push_back({Vector2d(a.front().uv.x(), v_pole), apex});
            }
            outer = band;
            if (band.size() >= 2 && (band.back().uv - band.front().uv).norm() < 1e-12 && band.back().point == band.front().point)
                outer.pop_back();
            for (auto& l : closed_loops) holes.push_back(l);
        } else {
            if (closed_loops.empty()) {
                fail(f, "no bound gives a polygon");
                return;
            }
            // The outer bound is the one of largest area (FACE_OUTER_BOUND is optional).
            size_t o = 0;
            for (size_t k = 1; k < closed_loops.size(); ++k)
                if (std::abs(signed_area(closed_loops[k])) > std::abs(signed_area(closed_loops[o]))) o = k;
            outer = closed_loops[o];
            for (size_t k = 0; k < closed_loops.size(); ++k)
                if (k != o) holes.push_back(closed_loops[k]);
            // Holes brought within a period of the outer loop.
            for (auto& h : holes) {
                Vector2d offset = outer[0].uv - h[0].uv;
                for (int d = 0; d < 2; ++d) offset[d] = periods[d] > 0 ? periods[d] * std::round(offset[d] / periods[d]) : 0;
                for (UvPoint& p : h) p.uv += offset;
            }
        }
        // Counter-clockwise outer, clockwise holes; the face's side from the
        // surface normal, the face's sense and the shell's.
        const bool flipped_uv = signed_area(outer) < 0;
        if (flipped_uv) std::reverse(outer.begin(), outer.end());
        for (auto& h : holes)
            if (signed_area(h) > 0) std::reverse(h.begin(), h.end());
        // A parameter plane scaled to lengths, so that ears are judged by shape.
        scale_ = parameter_scale(s, outer);
        for (UvPoint& p : outer) p.uv = p.uv.cwiseProduct(scale_);
        for (auto& h : holes)
            for (UvPoint& p : h) p.uv = p.uv.cwiseProduct(scale_);
        const std::vector<UvPoint> polygon = bridge_holes(outer, holes);
        std::vector<std::array<uint32_t, 3>> positions;
        if (!ear_clip(polygon, positions)) {
            fail(f, "its bounds do not make a simple polygon in the surface's parameters");
            return;
        }
        // Nodes: a mesh point with one of its uvs (a seam or pole point has
        // several, one per side); the polygon's positions become nodes.
        nodes_.clear();
        std::map<std::pair<uint32_t, std::pair<double, double>>, uint32_t> node_of;
        std::vector<uint32_t> node_at(polygon.size());
        for (size_t k = 0; k < polygon.size(); ++k) {
            const auto key = std::make_pair(polygon[k].point, std::make_pair(polygon[k].uv.x(), polygon[k].uv.y()));
            auto it = node_of.find(key);
            if (it == node_of.end()) {
                it = node_of.emplace(key, uint32_t(nodes_.size())).first;
                nodes_.push_back(polygon[k]);
            }
            node_at[k] = it->second;
        }
        std::vector<std::array<uint32_t, 3>> tris;
        for (const auto& t : positions) tris.push_back({node_at[t[0]], node_at[t[1]], node_at[t[2]]});
        std::vector<std::pair<uint32_t, uint32_t>> boundary;
        for (size_t k = 0; k < polygon.size(); ++k) boundary.emplace_back(node_at[k], node_at[(k + 1) % polygon.size()]);
        refine(s, tris, boundary);
        const bool flip = !f.same_sense != reversed;
        for (const auto& tn : tris) {
            std::array<uint32_t, 3> t = {nodes_[tn[0]].point, nodes_[tn[1]].point, nodes_[tn[2]].point};
            const Vector3d &p0 = out_.mesh.points[t[0]], &p1 = out_.mesh.points[t[1]], &p2 = out_.mesh.points[t[2]];
            // (a triangle with two corners at one pole has no area: its edges are its neighbours')
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || (p1 - p0).cross(p2 - p0).squaredNorm() == 0) continue;
            if (flip) std::swap(t[1], t[2]);
            out_.mesh.triangles.push_back(t);
        }
        ++out_.faces_meshed;
    }

    uint32_t add_point(const Vector3d& p) {
        out_.mesh.points.push_back(p);
        return uint32_t(out_.mesh.points.size() - 1);
    }

private:
    void fail(const Face& f, const std::string& why) {
        ++out_.faces_failed;
        out_.problems.push_back({0, f.entity, "face not meshed: " + why});
    }

    uint32_t point_of_vertex(uint32_t v) {
        auto it = vertex_point_.find(v);
        if (it != vertex_point_.end()) return it->second;
        const uint32_t k = add_point(b_.vertices[v].point);
        vertex_point_[v] = k;
        return k;
    }

    // The mesh points of an edge, discretised once, from its start to its end.
    const std::vector<uint32_t>& edge_points(uint32_t e) {
        auto it = edge_points_.find(e);
        if (it != edge_points_.end()) return it->second;
        const Edge& edge = b_.edges[e];
        const std::vector<Vector3d> pts = discretise(b_, edge, tol_);
        std::vector<uint32_t> ids;
        ids.push_back(point_of_vertex(edge.start));
        for (size_t k = 1; k + 1 < pts.size(); ++k) ids.push_back(add_point(pts[k]));
        ids.push_back(point_of_vertex(edge.end));
        return edge_points_.emplace(e, std::move(ids)).first->second;
    }

    // The loop's mesh points in order, the first repeated at the end.
    std::vector<uint32_t> loop_points(const Loop& l) {
        std::vector<uint32_t> out;
        if (l.kind == Loop::Kind::Poly) {
            for (const Vector3d& p : l.polygon) out.push_back(poly_point(p));
        } else {
            for (const OrientedEdge& oe : l.edges) {
                std::vector<uint32_t> pts = edge_points(oe.edge);
                if (!oe.forward) std::reverse(pts.begin(), pts.end());
                for (size_t k = out.empty() ? 0 : 1; k < pts.size(); ++k) out.push_back(pts[k]);
            }
        }
        if (!l.orientation) std::reverse(out.begin(), out.end());
        if (l.kind == Loop::Kind::Poly && !out.empty()) out.push_back(out.front());
        return out;
    }

    uint32_t poly_point(const Vector3d& p) {
        for (uint32_t k = 0; k < poly_points_.size(); ++k)
            if (out_.mesh.points[poly_points_[k]] == p) return poly_points_[k];
        poly_points_.push_back(add_point(p));
        return poly_points_.back();
    }

    // Along the loop, each point's uv next to the previous one's; a point at a
    // pole (where u says nothing) takes its neighbour's u.
    std::vector<UvPoint> unroll(const Surface& s, const std::vector<uint32_t>& pts) {
        std::vector<UvPoint> out;
        for (size_t k = 0; k < pts.size(); ++k) {
            const Vector3d& p = out_.mesh.points[pts[k]];
            Vector2d uv = out.empty() ? surface_parameters(s, p) : surface_parameters(s, p, &out.back().uv);
            if (at_pole(s, uv) && !out.empty()) uv.x() = out.back().uv.x();
            out.push_back({uv, pts[k]});
        }
        // A pole first in the loop takes the u of the point after it.
        if (out.size() > 1 && at_pole(s, out[0].uv)) out[0].uv.x() = out[1].uv.x();
        return out;
    }

    static bool at_pole(const Surface& s, const Vector2d& uv) {
        switch (s.kind) {
            case Surface::Kind::Cone:
                return std::abs(s.radius + uv.y() * std::tan(s.semi_angle)) < 1e-9 * std::max(s.radius, 1e-3);
            case Surface::Kind::Sphere:
                return std::abs(std::abs(uv.y()) - M_PI / 2) < 1e-9;
            default:
                return false;
        }
    }

    // The v of the pole a once-wrapping loop leaves uncovered (sphere caps,
    // cones), or NaN.
    static double pole_v(const Surface& s, const std::vector<UvPoint>& loop) {
        double mean = 0;
        for (const UvPoint& p : loop) mean += p.uv.y();
        mean /= double(loop.size());
        const double turn = loop.back().uv.x() - loop.front().uv.x();
        if (s.kind == Surface::Kind::Sphere) return turn > 0 ? M_PI / 2 : -M_PI / 2;
        if (s.kind == Surface::Kind::Cone) return -s.radius / std::tan(s.semi_angle);
        (void)mean;
        return NAN;
    }

    // Lengths per unit of u and of v about the face.
    static Vector2d parameter_scale(const Surface& s, const std::vector<UvPoint>& loop) {
        Vector2d mean = Vector2d::Zero();
        for (const UvPoint& p : loop) mean += p.uv;
        mean /= double(std::max<size_t>(loop.size(), 1));
        const double h = 1e-6;
        const Vector3d p = surface_point(s, mean.x(), mean.y());
        double su = (surface_point(s, mean.x() + h, mean.y()) - p).norm() / h;
        double sv = (surface_point(s, mean.x(), mean.y() + h) - p).norm() / h;
        if (!(su > 1e-12)) su = 1;
        if (!(sv > 1e-12)) sv = 1;
        return {su, sv};
    }

    // The face's triangles in its (scaled) parameter plane with their
    // neighbours: adj[t][k] is the triangle across the edge from corner k to
    // corner k + 1 (-1 on the polygon's edges, which stay as they are).
    struct Adjacent {
        std::vector<std::array<uint32_t, 3>> tri;
        std::vector<std::array<int32_t, 3>> adj;
    };

    static Adjacent connect(const std::vector<std::array<uint32_t, 3>>& tris,
                            const std::vector<std::pair<uint32_t, uint32_t>>& polygon_edges) {
        auto key = [](uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32 | b) : (uint64_t(b) << 32 | a); };
        std::unordered_map<uint64_t, int> fixed;
        for (const auto& [a, b] : polygon_edges) fixed[key(a, b)]++;
        Adjacent m;
        m.tri = tris;
        m.adj.assign(tris.size(), {-1, -1, -1});
        std::unordered_map<uint64_t, std::pair<int32_t, int>> directed;  // (from, to) -> (triangle, corner)
        directed.reserve(tris.size() * 3);
        for (size_t t = 0; t < tris.size(); ++t)
            for (int k = 0; k < 3; ++k)
                directed[uint64_t(tris[t][size_t(k)]) << 32 | tris[t][size_t((k + 1) % 3)]] = {int32_t(t), k};
        for (size_t t = 0; t < tris.size(); ++t)
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = tris[t][size_t(k)], b = tris[t][size_t((k + 1) % 3)];
                if (fixed.count(key(a, b))) continue;
                const auto it = directed.find(uint64_t(b) << 32 | a);
                if (it != directed.end()) m.adj[t][size_t(k)] = it->second.first;
            }
        return m;
    }

    static int corner_of(const Adjacent& m, int32_t t, uint32_t a, uint32_t b) {
        for (int k = 0; k < 3; ++k)
            if (m.tri[size_t(t)][size_t(k)] == a && m.tri[size_t(t)][size_t((k + 1) % 3)] == b) return k;
        return -1;
    }

    static void repoint(Adjacent& m, int32_t t, int32_t from, int32_t to) {
        if (t < 0) return;
        for (int k = 0; k < 3; ++k)
            if (m.adj[size_t(t)][size_t(k)] == from) m.adj[size_t(t)][size_t(k)] = to;
    }

    // Whether the edge at corner k of t should be flipped (its opposite corner
    // across lies inside t's circumcircle, and the other diagonal lies inside
    // the quadrilateral).
    bool should_flip(const Adjacent& m, int32_t t, int k) const {
        const int32_t u = m.adj[size_t(t)][size_t(k)];
        if (u < 0) return false;
        const uint32_t a = m.tri[size_t(t)][size_t(k)], b = m.tri[size_t(t)][size_t((k + 1) % 3)],
                       c = m.tri[size_t(t)][size_t((k + 2) % 3)];
        const int ku = corner_of(m, u, b, a);
        if (ku < 0) return false;
        const uint32_t d = m.tri[size_t(u)][size_t((ku + 2) % 3)];
        if (c == d) return false;
        const Vector2d &A = nodes_[a].uv, &B = nodes_[b].uv, &C = nodes_[c].uv, &D = nodes_[d].uv;
        if (!(cross2(D - C, A - C) < 0 && cross2(D - C, B - C) > 0)) return false;
        const Vector2d ad = A - D, bd = B - D, cd = C - D;
        const double in_circle =
            ad.squaredNorm() * cross2(bd, cd) - bd.squaredNorm() * cross2(ad, cd) + cd.squaredNorm() * cross2(ad, bd);
        const double scale = ad.squaredNorm() + bd.squaredNorm() + cd.squaredNorm();
        return in_circle > 1e-12 * scale * scale;
    }

    // (a, b, c) and (b, a, d) become (a, d, c) and (d, b, c); returns the
    // edges now facing the quadrilateral's outside, to check again.
    void flip(Adjacent& m, int32_t t, int k, std::vector<std::pair<int32_t, int>>& check) {
        const int32_t u = m.adj[size_t(t)][size_t(k)];
        const uint32_t a = m.tri[size_t(t)][size_t(k)], b = m.tri[size_t(t)][size_t((k + 1) % 3)],
                       c = m.tri[size_t(t)][size_t((k + 2) % 3)];
        const int ku = corner_of(m, u, b, a);
        const uint32_t d = m.tri[size_t(u)][size_t((ku + 2) % 3)];
        const int32_t x1 = m.adj[size_t(t)][size_t((k + 1) % 3)], x2 = m.adj[size_t(t)][size_t((k + 2) % 3)];
        const int32_t y1 = m.adj[size_t(u)][size_t((ku + 1) % 3)], y2 = m.adj[size_t(u)][size_t((ku + 2) % 3)];
        m.tri[size_t(t)] = {a, d, c};
        m.adj[size_t(t)] = {y1, u, x2};
        m.tri[size_t(u)] = {d, b, c};
        m.adj[size_t(u)] = {y2, x1, t};
        repoint(m, x1, t, u);
        repoint(m, y1, u, t);
        check.push_back({t, 0});
        check.push_back({t, 2});
        check.push_back({u, 0});
        check.push_back({u, 1});
    }

    void legalise(Adjacent& m, std::vector<std::pair<int32_t, int>>& check) {
        // From a fan, reaching Delaunay takes up to the square of the count
        // of flips; each is a few operations.
        size_t guard = 0;
        const size_t limit = std::min<size_t>(200'000'000, 4 * m.tri.size() * m.tri.size() + 1000);
        while (!check.empty() && ++guard < limit) {
            const auto [t, k] = check.back();
            check.pop_back();
            if (should_flip(m, t, k)) flip(m, t, k, check);
        }
        check.clear();
    }

    // Lawson's flips to the constrained Delaunay triangulation (in the scaled
    // parameter plane: triangles as far from slivers as the bounds allow; a
    // sliver split at its middle folds over on a curved surface), then the
    // inner edges whose middle lies farther from the surface than the chord
    // tolerance split, each split legalised, until none is. The polygon's
    // edges are never split: they are the edges' discretisation, shared with
    // the neighbouring faces.
    void refine(const Surface& s, std::vector<std::array<uint32_t, 3>>& tris,
                const std::vector<std::pair<uint32_t, uint32_t>>& polygon_edges) {
        Adjacent m = connect(tris, polygon_edges);
        std::vector<std::pair<int32_t, int>> check;
        for (size_t t = 0; t < m.tri.size(); ++t)
            for (int k = 0; k < 3; ++k) check.push_back({int32_t(t), k});
        legalise(m, check);
        if (s.kind != Surface::Kind::Plane) {
            const size_t limit = m.tri.size() * 64 + 200000;
            auto to_surface = [&](const Vector2d& uv) { return surface_point(s, uv.x() / scale_.x(), uv.y() / scale_.y()); };
            for (int round = 0; round < 40 && m.tri.size() < limit; ++round) {
                std::vector<std::pair<int32_t, int>> split;
                for (size_t t = 0; t < m.tri.size(); ++t)
                    for (int k = 0; k < 3; ++k) {
                        const int32_t u = m.adj[t][size_t(k)];
                        if (u < int32_t(t)) continue;  // each inner edge once; polygon edges (-1) never
                        const UvPoint &a = nodes_[m.tri[t][size_t(k)]], &b = nodes_[m.tri[t][size_t((k + 1) % 3)]];
                        if (a.point == b.point) continue;
                        const Vector3d chord = 0.5 * (out_.mesh.points[a.point] + out_.mesh.points[b.point]);
                        if ((to_surface(0.5 * (a.uv + b.uv)) - chord).norm() > tol_.chord) split.push_back({int32_t(t), k});
                    }
                if (split.empty()) break;
                for (const auto& [t0, k0] : split) {
                    // The edge may have moved with earlier splits' flips: found again by its ends.
                    (void)k0;
                    const uint32_t a = m.tri[size_t(t0)][size_t(k0)], b = m.tri[size_t(t0)][size_t((k0 + 1) % 3)];
                    const int k = corner_of(m, t0, a, b);
                    if (k < 0 || m.adj[size_t(t0)][size_t(k)] < 0) continue;
                    split_edge(m, t0, k, to_surface, check);
                    legalise(m, check);
                }
            }
        }
        tris = m.tri;
    }

    template <class ToSurface>
    void split_edge(Adjacent& m, int32_t t, int k, const ToSurface& to_surface, std::vector<std::pair<int32_t, int>>& check) {
        const int32_t u = m.adj[size_t(t)][size_t(k)];
        const uint32_t a = m.tri[size_t(t)][size_t(k)], b = m.tri[size_t(t)][size_t((k + 1) % 3)],
                       c = m.tri[size_t(t)][size_t((k + 2) % 3)];
        const int ku = corner_of(m, u, b, a);
        if (ku < 0) return;
        const uint32_t d = m.tri[size_t(u)][size_t((ku + 2) % 3)];
        const int32_t x1 = m.adj[size_t(t)][size_t((k + 1) % 3)], x2 = m.adj[size_t(t)][size_t((k + 2) % 3)];
        const int32_t y1 = m.adj[size_t(u)][size_t((ku + 1) % 3)], y2 = m.adj[size_t(u)][size_t((ku + 2) % 3)];
        const Vector2d mid = 0.5 * (nodes_[a].uv + nodes_[b].uv);
        const uint32_t mn = uint32_t(nodes_.size());
        nodes_.push_back({mid, add_point(to_surface(mid))});
        const int32_t t2 = int32_t(m.tri.size()), u2 = t2 + 1;
        // t = (a, m, c), t2 = (m, b, c), u = (b, m, d), u2 = (m, a, d)
        m.tri[size_t(t)] = {a, mn, c};
        m.adj[size_t(t)] = {u2, t2, x2};
        m.tri.push_back({mn, b, c});
        m.adj.push_back({u, x1, t});
        m.tri[size_t(u)] = {b, mn, d};
        m.adj[size_t(u)] = {t2, u2, y2};
        m.tri.push_back({mn, a, d});
        m.adj.push_back({t, y1, u});
        repoint(m, x1, t, t2);
        repoint(m, y1, u, u2);
        check.push_back({t, 2});
        check.push_back({t2, 1});
        check.push_back({u, 2});
        check.push_back({u2, 1});
    }

    const Brep& b_;
    Tolerance tol_;
    SolidMesh& out_;
    Vector2d scale_ = Vector2d::Ones();
    std::unordered_map<uint32_t, uint32_t> vertex_point_;
    std::unordered_map<uint32_t, std::vector<uint32_t>> edge_points_;
    std::vector<uint32_t> poly_points_;
    std::vector<UvPoint> nodes_;  // the current face's (scaled) uv nodes
};

}  // namespace

std::vector<SolidMesh> tessellate(const Brep& b, const Tolerance& tolerance) {
    std::vector<SolidMesh> out;
    for (uint32_t k = 0; k < b.solids.size(); ++k) {
        const Solid& solid = b.solids[k];
        SolidMesh m;
        m.name = solid.name;
        m.solid = k;
        SolidTessellator t(b, tolerance, m);
        for (const Shell& sh : solid.shells)
            for (uint32_t f : sh.faces) t.face(b.faces[f], sh.reversed);
        out.push_back(std::move(m));
    }
    return out;
}

}  // namespace mbx_step
