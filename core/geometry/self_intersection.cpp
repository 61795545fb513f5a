#include "core/geometry/self_intersection.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace mbx {

namespace {

// Whether segment p->q passes through triangle (a, b, c) strictly inside both
// (the ends and the triangle's rim excluded by a relative margin of 1e-7).
bool segment_crosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 d = q - p, e1 = b - a, e2 = c - a;
    const Vec3 h = d.cross(e2);
    const double det = e1.dot(h);  // |d| |e1 x e2| sin(the edge's angle to the plane)
    const double scale = d.norm() * e1.cross(e2).norm();
    // An edge within 1e-6 rad of the triangle's plane (neighbours on a
    // smooth surface meet at such angles) has no well-defined crossing: its
    // computed crossing point lands anywhere near the corner they share.
    if (!(std::abs(det) > 1e-6 * scale)) return false;
    const double inv = 1.0 / det;
    const Vec3 s = p - a;
    const double u = s.dot(h) * inv;
    const double margin = 1e-7;
    if (u <= margin || u >= 1 - margin) return false;
    const Vec3 qv = s.cross(e1);
    const double v = d.dot(qv) * inv;
    if (v <= margin || u + v >= 1 - margin) return false;
    const double t = e2.dot(qv) * inv;
    return t > margin && t < 1 - margin;
}

int shared_corners(const uint32_t* x, const uint32_t* y) {
    int n = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) n += x[i] == y[j];
    return n;
}

bool crosses(const std::vector<Vec3>& v, const uint32_t* x, const uint32_t* y) {
    for (int k = 0; k < 3; ++k) {
        // An edge of one through the other, or the other's edge through it.
        if (segment_crosses(v[x[k]], v[x[(k + 1) % 3]], v[y[0]], v[y[1]], v[y[2]])) return true;
        if (segment_crosses(v[y[k]], v[y[(k + 1) % 3]], v[x[0]], v[x[1]], v[x[2]])) return true;
    }
    return false;
}

}  // namespace

SelfIntersections find_self_intersections(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& triangles,
                                          size_t limit) {
    SelfIntersections out;
    const size_t n = triangles.size() / 3;
    if (n < 2) return out;
    Eigen::AlignedBox3d all;
    double mean_edge = 0;
    for (size_t t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = vertices[triangles[3 * t + size_t(k)]];
            all.extend(p);
            mean_edge += (p - vertices[triangles[3 * t + size_t((k + 1) % 3)]]).norm();
        }
    mean_edge /= double(3 * n);
    // Cells about twice the mean edge, but never more cells than triangles
    // per axis cubed allows (a few large triangles must not make a huge grid).
    const Vec3 extent = all.sizes();
    double cell = std::max(2 * mean_edge, 1e-300);
    const double max_cells = 8.0 * double(n);
    while ((std::floor(extent.x() / cell) + 1) * (std::floor(extent.y() / cell) + 1) * (std::floor(extent.z() / cell) + 1) >
           max_cells)
        cell *= 1.5;
    auto key = [](int64_t x, int64_t y, int64_t z) {
        return uint64_t(x & 0x1FFFFF) | uint64_t(y & 0x1FFFFF) << 21 | uint64_t(z & 0x1FFFFF) << 42;
    };
    auto cell_of = [&](const Vec3& p) {
        return Eigen::Array<int64_t, 3, 1>(int64_t(std::floor((p.x() - all.min().x()) / cell)),
                                           int64_t(std::floor((p.y() - all.min().y()) / cell)),
                                           int64_t(std::floor((p.z() - all.min().z()) / cell)));
    };
    std::vector<Eigen::AlignedBox3d> boxes(n);
    std::vector<std::pair<uint64_t, uint32_t>> entries;  // (cell, triangle), sorted by cell
    entries.reserve(2 * n);
    for (size_t t = 0; t < n; ++t) {
        for (int k = 0; k < 3; ++k) boxes[t].extend(vertices[triangles[3 * t + size_t(k)]]);
        const auto lo = cell_of(boxes[t].min()), hi = cell_of(boxes[t].max());
        for (int64_t x = lo.x(); x <= hi.x(); ++x)
            for (int64_t y = lo.y(); y <= hi.y(); ++y)
                for (int64_t z = lo.z(); z <= hi.z(); ++z) entries.emplace_back(key(x, y, z), uint32_t(t));
    }
    std::sort(entries.begin(), entries.end());
    std::vector<std::pair<uint32_t, uint32_t>> seen;
    for (size_t first = 0; first < entries.size() && seen.size() <= limit;) {
        size_t last = first;
        while (last < entries.size() && entries[last].first == entries[first].first) ++last;
        for (size_t i = first; i < last; ++i)
            for (size_t j = i + 1; j < last; ++j) {
                const uint32_t a = entries[i].second, b = entries[j].second;
                if (!boxes[a].intersects(boxes[b])) continue;
                // Tested once: in the cell holding the corner where their boxes' overlap begins.
                const auto owner = cell_of(boxes[a].min().cwiseMax(boxes[b].min()));
                if (key(owner.x(), owner.y(), owner.z()) != entries[first].first) continue;
                const uint32_t* x = &triangles[3 * size_t(a)];
                const uint32_t* y = &triangles[3 * size_t(b)];
                if (shared_corners(x, y) >= 2) continue;
                if (!crosses(vertices, x, y)) continue;
                seen.emplace_back(std::min(a, b), std::max(a, b));
            }
        first = last;
    }
    // (a pair found in several cells counts once)
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    out.count = std::min(seen.size(), limit);
    seen.resize(out.count);
    out.pairs = std::move(seen);
    if (out.pairs.size() > 10) out.pairs.resize(10);
    return out;
}

}  // namespace mbx
