#include "primitive_meshes.h"

#include <cmath>

namespace mbx_files::vrml {
namespace {

const double pi = std::acos(-1.0);

uint32_t add_vertex(VrmlMesh& m, double x, double y, double z) {
    m.vertices.insert(m.vertices.end(), {x, y, z});
    return static_cast<uint32_t>(m.vertices.size() / 3 - 1);
}

void add_triangle(VrmlMesh& m, uint32_t a, uint32_t b, uint32_t c) { m.triangles.insert(m.triangles.end(), {a, b, c}); }

// A ring of `n` vertices at height y, starting on +Z and turning
// counter-clockwise seen from +Y (as VRML's texture seam does).
uint32_t add_ring(VrmlMesh& m, double radius, double y, int n) {
    const uint32_t first = static_cast<uint32_t>(m.vertices.size() / 3);
    for (int i = 0; i < n; ++i) {
        const double a = 2 * pi * i / n;
        add_vertex(m, radius * std::sin(a), y, radius * std::cos(a));
    }
    return first;
}

}  // namespace

VrmlMesh box_mesh(double sx, double sy, double sz) {
    VrmlMesh m;
    const double x = sx / 2, y = sy / 2, z = sz / 2;
    // Vertex i has coordinate signs from its bits: bit0 x, bit1 y, bit2 z.
    for (int i = 0; i < 8; ++i) add_vertex(m, (i & 1) ? x : -x, (i & 2) ? y : -y, (i & 4) ? z : -z);
    const uint32_t quads[6][4] = {
        {0, 4, 6, 2},  // -x
        {1, 3, 7, 5},  // +x
        {0, 1, 5, 4},  // -y
        {2, 6, 7, 3},  // +y
        {0, 2, 3, 1},  // -z
        {4, 5, 7, 6},  // +z
    };
    for (const auto& q : quads) {
        add_triangle(m, q[0], q[1], q[2]);
        add_triangle(m, q[0], q[2], q[3]);
    }
    return m;
}

VrmlMesh sphere_mesh(double radius, int segments) {
    VrmlMesh m;
    const int rings = segments / 2;  // latitude bands
    const uint32_t north = add_vertex(m, 0, radius, 0);
    std::vector<uint32_t> ring_start;
    for (int r = 1; r < rings; ++r) {
        const double polar = pi * r / rings;
        ring_start.push_back(add_ring(m, radius * std::sin(polar), radius * std::cos(polar), segments));
    }
    const uint32_t south = add_vertex(m, 0, -radius, 0);
    const auto n = static_cast<uint32_t>(segments);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t j = (i + 1) % n;
        add_triangle(m, north, ring_start.front() + i, ring_start.front() + j);
        for (size_t r = 0; r + 1 < ring_start.size(); ++r) {
            const uint32_t a = ring_start[r], b = ring_start[r + 1];
            add_triangle(m, a + i, b + i, b + j);
            add_triangle(m, a + i, b + j, a + j);
        }
        add_triangle(m, south, ring_start.back() + j, ring_start.back() + i);
    }
    return m;
}

VrmlMesh cylinder_mesh(double radius, double height, bool side, bool top, bool bottom, int segments) {
    VrmlMesh m;
    const double h = height / 2;
    const auto n = static_cast<uint32_t>(segments);
    // Caps share the side's rim vertices so the whole mesh is closed.
    const uint32_t lo = add_ring(m, radius, -h, segments);
    const uint32_t hi = add_ring(m, radius, h, segments);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t j = (i + 1) % n;
        if (side) {
            add_triangle(m, lo + i, lo + j, hi + j);
            add_triangle(m, lo + i, hi + j, hi + i);
        }
    }
    if (top) {
        const uint32_t c = add_vertex(m, 0, h, 0);
        for (uint32_t i = 0; i < n; ++i) add_triangle(m, c, hi + i, hi + (i + 1) % n);
    }
    if (bottom) {
        const uint32_t c = add_vertex(m, 0, -h, 0);
        for (uint32_t i = 0; i < n; ++i) add_triangle(m, c, lo + (i + 1) % n, lo + i);
    }
    return m;
}

VrmlMesh cone_mesh(double bottom_radius, double height, bool side, bool bottom, int segments) {
    VrmlMesh m;
    const double h = height / 2;
    const auto n = static_cast<uint32_t>(segments);
    const uint32_t rim = add_ring(m, bottom_radius, -h, segments);
    if (side) {
        const uint32_t apex = add_vertex(m, 0, h, 0);
        for (uint32_t i = 0; i < n; ++i) add_triangle(m, rim + i, rim + (i + 1) % n, apex);
    }
    if (bottom) {
        const uint32_t c = add_vertex(m, 0, -h, 0);
        for (uint32_t i = 0; i < n; ++i) add_triangle(m, c, rim + (i + 1) % n, rim + i);
    }
    return m;
}

}  // namespace mbx_files::vrml
