#include "export/mesh/collision_meshes.h"

#include <cctype>
#include <cmath>
#include <set>

#include "sim/contact/convex_hull.h"

namespace mbx {

namespace {

void triangle(Mesh& m, size_t a, size_t b, size_t c) {
    m.triangles.push_back(uint32_t(a)), m.triangles.push_back(uint32_t(b)), m.triangles.push_back(uint32_t(c));
}

// A surface of revolution about z: `rings` circles (radius, z) between two
// poles, each circle kCollisionSegments points, caps closed by fans.
Mesh revolve(const std::vector<std::pair<double, double>>& rings, double z_bottom, double z_top) {
    Mesh m;
    const int n = kCollisionSegments;
    m.vertices.push_back(Vec3(0, 0, z_bottom));
    for (const auto& [r, z] : rings)
        for (int k = 0; k < n; ++k) {
            const double a = 2 * M_PI * k / n;
            m.vertices.push_back(Vec3(r * std::cos(a), r * std::sin(a), z));
        }
    m.vertices.push_back(Vec3(0, 0, z_top));
    const size_t top = m.vertices.size() - 1;
    auto at = [&](size_t ring, int k) { return 1 + ring * size_t(n) + size_t((k + n) % n); };
    for (int k = 0; k < n; ++k) triangle(m, 0, at(0, k + 1), at(0, k));  // seen from below: clockwise from above
    for (size_t ring = 0; ring + 1 < rings.size(); ++ring)
        for (int k = 0; k < n; ++k) {
            triangle(m, at(ring, k), at(ring, k + 1), at(ring + 1, k + 1));
            triangle(m, at(ring, k), at(ring + 1, k + 1), at(ring + 1, k));
        }
    for (int k = 0; k < n; ++k) triangle(m, top, at(rings.size() - 1, k), at(rings.size() - 1, k + 1));
    return m;
}

std::string identifier(const std::string& s) {
    std::string out;
    for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return out;
}

}  // namespace

Mesh primitive_mesh(const CollisionSpec& s) {
    std::vector<std::pair<double, double>> rings;
    switch (s.kind) {
    case CollisionKind::Sphere:
        for (int i = 1; i < kCollisionRings; ++i) {
            const double polar = M_PI * i / kCollisionRings;
            rings.push_back({s.radius * std::sin(polar), -s.radius * std::cos(polar)});
        }
        return revolve(rings, -s.radius, s.radius);
    case CollisionKind::Cylinder:
        return revolve({{s.radius, -s.length / 2}, {s.radius, s.length / 2}}, -s.length / 2, s.length / 2);
    case CollisionKind::Capsule: {
        // Two hemispheres of kCollisionRings / 2 rings each, their equators
        // at the ends of the axis.
        const int half = kCollisionRings / 2;
        for (int i = 1; i <= half; ++i) {
            const double polar = M_PI / 2 * i / half;
            rings.push_back({s.radius * std::sin(polar), -s.length / 2 - s.radius * std::cos(polar)});
        }
        for (int i = half; i >= 1; --i) {
            const double polar = M_PI / 2 * i / half;
            rings.push_back({s.radius * std::sin(polar), s.length / 2 + s.radius * std::cos(polar)});
        }
        return revolve(rings, -s.length / 2 - s.radius, s.length / 2 + s.radius);
    }
    case CollisionKind::Box: {
        Mesh m;
        for (int k = 0; k < 8; ++k)
            m.vertices.push_back(Vec3(k & 1 ? 0.5 : -0.5, k & 2 ? 0.5 : -0.5, k & 4 ? 0.5 : -0.5).cwiseProduct(s.size));
        // Each face's corners counter-clockwise seen from outside.
        const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (const auto& q : quads) triangle(m, size_t(q[0]), size_t(q[1]), size_t(q[2])), triangle(m, size_t(q[0]), size_t(q[2]), size_t(q[3]));
        return m;
    }
    case CollisionKind::Plane:
    case CollisionKind::Hull: break;
    }
    return {};
}

std::vector<CollisionMesh> collision_meshes(ExportModel& model, const std::string& format, bool hulls_only) {
    const ResolvedContact& rc = model.settings().contact;
    const Mechanism& m = model.mechanism();
    std::vector<CollisionMesh> out;
    std::set<std::string> taken;
    for (size_t b = 0; b < m.bodies.size(); ++b)
        if (model.has_mesh(int(b))) taken.insert(model.mesh_stem(int(b)));
    for (size_t i = 0; i < rc.shapes.size(); ++i) {
        const ResolvedCollision& r = rc.shapes[i];
        CollisionMesh c;
        c.shape = int(i), c.body = r.body, c.pose = r.pose;
        if (hulls_only && r.spec.kind != CollisionKind::Hull) continue;
        if (r.spec.kind == CollisionKind::Plane) {
            model.note(MBX_SEVERITY_INFO, MBX_FINDING_EXPORT_APPROXIMATION, Subject::model(r.name),
                       format + ": plane '" + r.name + "' is unbounded and left out");
            continue;
        }
        if (r.spec.kind == CollisionKind::Hull) {
            const std::string& part = m.assembly.parts[size_t(r.hull_part)].id;
            std::vector<Eigen::Vector3d> points;
            for (const Mesh& mesh : model.shapes(r.body))
                if (mesh.part_id == part) points.insert(points.end(), mesh.vertices.begin(), mesh.vertices.end());
            if (points.empty()) {
                model.note(MBX_SEVERITY_INFO, MBX_FINDING_EXPORT_APPROXIMATION, Subject::model(r.name),
                           format + ": part '" + m.assembly.parts[size_t(r.hull_part)].name +
                               "' has no mesh, so no hull '" + r.name + "'");
                continue;
            }
            const sim::contact::ConvexHull hull = sim::contact::convex_hull(points, r.name);
            c.mesh.vertices = hull.vertices;
            for (size_t f = 0; f < size_t(hull.face_count); ++f)
                triangle(c.mesh, size_t(hull.faces[4 * f + 1]), size_t(hull.faces[4 * f + 2]), size_t(hull.faces[4 * f + 3]));
        } else {
            c.mesh = primitive_mesh(r.spec);
        }
        c.mesh.name = r.name;
        std::string node = "collision_" + identifier(r.name);
        for (int k = 2; taken.count(node); ++k) node = "collision_" + identifier(r.name) + "_" + std::to_string(k);
        taken.insert(node);
        c.node = node;
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace mbx
