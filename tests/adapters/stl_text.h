// Boxes as STL files (ASCII and binary), for mesh-file tests.
#pragma once
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "tiny_pmxml.h"

namespace atest {

// The 12 outward triangles of an axis-aligned box of edge lengths `size`
// centred at `centre`, as corner triples.
inline std::vector<std::array<Eigen::Vector3d, 3>> box_triangles(const Eigen::Vector3d& centre,
                                                                  const Eigen::Vector3d& size) {
    std::array<Eigen::Vector3d, 8> v;
    for (int k = 0; k < 8; ++k)
        v[size_t(k)] = centre + 0.5 * Eigen::Vector3d(k & 1 ? size.x() : -size.x(), k & 2 ? size.y() : -size.y(),
                                                      k & 4 ? size.z() : -size.z());
    static const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                     {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    std::vector<std::array<Eigen::Vector3d, 3>> out;
    for (const auto& f : faces) out.push_back({v[size_t(f[0])], v[size_t(f[1])], v[size_t(f[2])]});
    return out;
}

inline std::string stl_ascii(const std::vector<std::array<Eigen::Vector3d, 3>>& triangles) {
    std::string s = "solid box\n";
    for (const auto& t : triangles) {
        const Eigen::Vector3d n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
        s += "  facet normal " + number_text(n.x()) + " " + number_text(n.y()) + " " + number_text(n.z()) + "\n";
        s += "    outer loop\n";
        for (const Eigen::Vector3d& p : t)
            s += "      vertex " + number_text(p.x()) + " " + number_text(p.y()) + " " + number_text(p.z()) + "\n";
        s += "    endloop\n  endfacet\n";
    }
    return s + "endsolid box\n";
}

inline std::string stl_binary(const std::vector<std::array<Eigen::Vector3d, 3>>& triangles) {
    std::string s(80, ' ');
    const uint32_t n = uint32_t(triangles.size());
    for (int i = 0; i < 4; ++i) s += char((n >> (8 * i)) & 0xff);
    auto put = [&s](float f) {
        char b[4];
        std::memcpy(b, &f, 4);  // little-endian hosts only, as the CI
        s.append(b, 4);
    };
    for (const auto& t : triangles) {
        const Eigen::Vector3d nrm = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
        for (int i = 0; i < 3; ++i) put(float(nrm[i]));
        for (const Eigen::Vector3d& p : t)
            for (int i = 0; i < 3; ++i) put(float(p[i]));
        s += std::string(2, '\0');
    }
    return s;
}

}  // namespace atest
