// What the STEP tests share: a Part 21 file around some DATA lines, and
// OpenCASCADE's reading of a file (tests/step/occt_oracle.cpp).
#pragma once

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <cstdio>
#include <string>
#include <vector>

#include "host_adapters/step/tessellate.h"
#include "tests/common/skip.h"

namespace step_test {

// A whole Part 21 file whose DATA section is `data`.
inline std::string wrap(const std::string& data, const std::string& schema = "AUTOMOTIVE_DESIGN") {
    return "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('','',(''),(''),'','','');\n"
           "FILE_SCHEMA(('" + schema + "'));\nENDSEC;\nDATA;\n" + data + "ENDSEC;\nEND-ISO-10303-21;\n";
}

// A mesh's triangles as one index list (what core/geometry takes) and the
// volume it encloses, signed: positive when its normals face out.
struct FlatMesh {
    std::vector<uint32_t> indices;
    double signed_volume = 0;
};

inline FlatMesh flatten(const mbx_step::TriangleMesh& m) {
    FlatMesh out;
    out.indices.reserve(3 * m.triangles.size());
    double six = 0;
    for (const auto& t : m.triangles) {
        out.indices.insert(out.indices.end(), t.begin(), t.end());
        six += m.points[t[0]].dot(m.points[t[1]].cross(m.points[t[2]]));
    }
    out.signed_volume = six / 6;
    return out;
}

struct OracleSolid {
    int faces = 0, edges = 0, vertices = 0;
    double volume = 0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the centroid, unit density
};

struct Oracle {
    std::vector<OracleSolid> solids;
    int faces = 0, edges = 0, vertices = 0;  // distinct definitions
};

// OpenCASCADE's reading of the file; skips the test where it was not built.
inline Oracle occt(const std::string& path) {
#ifndef MBX_STEP_ORACLE
    throw mbx_test::SkipTest{"OpenCASCADE was not found when this build was configured (bash .ci/install-deps)"};
#else
    // (OpenCASCADE keeps allocations of its own to exit: no leak check on it in the sanitizer build)
    FILE* pipe = ::popen(("ASAN_OPTIONS=detect_leaks=0 " + std::string(MBX_STEP_ORACLE) + " '" + path + "'").c_str(), "r");
    REQUIRE(pipe != nullptr);
    Oracle o;
    char line[2048];
    while (std::fgets(line, sizeof line, pipe)) {
        OracleSolid s;
        double x[10];
        if (std::sscanf(line, "solid %d %d %d %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf", &s.faces, &s.edges, &s.vertices,
                        &x[0], &x[1], &x[2], &x[3], &x[4], &x[5], &x[6], &x[7], &x[8], &x[9]) == 13) {
            s.volume = x[0];
            s.centroid = Eigen::Vector3d(x[1], x[2], x[3]);
            s.inertia << x[4], -x[7], -x[8], -x[7], x[5], -x[9], -x[8], -x[9], x[6];
            o.solids.push_back(s);
        } else {
            std::sscanf(line, "distinct %d %d %d", &o.faces, &o.edges, &o.vertices);
        }
    }
    REQUIRE(::pclose(pipe) == 0);
    return o;
#endif
}

// OpenCASCADE's distance from each point (metres, in the file's frame) to
// the nearest face of the file's shape, and the file's own gap there: the
// largest tolerance OpenCASCADE gives an edge within `reach` of the point
// (0 where none is given).
struct OcctDistance {
    double distance = 0, gap = 0;
};

inline std::vector<OcctDistance> occt_distances(const std::string& path, const std::vector<Eigen::Vector3d>& points,
                                                const std::string& scratch, const std::vector<double>& reach = {}) {
#ifndef MBX_STEP_ORACLE
    (void)path, (void)points, (void)scratch, (void)reach;
    throw mbx_test::SkipTest{"OpenCASCADE was not found when this build was configured (bash .ci/install-deps)"};
#else
    {
        FILE* out = std::fopen(scratch.c_str(), "w");
        REQUIRE(out != nullptr);
        for (size_t k = 0; k < points.size(); ++k)
            std::fprintf(out, "%.17g %.17g %.17g %.17g\n", points[k].x(), points[k].y(), points[k].z(),
                         k < reach.size() ? reach[k] : 0.0);
        std::fclose(out);
    }
    FILE* pipe = ::popen(("ASAN_OPTIONS=detect_leaks=0 " + std::string(MBX_STEP_ORACLE) + " '" + path + "' --distance '" +
                          scratch + "'").c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::vector<OcctDistance> d;
    char line[256];
    OcctDistance x;
    while (std::fgets(line, sizeof line, pipe))
        if (std::sscanf(line, "distance %lf gap %lf", &x.distance, &x.gap) == 2) d.push_back(x);
    REQUIRE(::pclose(pipe) == 0);
    REQUIRE(d.size() == points.size());
    return d;
#endif
}

}  // namespace step_test
