#include "sim/contact/convex_hull.h"

#include <array>
#include <cmath>
#include <map>

#include "core/finding.h"

namespace mbx::sim::contact {

namespace {

struct Face {
    std::array<int, 3> v;
    Eigen::Vector3d normal;  // unit, outward
    double offset = 0;       // normal . x = offset on the face
    bool alive = true;
};

Face make_face(const std::vector<Eigen::Vector3d>& p, int a, int b, int c) {
    Face f;
    f.v = {a, b, c};
    f.normal = (p[size_t(b)] - p[size_t(a)]).cross(p[size_t(c)] - p[size_t(a)]).normalized();
    f.offset = f.normal.dot(p[size_t(a)]);
    return f;
}

}  // namespace

ConvexHull convex_hull(const std::vector<Eigen::Vector3d>& points, const std::string& name) {
    auto fail = [&](const std::string& what) {
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(name), "convex hull of '" + name + "': " + what);
    };
    for (const Eigen::Vector3d& x : points)
        if (!x.allFinite()) fail("a vertex is not finite");
    if (points.size() < 4) fail("fewer than four vertices");
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
    const Eigen::Vector3d inside = (points[size_t(i0)] + points[size_t(i1)] + points[size_t(i2)] + points[size_t(i3)]) / 4;
    auto add = [&](int a, int b, int c) {
        Face f = make_face(points, a, b, c);
        if (f.normal.dot(inside) > f.offset) f = make_face(points, a, c, b);  // keep the normal outward
        faces.push_back(f);
    };
    add(i0, i1, i2), add(i0, i1, i3), add(i0, i2, i3), add(i1, i2, i3);

    for (size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d& x = points[i];
        // Directed edges of the faces x sees; an edge whose reverse is not
        // among them is on the horizon.
        std::map<std::pair<int, int>, bool> seen;
        bool outside = false;
        for (Face& f : faces) {
            if (!f.alive || f.normal.dot(x) - f.offset <= eps) continue;
            outside = true;
            f.alive = false;
            for (int k = 0; k < 3; ++k) seen[{f.v[size_t(k)], f.v[size_t((k + 1) % 3)]}] = true;
        }
        if (!outside) continue;
        for (const auto& [edge, unused] : seen) {
            (void)unused;
            if (seen.count({edge.second, edge.first})) continue;
            Face f = make_face(points, edge.first, edge.second, int(i));
            faces.push_back(f);
        }
        std::vector<Face> alive;
        alive.reserve(faces.size());
        for (Face& f : faces)
            if (f.alive) alive.push_back(f);
        faces = std::move(alive);
    }

    ConvexHull hull;
    std::map<int, int> index;  // point -> hull vertex
    for (const Face& f : faces) {
        hull.faces.push_back(3);
        for (int v : f.v) {
            auto [it, fresh] = index.emplace(v, int(hull.vertices.size()));
            if (fresh) hull.vertices.push_back(points[size_t(v)]);
            hull.faces.push_back(it->second);
        }
        ++hull.face_count;
    }
    return hull;
}

}  // namespace mbx::sim::contact
