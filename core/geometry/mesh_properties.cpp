#include "core/geometry/mesh_properties.h"

#include <unordered_map>

namespace mbx {

MeshClosure check_closure(const std::vector<uint32_t>& triangles) {
    // Directed edge (a,b) counts +1 and its reverse -1 on the undirected key;
    // a closed oriented surface cancels to zero with two uses per edge.
    struct Use {
        int forward = 0, backward = 0;
    };
    std::unordered_map<uint64_t, Use> edges;
    edges.reserve(triangles.size() * 2);
    for (size_t t = 0; t + 2 < triangles.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = triangles[t + size_t(k)], b = triangles[t + size_t((k + 1) % 3)];
            const uint64_t key = a < b ? (uint64_t(a) << 32 | b) : (uint64_t(b) << 32 | a);
            Use& u = edges[key];
            (a < b ? u.forward : u.backward)++;
        }
    MeshClosure c;
    for (const auto& [key, u] : edges) {
        if (u.forward == 1 && u.backward == 1) continue;
        if (u.forward + u.backward == 1)
            ++c.boundary_edges;
        else
            ++c.nonmanifold_edges;
    }
    c.closed = !triangles.empty() && c.boundary_edges == 0 && c.nonmanifold_edges == 0;
    return c;
}

void SolidAccumulator::add(const std::vector<Vec3>& v, const std::vector<uint32_t>& triangles) {
    for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const Vec3& a = v[triangles[t]];
        const Vec3& b = v[triangles[t + 1]];
        const Vec3& c = v[triangles[t + 2]];
        // Signed tetrahedron (origin, a, b, c): volume det/6, first moment
        // vol*(a+b+c)/4, second moment vol/20 * (sum x x^T + s s^T), s = a+b+c.
        const double vol = a.dot(b.cross(c)) / 6.0;
        const Vec3 s = a + b + c;
        volume_ += vol;
        first_ += vol * s / 4.0;
        second_ += vol / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
    }
}

SolidProperties SolidAccumulator::result() const {
    SolidProperties p;
    if (volume_ == 0) return p;
    // Inward-facing normals give a negative volume and negated moments alike.
    const double sign = volume_ < 0 ? -1.0 : 1.0;
    p.volume = sign * volume_;
    p.centroid = first_ / volume_;
    const Mat3 second_about_centroid = sign * second_ - p.volume * p.centroid * p.centroid.transpose();
    p.inertia_per_density = second_about_centroid.trace() * Mat3::Identity() - second_about_centroid;
    return p;
}

}  // namespace mbx
