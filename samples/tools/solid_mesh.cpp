#include "solid_mesh.h"

#include <cmath>
#include <stdexcept>

namespace mbx_samples {

Eigen::Isometry3d make_pose(const Eigen::Vector3d& position, const Eigen::Matrix3d& rotation) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = rotation;
    p.translation() = position;
    return p;
}

Eigen::Matrix3d frame_from_x(const Eigen::Vector3d& x, const Eigen::Vector3d& y_hint) {
    const Eigen::Vector3d ex = x.normalized();
    const Eigen::Vector3d ey = (y_hint - y_hint.dot(ex) * ex).normalized();
    Eigen::Matrix3d r;
    r.col(0) = ex;
    r.col(1) = ey;
    r.col(2) = ex.cross(ey);
    return r;
}

Solid box(const Eigen::Vector3d& size, const Eigen::Isometry3d& pose) {
    Solid s;
    const Eigen::Vector3d h = size / 2;
    for (int i = 0; i < 8; ++i)
        s.vertices.push_back(pose * Eigen::Vector3d(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()));
    // Two triangles per face, outward normals.
    s.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},   // -z, +z
                   {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},   // -y, +y
                   {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};  // -x, +x
    return s;
}

Solid cylinder(double radius, double length, int segments, const Eigen::Isometry3d& pose) {
    Solid s;
    const uint32_t n = uint32_t(segments);
    const double pi = std::acos(-1.0);
    for (uint32_t k = 0; k < n; ++k) {
        const double a = 2 * pi * double(k) / double(n);
        const double x = radius * std::cos(a), y = radius * std::sin(a);
        s.vertices.push_back(pose * Eigen::Vector3d(x, y, -length / 2));
        s.vertices.push_back(pose * Eigen::Vector3d(x, y, length / 2));
    }
    const uint32_t bottom = uint32_t(s.vertices.size()), top = bottom + 1;
    s.vertices.push_back(pose * Eigen::Vector3d(0, 0, -length / 2));
    s.vertices.push_back(pose * Eigen::Vector3d(0, 0, length / 2));
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t b0 = 2 * k, t0 = 2 * k + 1, b1 = 2 * ((k + 1) % n), t1 = b1 + 1;
        s.triangles.push_back({b0, b1, t1});
        s.triangles.push_back({b0, t1, t0});
        s.triangles.push_back({bottom, b1, b0});
        s.triangles.push_back({top, t0, t1});
    }
    return s;
}

Solid tube(double inner_radius, double outer_radius, double length, int segments, const Eigen::Isometry3d& pose) {
    Solid s;
    const uint32_t n = uint32_t(segments);
    const double pi = std::acos(-1.0);
    // Per angle: outer bottom, outer top, inner bottom, inner top.
    for (uint32_t k = 0; k < n; ++k) {
        const double a = 2 * pi * double(k) / double(n);
        const double c = std::cos(a), si = std::sin(a);
        for (double r : {outer_radius, inner_radius}) {
            s.vertices.push_back(pose * Eigen::Vector3d(r * c, r * si, -length / 2));
            s.vertices.push_back(pose * Eigen::Vector3d(r * c, r * si, length / 2));
        }
    }
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t o0 = 4 * k, o1 = 4 * ((k + 1) % n);
        const uint32_t ob0 = o0, ot0 = o0 + 1, ib0 = o0 + 2, it0 = o0 + 3;
        const uint32_t ob1 = o1, ot1 = o1 + 1, ib1 = o1 + 2, it1 = o1 + 3;
        s.triangles.push_back({ob0, ob1, ot1});  // outer wall, facing out
        s.triangles.push_back({ob0, ot1, ot0});
        s.triangles.push_back({ib0, it1, ib1});  // bore wall, facing the axis
        s.triangles.push_back({ib0, it0, it1});
        s.triangles.push_back({ob0, ib1, ob1});  // bottom ring, facing -z
        s.triangles.push_back({ob0, ib0, ib1});
        s.triangles.push_back({ot0, ot1, it1});  // top ring, facing +z
        s.triangles.push_back({ot0, it1, it0});
    }
    return s;
}

Solid bar(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double width, double height,
          const Eigen::Vector3d& side, double overhang) {
    const Eigen::Vector3d d = b - a;
    const Eigen::Matrix3d r = frame_from_x(d, side);
    return box(Eigen::Vector3d(d.norm() + 2 * overhang, width, height), make_pose((a + b) / 2, r));
}

Solid transformed(const Solid& solid, const Eigen::Isometry3d& pose) {
    Solid s = solid;
    for (Eigen::Vector3d& v : s.vertices) v = pose * v;
    return s;
}

SolidProperties properties(const std::vector<const Solid*>& solids) {
    // Integrate over tetrahedra from a point near the solids: from the origin,
    // parts far from it would lose digits to cancellation.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (const Solid* s : solids)
        for (const Eigen::Vector3d& v : s->vertices) {
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
        }
    const Eigen::Vector3d o = (lo + hi) / 2;
    double volume = 0, area = 0;
    Eigen::Vector3d first = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // integral of r r^T
    for (const Solid* s : solids)
        for (const auto& t : s->triangles) {
            const Eigen::Vector3d a = s->vertices[t[0]] - o, b = s->vertices[t[1]] - o, c = s->vertices[t[2]] - o;
            const double v = a.dot(b.cross(c)) / 6;
            const Eigen::Vector3d sum = a + b + c;
            volume += v;
            first += v * sum / 4;
            second += v / 20 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
            area += (b - a).cross(c - a).norm() / 2;
        }
    if (!(volume > 0)) throw std::runtime_error("solid without positive volume (open or inside out)");
    SolidProperties p;
    p.volume = volume;
    p.area = area;
    const Eigen::Vector3d c = first / volume;
    p.centroid = o + c;
    const Eigen::Matrix3d about_centroid = second - volume * c * c.transpose();
    p.inertia = about_centroid.trace() * Eigen::Matrix3d::Identity() - about_centroid;
    return p;
}

}  // namespace mbx_samples
