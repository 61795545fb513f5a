#include "host_adapters/step/tessellate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
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
            // The bridge must leave P into the polygon: where P is a point met
            // twice (an earlier bridge's end), only one of its copies faces M.
            const Vector2d to_prev = outer[(c + outer.size() - 1) % outer.size()].uv - P,
                           to_next = outer[(c + 1) % outer.size()].uv - P, d = M - P;
            const bool convex = cross2(to_next, to_prev) >= 0;
            const bool inside = convex ? (cross2(to_next, d) > 0 && cross2(d, to_prev) > 0)
                                       : (cross2(to_next, d) > 0 || cross2(d, to_prev) > 0);
            if (!inside) continue;
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
    SolidTessellator(const Brep& b, const Solid& solid, const Tolerance& tol, SolidMesh& out)
        : b_(b), solid_(solid), tol_(tol), out_(out) {}

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
                // The closing point is the first again, unless the loop starts
                // at a pole it left with another u (then the pole row closes it).
                if ((uv.back().uv - uv.front().uv).norm() <= 1e-12 * (1 + uv.front().uv.norm())) uv.pop_back();
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
            // After the seam from a's end: the other loop and its first point
            // again a period on, or the pole row.
            std::vector<UvPoint> beyond;
            Vector2d seam_end;
            if (wrapping.size() >= 2) {
                std::vector<UvPoint> other = wrapping[1];
                // The other loop traversed against the first, starting at its
                // point nearest the first's end.
                const Vector2d other_turn = other.back().uv - other.front().uv;
                if (other_turn.dot(shift) > 0) std::reverse(other.begin(), other.end());
                other.pop_back();
                // (distances modulo the periods: the other loop was unrolled
                // from its own first point, maybe a period or more away)
                auto apart = [&](const Vector2d& p) {
                    Vector2d d = p - a.back().uv;
                    for (int k = 0; k < 2; ++k)
                        if (periods[k] > 0) d[k] = std::remainder(d[k], periods[k]);
                    return d.squaredNorm();
                };
                size_t start = 0;
                for (size_t k = 1; k < other.size(); ++k)
                    if (apart(other[k].uv) < apart(other[start].uv)) start = k;
                std::rotate(other.begin(), other.begin() + long(start), other.end());
                // (unrolled again from the new start: where it began there is a period's jump)
                for (size_t k = 1; k < other.size(); ++k)
                    for (int d = 0; d < 2; ++d)
                        if (periods[d] > 0)
                            other[k].uv[d] += periods[d] * std::round((other[k - 1].uv[d] - other[k].uv[d]) / periods[d]);
                // Bring it next to the first loop's end (whole periods only).
                Vector2d offset = a.back().uv - other[0].uv;
                for (int d = 0; d < 2; ++d)
                    offset[d] = periods[d] > 0 ? periods[d] * std::round(offset[d] / periods[d]) : 0;
                // On a surface periodic across the band too (a torus), the other
                // loop may sit a period either side: the face lies left of its
                // first loop seen from its outside (right of it in the surface's
                // own uv when the face is against the surface's normal).
                const int across_d = std::abs(shift.x()) >= std::abs(shift.y()) ? 1 : 0;
                if (periods[across_d] > 0) {
                    const double side = cross2(shift, other[0].uv + offset - a.back().uv);
                    const double want = f.same_sense ? 1.0 : -1.0;
                    if (side * want < 0) offset[across_d] += periods[across_d] * (shift[1 - across_d] > 0 ? want : -want) * (across_d == 1 ? 1.0 : -1.0);
                }
                for (UvPoint& p : other) p.uv += offset;
                seam_end = other[0].uv;
                beyond = other;
                UvPoint closing = other[0];
                closing.uv -= shift;  // the other loop's first point again, a period on
                beyond.push_back(closing);
                for (size_t w = 2; w < wrapping.size(); ++w) holes.push_back(wrapping[w]);
            } else {
                // Wrapping once: closed by a pole the bounds name (a vertex
                // loop) or by one of the surface's own (a sphere's cap bounded
                // by one circle).
                double v_pole = NAN;
                uint32_t apex = kUnresolved;
                if (!poles.empty()) {
                    v_pole = poles[0].uv.y();
                    apex = poles[0].point;
                } else {
                    v_pole = pole_v(s, a);
                    if (std::isnan(v_pole)) {
                        fail(f, "a bound winds round the surface and nothing closes it");
                        return;
                    }
                    apex = pole_point(surface_point(s, a.front().uv.x(), v_pole));
                }
                seam_end = Vector2d(a.back().uv.x(), v_pole);
                beyond.push_back({seam_end, apex});
                beyond.push_back({Vector2d(a.front().uv.x(), v_pole), apex});
            }
            // The seam is a curve on the surface (a sphere's meridian, a
            // torus's minor circle) that the face meets on both sides: its
            // points are made once and used by both copies, a period apart.
            const std::vector<UvPoint> across = seam_points(s, a.back().uv, seam_end);
            band.insert(band.end(), across.begin(), across.end());
            band.insert(band.end(), beyond.begin(), beyond.end());
            for (auto it = across.rbegin(); it != across.rend(); ++it) band.push_back({it->uv - shift, it->point});
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
        // Counter-clockwise outer, clockwise holes. The face's side is the
        // one its bounds say (the face lies left of its outer bound seen from
        // its outside): where a file's same-sense flag disagrees with its
        // bounds, the bounds keep the shell consistent (as OpenCASCADE reads
        // it), since each edge is walked once each way by its two faces.
        const bool flipped_uv = signed_area(outer) < 0;
        if (flipped_uv) std::reverse(outer.begin(), outer.end());
        for (auto& h : holes)
            if (signed_area(h) > 0) std::reverse(h.begin(), h.end());
        // A parameter plane scaled to lengths, so that ears are judged by shape.
        scale_ = parameter_scale(s, outer).cwiseQuotient(stretch(s, outer));
        for (UvPoint& p : outer) p.uv = p.uv.cwiseProduct(scale_);
        for (auto& h : holes)
            for (UvPoint& p : h) p.uv = p.uv.cwiseProduct(scale_);
        const std::vector<UvPoint> polygon = bridge_holes(outer, holes);
        for (const UvPoint& p : polygon)
            if (!p.uv.allFinite() || !out_.mesh.points[p.point].allFinite()) {
                fail(f, "a point of its bounds is not a number or has no parameters on its surface");
                return;
            }
        // Bounds that are not on the surface at all (a circle placed off a
        // torus) are no exporter's gap, which is micrometres on a part of
        // millimetres: refining against them never meets the chord and fills
        // the budget with folds (a 2 kB file made 4.8 million triangles of
        // negative volume). A tenth of the bounds' own extent is the line.
        // (A plane is never refined, and a faceted face's plane is its loop's.)
        if (s.kind != Surface::Kind::Plane) {
            Eigen::AlignedBox3d extent;
            double gap = 0;
            for (const UvPoint& p : polygon) {
                const Vector3d& q = out_.mesh.points[p.point];
                extent.extend(q);
                const Vector2d at = p.uv.cwiseQuotient(scale_);
                const double d = (surface_point(s, at.x(), at.y()) - q).norm();
                gap = std::max(gap, std::isfinite(d) ? d : INFINITY);
            }
            const double size = extent.isEmpty() ? 0.0 : extent.diagonal().norm();
            if (size > 0 && !(gap <= 0.1 * size)) {
                std::ostringstream why;
                why.precision(3);
                why << "its bounds lie up to " << gap << " m off its surface, " << gap / size
                    << " of their own extent: they are not on it";
                fail(f, why.str());
                return;
            }
        }
        std::vector<std::array<uint32_t, 3>> positions;
        if (!ear_clip(polygon, positions)) {
            fail(f, "its bounds do not make a simple polygon in the surface's parameters");
            return;
        }
        // Nodes: a mesh point with one of its uvs (a seam or pole point has
        // several, one per side); the polygon's positions become nodes.
        nodes_.clear();
        on_surface_.clear();
        std::map<std::pair<uint32_t, std::pair<double, double>>, uint32_t> node_of;
        std::vector<uint32_t> node_at(polygon.size());
        for (size_t k = 0; k < polygon.size(); ++k) {
            const auto key = std::make_pair(polygon[k].point, std::make_pair(polygon[k].uv.x(), polygon[k].uv.y()));
            auto it = node_of.find(key);
            if (it == node_of.end()) {
                it = node_of.emplace(key, uint32_t(nodes_.size())).first;
                nodes_.push_back(polygon[k]);
                on_surface_.push_back(surface_point(s, polygon[k].uv.x() / scale_.x(), polygon[k].uv.y() / scale_.y()));
            }
            node_at[k] = it->second;
        }
        std::vector<std::array<uint32_t, 3>> tris;
        for (const auto& t : positions) tris.push_back({node_at[t[0]], node_at[t[1]], node_at[t[2]]});
        std::vector<std::pair<uint32_t, uint32_t>> boundary;
        for (size_t k = 0; k < polygon.size(); ++k) boundary.emplace_back(node_at[k], node_at[(k + 1) % polygon.size()]);
        if (!refine(s, tris, boundary))
            out_.problems.push_back({f.line, f.id,
                                     "face meshed coarser than the chord tolerance: its refinement stopped at " +
                                         std::to_string(tris.size()) + " triangles"});
        // A point that is not one (a malformed coordinate, a surface that
        // evaluates to NaN) makes the face a finding, never a mesh with NaN in it.
        for (const auto& tn : tris)
            for (uint32_t n : tn)
                if (!out_.mesh.points[nodes_[n].point].allFinite()) {
                    fail(f, "a point of it is not a number (see the geometry's problems)");
                    return;
                }
        const bool flip = flipped_uv != reversed;
        if (flipped_uv == f.same_sense) ++out_.sense_disagreements;
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
        out_.problems.push_back({f.line, f.id, "face not meshed: " + why});
    }

    // The points inside a seam from `from` to `to` (a straight line in uv),
    // close enough for the chord and the angle tolerance.
    std::vector<UvPoint> seam_points(const Surface& s, const Vector2d& from, const Vector2d& to) {
        std::vector<double> at;
        auto point_at = [&](double t) {
            const Vector2d uv = from + t * (to - from);
            return surface_point(s, uv.x(), uv.y());
        };
        struct Span {
            double t0, t1;
            Vector3d p0, p1;
            int depth;
        };
        std::vector<Span> stack = {{0, 1, point_at(0), point_at(1), 0}};
        while (!stack.empty()) {
            const Span sp = stack.back();
            stack.pop_back();
            const double tm = 0.5 * (sp.t0 + sp.t1);
            const Vector3d pm = point_at(tm);
            const Vector3d d0 = pm - sp.p0, d1 = sp.p1 - pm;
            const double turn = d0.norm() > 0 && d1.norm() > 0 ? std::acos(std::clamp(d0.normalized().dot(d1.normalized()), -1.0, 1.0)) : 0;
            if (sp.depth < 20 && ((pm - 0.5 * (sp.p0 + sp.p1)).norm() > tol_.chord || turn > 0.5 * tol_.angle)) {
                stack.push_back({tm, sp.t1, pm, sp.p1, sp.depth + 1});  // (the right half after the left)
                stack.push_back({sp.t0, tm, sp.p0, pm, sp.depth + 1});
                at.push_back(tm);
            }
        }
        std::sort(at.begin(), at.end());
        std::vector<UvPoint> out;
        for (double t : at) out.push_back({from + t * (to - from), add_point(point_at(t))});
        return out;
    }

    // A pole the face's bounds do not name may still be a vertex of the
    // solid (a cone's apex where an edge of another face ends): then it is
    // that vertex's point, so that the faces meeting there share it.
    uint32_t pole_point(const Vector3d& p) {
        uint32_t best = kUnresolved;
        double nearest = tol_.chord;
        for (const Shell& sh : solid_.shells)
            for (uint32_t fi : sh.faces)
                for (const Loop& l : b_.faces[fi].bounds) {
                    auto consider = [&](uint32_t v) {
                        const double d = (b_.vertices[v].point - p).norm();
                        if (d <= nearest) nearest = d, best = v;
                    };
                    if (l.kind == Loop::Kind::Vertex) consider(l.vertex);
                    for (const OrientedEdge& oe : l.edges) consider(b_.edges[oe.edge].start), consider(b_.edges[oe.edge].end);
                }
        return best == kUnresolved ? add_point(p) : point_of_vertex(best);
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

    // Along the loop, each point's uv next to the previous one's. A point at
    // a pole (where u says nothing) is the pole row's two ends: the u it
    // arrives with and the u it leaves with (one copy where they agree), so
    // that the generator lines to a cone's apex stay straight in uv.
    std::vector<UvPoint> unroll(const Surface& s, std::vector<uint32_t> pts) {
        // A pole's u says nothing, so unrolling through it may land the next
        // point a half turn off: a closed loop through a pole is unrolled from
        // the point after it, so that the pole comes last.
        const bool has_poles = s.kind == Surface::Kind::Cone || s.kind == Surface::Kind::Sphere;
        if (has_poles && pts.size() > 2 && pts.front() == pts.back())
            for (size_t k = 0; k + 1 < pts.size(); ++k)
                if (at_pole(s, surface_parameters(s, out_.mesh.points[pts[k]]))) {
                    std::vector<uint32_t> turned(pts.begin() + long(k) + 1, pts.end() - 1);
                    turned.insert(turned.end(), pts.begin(), pts.begin() + long(k) + 1);
                    turned.push_back(turned.front());
                    pts = std::move(turned);
                    break;
                }
        std::vector<UvPoint> raw;
        for (size_t k = 0; k < pts.size(); ++k) {
            const Vector3d& p = out_.mesh.points[pts[k]];
            raw.push_back({raw.empty() ? surface_parameters(s, p) : surface_parameters(s, p, &raw.back().uv), pts[k]});
        }
        std::vector<char> pole(raw.size());
        for (size_t k = 0; k < raw.size(); ++k) pole[k] = at_pole(s, raw[k].uv);
        // The closing point after the pole is the first point: its own uv
        // (unrolled from the pole's it could land a half turn off).
        if (raw.size() > 2 && pts.front() == pts.back() && pole[raw.size() - 2]) raw.back().uv = raw.front().uv;
        // The u of the nearest point before (or after) k that is not a pole.
        auto u_near = [&](size_t k, int step) {
            for (long j = long(k) + step; j >= 0 && j < long(raw.size()); j += step)
                if (!pole[size_t(j)]) return raw[size_t(j)].uv.x();
            return raw[k].uv.x();
        };
        std::vector<UvPoint> out;
        for (size_t k = 0; k < raw.size(); ++k) {
            if (!pole[k]) {
                out.push_back(raw[k]);
                continue;
            }
            const double in = k == 0 ? u_near(k, +1) : u_near(k, -1);
            const double on = k + 1 == raw.size() ? in : u_near(k, +1);
            out.push_back({Vector2d(in, raw[k].uv.y()), raw[k].point});
            if (std::abs(on - in) > 1e-12 * (1 + std::abs(in))) out.push_back({Vector2d(on, raw[k].uv.y()), raw[k].point});
        }
        return out;
    }

    static bool at_pole(const Surface& s, const Vector2d& uv) {
        switch (s.kind) {
            case Surface::Kind::Cone:
                return std::abs(s.radius + uv.y() * std::tan(s.semi_angle)) < 1e-7 * std::max(s.radius, 1e-3);
            case Surface::Kind::Sphere:
                return std::abs(std::abs(uv.y()) - M_PI / 2) < 1e-8;
            default:
                return false;
        }
    }

    bool pole_node(const Surface& s, const UvPoint& n) const { return at_pole(s, n.uv.cwiseQuotient(scale_)); }

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

    // How much longer a triangle may be along u and along v than across,
    // for the chord to be met with fewer triangles: along a cylinder's or a
    // cone's straight lines the surface does not curve, and round a torus's
    // major circle it curves less than round its minor one (the chord
    // allows edges in proportion to 1/sqrt(curvature)). Capped, since long
    // triangles meet the bounds' short segments at poor angles.
    static Vector2d stretch(const Surface& s, const std::vector<UvPoint>& loop) {
        constexpr double kMost = 4;
        if (s.kind == Surface::Kind::Cylinder || s.kind == Surface::Kind::Cone) return {1, kMost};
        if (s.kind == Surface::Kind::Torus && s.minor_radius > 0) {
            double v = 0;
            for (const UvPoint& p : loop) v += p.uv.y();
            v /= double(std::max<size_t>(loop.size(), 1));
            // Normal curvatures round the major circle and round the minor one.
            const double across = std::abs(std::cos(v)) / std::max(std::abs(s.radius + s.minor_radius * std::cos(v)), 1e-300);
            const double around = 1 / s.minor_radius;
            const double ratio = across > 0 ? std::sqrt(around / across) : kMost;
            return {std::clamp(ratio, 1.0, kMost), 1};
        }
        return {1, 1};
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
        std::vector<char> touched;  // made or changed since the refinement's last look
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

    static void mark(Adjacent& m, int32_t t) {
        if (m.touched.size() <= size_t(t)) m.touched.resize(size_t(t) + 1, 0);
        m.touched[size_t(t)] = 1;
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
        mark(m, t), mark(m, u);
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

    // How far q (a point of the mesh) lies from the surface about uv (in
    // the scaled parameter plane, where q's triangle or edge spans `reach`).
    // The surface's point at uv bounds it from above, and is the answer
    // where it already lies within the tolerance; otherwise q's foot point
    // (beside a bound, the surface at uv may lie far from a triangle that
    // is close to it: a bound's straight line in uv is not its curve),
    // unless that foot lies elsewhere on the surface than q's own piece of
    // it (a chord across most of a turn ends near the surface again).
    double off_surface(const Surface& s, const Vector3d& q, const Vector2d& uv, double reach) const {
        const Vector2d at = uv.cwiseQuotient(scale_);
        const double at_uv = (surface_point(s, at.x(), at.y()) - q).norm();
        if (!(at_uv > tol_.chord)) return at_uv;
        const Vector2d foot = surface_foot(s, q, at, 0.01 * tol_.chord);
        if (!foot.allFinite() || (foot - at).cwiseProduct(scale_).norm() > 0.25 * reach) return at_uv;
        const double d = (surface_point(s, foot.x(), foot.y()) - q).norm();
        return std::isfinite(d) ? std::min(d, at_uv) : at_uv;
    }

    // Lawson's flips to the constrained Delaunay triangulation (in the scaled
    // parameter plane: triangles as far from slivers as the bounds allow; a
    // sliver split at its middle folds over on a curved surface), then the
    // inner edges whose middle lies farther from the surface than the chord
    // tolerance split, each split legalised, until none is. The polygon's
    // edges are never split: they are the edges' discretisation, shared with
    // the neighbouring faces.
    // Returns false where the refinement stopped at its budget short of the tolerance.
    bool refine(const Surface& s, std::vector<std::array<uint32_t, 3>>& tris,
                const std::vector<std::pair<uint32_t, uint32_t>>& polygon_edges) {
        bool within = true;
        Adjacent m = connect(tris, polygon_edges);
        std::vector<std::pair<int32_t, int>> check;
        for (size_t t = 0; t < m.tri.size(); ++t)
            for (int k = 0; k < 3; ++k) check.push_back({int32_t(t), k});
        legalise(m, check);
        if (s.kind != Surface::Kind::Plane) {
            const size_t limit = m.tri.size() + tol_.face_triangle_budget;
            auto to_surface = [&](const Vector2d& uv) { return surface_point(s, uv.x() / scale_.x(), uv.y() / scale_.y()); };
            // A polygon edge is the chord of its curve, within the tolerance of
            // the curve but maybe not of this surface (an exporter's curve lies
            // only within its own tolerance of the surface): a triangle on it
            // is allowed what the edge shows, else no split beside it would end.
            std::vector<double> allowance(nodes_.size(), 0.0);
            for (const auto& [a, b] : polygon_edges) {
                if (nodes_[a].point == nodes_[b].point) continue;
                const double e = off_surface(s, 0.5 * (on_surface_[a] + on_surface_[b]), 0.5 * (nodes_[a].uv + nodes_[b].uv),
                                             (nodes_[a].uv - nodes_[b].uv).norm());
                allowance[a] = std::max(allowance[a], e);
                allowance[b] = std::max(allowance[b], e);
            }
            auto allowed = [&](const std::array<uint32_t, 3>& t) {
                double e = 0;
                for (uint32_t n : t)
                    if (n < allowance.size()) e = std::max(e, allowance[n]);
                return std::max(tol_.chord, e);
            };
            // Each round looks only at the edges of triangles the last one
            // made or changed: the others were within the tolerance already.
            m.touched.assign(m.tri.size(), 1);
            within = false;
            for (int round = 0; round < 60 && m.tri.size() < limit; ++round) {
                std::vector<std::pair<int32_t, int>> split;
                std::vector<char> touched(m.tri.size(), 0);
                std::swap(touched, m.touched);
                for (size_t t = 0; t < m.tri.size(); ++t)
                    for (int k = 0; k < 3; ++k) {
                        const int32_t u = m.adj[t][size_t(k)];
                        if (u < int32_t(t)) continue;  // each inner edge once; polygon edges (-1) never
                        if (!touched[t] && !touched[size_t(u)]) continue;
                        const uint32_t na = m.tri[t][size_t(k)], nb = m.tri[t][size_t((k + 1) % 3)];
                        const UvPoint &a = nodes_[na], &b = nodes_[nb];
                        if (a.point == b.point) continue;
                        // From a pole (a cone's apex, a sphere's pole) the surface
                        // runs along the other end's u: a pole node's own u says nothing.
                        Vector2d mid = 0.5 * (a.uv + b.uv);
                        if (pole_node(s, a)) mid.x() = b.uv.x();
                        else if (pole_node(s, b)) mid.x() = a.uv.x();
                        // (the chord between the surface's points at the ends' uv: an
                        // edge point lies only within the exporter's tolerance of
                        // the surface, which no splitting near it would remove)
                        const Vector3d middle = 0.5 * (on_surface_[na] + on_surface_[nb]);
                        if (off_surface(s, middle, mid, (a.uv - b.uv).norm()) > allowed({na, nb, na})) split.push_back({int32_t(t), k});
                    }
                // Edge middles within the chord still leave a triangle's
                // inside up to 4/3 of it away (a sphere, an equilateral
                // triangle): its centroid is checked too. Its longest edge is
                // split, or where that is the polygon's, a node put at its
                // centroid (a shorter edge split beside a straight run of the
                // bounds halves towards it into slivers).
                std::vector<std::pair<int32_t, std::array<uint32_t, 3>>> centres;
                for (size_t t = 0; t < m.tri.size(); ++t) {
                    if (!touched[t]) continue;
                    const auto& tri = m.tri[t];
                    Vector3d centroid = Vector3d::Zero();
                    double longest_uv = 0;
                    int longest = 0;
                    for (int k = 0; k < 3; ++k) {
                        centroid += on_surface_[tri[size_t(k)]] / 3;
                        const double l = (nodes_[tri[size_t(k)]].uv - nodes_[tri[size_t((k + 1) % 3)]].uv).norm();
                        if (l > longest_uv) longest_uv = l, longest = k;
                    }
                    if (off_surface(s, centroid, centre_uv(s, tri), longest_uv) <= allowed(tri)) continue;
                    if (m.adj[t][size_t(longest)] >= 0) split.push_back({int32_t(t), longest});
                    else centres.push_back({int32_t(t), tri});
                }
                if (split.empty() && centres.empty()) {
                    within = true;
                    break;
                }
                for (const auto& [t0, tri] : centres) {
                    if (m.tri[size_t(t0)] != tri) continue;  // changed by an earlier insertion's flips
                    insert_centre(m, t0, centre_uv(s, tri), to_surface, check);
                    legalise(m, check);
                }
                for (const auto& [t0, k0] : split) {
                    // The edge may have moved with earlier splits' flips: found again by its ends.
                    const uint32_t a = m.tri[size_t(t0)][size_t(k0)], b = m.tri[size_t(t0)][size_t((k0 + 1) % 3)];
                    const int k = corner_of(m, t0, a, b);
                    if (k < 0 || m.adj[size_t(t0)][size_t(k)] < 0) continue;
                    split_edge(m, t0, k, to_surface, check);
                    legalise(m, check);
                }
            }
        }
        tris = m.tri;
        return within;
    }

    // A triangle's middle in the (scaled) parameter plane; a pole corner's u
    // says nothing (the surface runs along the other corners' u there).
    Vector2d centre_uv(const Surface& s, const std::array<uint32_t, 3>& tri) const {
        Vector2d centre = Vector2d::Zero();
        double u = 0;
        int off_pole = 0;
        for (uint32_t n : tri) {
            centre += nodes_[n].uv / 3;
            if (!pole_node(s, nodes_[n])) u += nodes_[n].uv.x(), ++off_pole;
        }
        if (off_pole > 0 && off_pole < 3) centre.x() = u / off_pole;
        return centre;
    }

    // (a, b, c) becomes (a, b, n), (b, c, n), (c, a, n) with n at uv.
    template <class ToSurface>
    void insert_centre(Adjacent& m, int32_t t, const Vector2d& uv, const ToSurface& to_surface,
                       std::vector<std::pair<int32_t, int>>& check) {
        const auto [a, b, c] = m.tri[size_t(t)];
        const auto [x0, x1, x2] = m.adj[size_t(t)];
        const uint32_t n = uint32_t(nodes_.size());
        const Vector3d p = to_surface(uv);
        nodes_.push_back({uv, add_point(p)});
        on_surface_.push_back(p);
        const int32_t t2 = int32_t(m.tri.size()), t3 = t2 + 1;
        m.tri[size_t(t)] = {a, b, n};
        m.adj[size_t(t)] = {x0, t2, t3};
        m.tri.push_back({b, c, n});
        m.adj.push_back({x1, t3, t});
        m.tri.push_back({c, a, n});
        m.adj.push_back({x2, t, t2});
        repoint(m, x1, t, t2);
        repoint(m, x2, t, t3);
        mark(m, t), mark(m, t2), mark(m, t3);
        check.push_back({t, 0});
        check.push_back({t2, 0});
        check.push_back({t3, 0});
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
        const Vector3d p = to_surface(mid);
        nodes_.push_back({mid, add_point(p)});
        on_surface_.push_back(p);
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
        mark(m, t), mark(m, u), mark(m, t2), mark(m, u2);
        check.push_back({t, 2});
        check.push_back({t2, 1});
        check.push_back({u, 2});
        check.push_back({u2, 1});
    }

    const Brep& b_;
    const Solid& solid_;
    Tolerance tol_;
    SolidMesh& out_;
    Vector2d scale_ = Vector2d::Ones();
    std::unordered_map<uint32_t, uint32_t> vertex_point_;
    std::unordered_map<uint32_t, std::vector<uint32_t>> edge_points_;
    std::vector<uint32_t> poly_points_;
    std::vector<UvPoint> nodes_;  // the current face's (scaled) uv nodes
    std::vector<Vector3d> on_surface_;  // the surface's point at each node's uv
};

// The diagonal of a solid's bounding box, from its edges (coarsely
// discretised, so that an arc's bulge counts) and faceted loops (a sphere's or
// torus's radius where there is nothing else): what a relative chord
// tolerance is relative to.
double solid_size(const Brep& b, const Solid& solid) {
    Eigen::AlignedBox3d box;
    double radius = 0;
    Tolerance coarse;
    coarse.chord = INFINITY;
    coarse.angle = kTwoPi / 24;
    for (const Shell& sh : solid.shells)
        for (uint32_t fi : sh.faces) {
            const Face& f = b.faces[fi];
            radius = std::max({radius, f.surface.radius + f.surface.minor_radius});
            for (const Loop& l : f.bounds) {
                if (l.kind == Loop::Kind::Vertex) box.extend(b.vertices[l.vertex].point);
                for (const Vector3d& p : l.polygon) box.extend(p);
                for (const OrientedEdge& oe : l.edges) {
                    for (const Vector3d& p : discretise(b, b.edges[oe.edge], coarse))
                        if (p.allFinite()) box.extend(p);
                }
            }
        }
    const double diagonal = box.isEmpty() ? 0.0 : box.diagonal().norm();
    return std::isfinite(diagonal) && diagonal > 0 ? diagonal : 2 * radius;
}

}  // namespace

std::vector<SolidMesh> tessellate(const Brep& b, const Tolerance& tolerance) {
    std::vector<SolidMesh> out;
    for (uint32_t k = 0; k < b.solids.size(); ++k) {
        const Solid& solid = b.solids[k];
        SolidMesh m;
        m.name = solid.name;
        m.solid = k;
        Tolerance tol = tolerance;
        if (!(tol.chord > 0)) {
            const double size = solid_size(b, solid);
            // (a solid with no extent at all is meshed at a micrometre: it has no size to be relative to)
            tol.chord = size > 0 ? tolerance.relative_chord * size : 1e-6;
        }
        m.chord = tol.chord;
        if (!solid.tessellated.triangles.empty()) {
            // AP242's own triangles: as the file gives them (its chord is the exporter's).
            m.mesh.points = solid.tessellated.points;
            m.mesh.triangles = solid.tessellated.triangles;
            m.faces_meshed = 1;
            out.push_back(std::move(m));
            continue;
        }
        SolidTessellator t(b, solid, tol, m);
        for (const Shell& sh : solid.shells)
            for (uint32_t f : sh.faces) t.face(b.faces[f], sh.reversed);
        out.push_back(std::move(m));
    }
    return out;
}

}  // namespace mbx_step
