#include "sim/contact/convex_hull.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <queue>
#include <unordered_map>
#include <unordered_set>

#include "core/finding.h"

namespace mbx::sim::contact {

namespace {

struct Face {
    std::array<int, 3> v;
    Eigen::Vector3d normal;  // unit, outward
    double offset = 0;       // normal . x = offset on the face
    bool alive = true;
    std::vector<int> outside;  // conflict list: points beyond this face, assigned to no other
    int farthest = -1;
    double farthest_distance = 0;
};

Face make_face(const std::vector<Eigen::Vector3d>& p, int a, int b, int c) {
    Face f;
    f.v = {a, b, c};
    f.normal = (p[size_t(b)] - p[size_t(a)]).cross(p[size_t(c)] - p[size_t(a)]).normalized();
    f.offset = f.normal.dot(p[size_t(a)]);
    return f;
}

uint64_t edge_key(int a, int b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); }

}  // namespace

ConvexHull convex_hull(const std::vector<Eigen::Vector3d>& points, const std::string& name, int max_vertices,
                       HullStats* stats) {
    auto fail = [&](const std::string& what) {
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(name), "convex hull of '" + name + "': " + what);
    };
    if (max_vertices < 4) fail("a vertex cap below four");
    for (const Eigen::Vector3d& x : points)
        if (!x.allFinite()) fail("a vertex is not finite");
    if (points.size() < 4) fail("fewer than four vertices");
    if (points.size() > size_t(INT32_MAX)) fail("more vertices than a hull index holds");
    Eigen::Vector3d lo = points[0], hi = points[0];
    for (const Eigen::Vector3d& x : points) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    const double scale = (hi - lo).norm();
    // A point counts as outside a face only beyond this: round-off on a
    // CAD mesh's coplanar vertices must not create sliver faces.
    const double eps = 1e-9 * std::max(scale, 1e-300);

    // Initial tetrahedron from extreme points: the first and farthest, the
    // farthest from their line, the farthest from their plane.
    int i0 = 0;
    for (size_t i = 1; i < points.size(); ++i)
        if (points[i].x() < points[size_t(i0)].x()) i0 = int(i);
    int i1 = -1, i2 = -1, i3 = -1;
    double best = 0;
    for (size_t i = 0; i < points.size(); ++i)
        if (const double d = (points[i] - points[size_t(i0)]).norm(); d > best) best = d, i1 = int(i);
    if (i1 < 0 || best <= eps) fail("all vertices coincide");
    const Eigen::Vector3d axis = (points[size_t(i1)] - points[size_t(i0)]).normalized();
    best = 0;
    for (size_t i = 0; i < points.size(); ++i)
        if (const double d = (points[i] - points[size_t(i0)]).cross(axis).norm(); d > best) best = d, i2 = int(i);
    if (i2 < 0 || best <= eps) fail("the vertices lie on one line");
    const Eigen::Vector3d plane =
        (points[size_t(i1)] - points[size_t(i0)]).cross(points[size_t(i2)] - points[size_t(i0)]).normalized();
    best = 0;
    for (size_t i = 0; i < points.size(); ++i)
        if (const double d = std::abs((points[i] - points[size_t(i0)]).dot(plane)); d > best) best = d, i3 = int(i);
    if (i3 < 0 || best <= eps) fail("the vertices lie in one plane (no volume)");

    std::vector<Face> faces;
    std::vector<int> uses(points.size(), 0);  // alive faces per point: a hull vertex while > 0
    int vertex_count = 0;
    auto add_face = [&](Face f) {
        for (int v : f.v)
            if (uses[size_t(v)]++ == 0) ++vertex_count;
        faces.push_back(std::move(f));
        return int(faces.size() - 1);
    };
    auto kill_face = [&](Face& f) {
        f.alive = false;
        for (int v : f.v)
            if (--uses[size_t(v)] == 0) --vertex_count;
    };
    // Files point i under the first of `candidates` it lies beyond; a point
    // beyond none is inside the hull for good.
    auto assign = [&](int i, const std::vector<int>& candidates) {
        for (int c : candidates) {
            Face& f = faces[size_t(c)];
            const double d = f.normal.dot(points[size_t(i)]) - f.offset;
            if (d <= eps) continue;
            f.outside.push_back(i);
            if (d > f.farthest_distance) f.farthest_distance = d, f.farthest = i;
            return;
        }
    };

    const Eigen::Vector3d inside = (points[size_t(i0)] + points[size_t(i1)] + points[size_t(i2)] + points[size_t(i3)]) / 4;
    std::vector<int> initial;
    for (const std::array<int, 3>& t : {std::array<int, 3>{i0, i1, i2}, std::array<int, 3>{i0, i1, i3},
                                        std::array<int, 3>{i0, i2, i3}, std::array<int, 3>{i1, i2, i3}}) {
        Face f = make_face(points, t[0], t[1], t[2]);
        if (f.normal.dot(inside) > f.offset) f = make_face(points, t[0], t[2], t[1]);  // keep the normal outward
        initial.push_back(add_face(std::move(f)));
    }
    for (size_t i = 0; i < points.size(); ++i)
        if (int(i) != i0 && int(i) != i1 && int(i) != i2 && int(i) != i3) assign(int(i), initial);

    // Faces by their farthest point, farthest first: the hull grows where it
    // is worst, so when the cap stops it the points left outside are the
    // nearest ones everywhere (a depth-first order refines one corner and
    // leaves the rest coarse). Entries go stale when a face dies.
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry> pending;
    for (int f : initial)
        if (!faces[size_t(f)].outside.empty()) pending.push({faces[size_t(f)].farthest_distance, f});
    std::vector<int> visible, created, orphans;
    std::unordered_set<uint64_t> visible_edges;
    while (!pending.empty()) {
        const int current = pending.top().second;
        if (!faces[size_t(current)].alive || faces[size_t(current)].outside.empty()) {
            pending.pop();
            continue;
        }
        if (vertex_count >= max_vertices) break;
        pending.pop();
        const int eye = faces[size_t(current)].farthest;
        const Eigen::Vector3d& x = points[size_t(eye)];
        // The faces the eye sees. Scanning every alive face costs the hull's
        // size per added vertex, which the cap bounds, not the point count.
        visible.clear();
        visible_edges.clear();
        for (size_t f = 0; f < faces.size(); ++f) {
            Face& face = faces[f];
            if (!face.alive || face.normal.dot(x) - face.offset <= eps) continue;
            visible.push_back(int(f));
            for (int k = 0; k < 3; ++k) visible_edges.insert(edge_key(face.v[size_t(k)], face.v[size_t((k + 1) % 3)]));
        }
        orphans.clear();
        for (int f : visible) {
            Face& face = faces[size_t(f)];
            kill_face(face);
            for (int p : face.outside)
                if (p != eye) orphans.push_back(p);
            face.outside.clear();
            face.outside.shrink_to_fit();
        }
        // An edge of a seen face whose reverse belongs to no seen face is on
        // the horizon: a fan from it to the eye replaces the seen faces.
        created.clear();
        for (int f : visible) {
            const std::array<int, 3> v = faces[size_t(f)].v;
            for (int k = 0; k < 3; ++k) {
                const int a = v[size_t(k)], b = v[size_t((k + 1) % 3)];
                if (visible_edges.count(edge_key(b, a))) continue;
                created.push_back(add_face(make_face(points, a, b, eye)));
            }
        }
        for (int p : orphans) assign(p, created);
        for (int f : created)
            if (!faces[size_t(f)].outside.empty()) pending.push({faces[size_t(f)].farthest_distance, f});
        // Dead faces pile up; drop them once they outnumber the living.
        if (faces.size() > 4 * size_t(std::max(vertex_count, 4)) * 2) {
            std::vector<Face> alive;
            alive.reserve(faces.size() / 2);
            for (Face& f : faces)
                if (f.alive) alive.push_back(std::move(f));
            faces = std::move(alive);
            pending = {};
            for (size_t f = 0; f < faces.size(); ++f)
                if (!faces[f].outside.empty()) pending.push({faces[f].farthest_distance, int(f)});
        }
    }

    ConvexHull hull;
    std::unordered_map<int, int> index;  // point -> hull vertex
    std::vector<int> left;               // points the cap left outside
    for (const Face& f : faces) {
        if (!f.alive) continue;
        left.insert(left.end(), f.outside.begin(), f.outside.end());
        hull.faces.push_back(3);
        for (int v : f.v) {
            auto [it, fresh] = index.emplace(v, int(hull.vertices.size()));
            if (fresh) hull.vertices.push_back(points[size_t(v)]);
            hull.faces.push_back(it->second);
        }
        ++hull.face_count;
    }
    double inflation = 1;
    if (!left.empty()) {
        // x is inside c + s (H - c) when n.(x - c) <= s (offset - n.c) for
        // every face: the smallest such s over the points left outside.
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (const Eigen::Vector3d& v : hull.vertices) c += v;
        c /= double(hull.vertices.size());
        std::vector<std::pair<Eigen::Vector3d, double>> planes;  // normal over room (> 0: c is inside)
        for (const Face& f : faces)
            if (f.alive) planes.push_back({f.normal, 1 / (f.offset - f.normal.dot(c))});
        for (int p : left) {
            const Eigen::Vector3d x = points[size_t(p)] - c;
            for (const auto& [normal, inverse_room] : planes) inflation = std::max(inflation, normal.dot(x) * inverse_room);
        }
        inflation *= 1 + 1e-12;  // the scaled faces' own round-off must not put the farthest point back outside
        for (Eigen::Vector3d& v : hull.vertices) v = c + inflation * (v - c);
    }
    if (stats) *stats = {points.size(), !left.empty(), inflation};
    return hull;
}

}  // namespace mbx::sim::contact
