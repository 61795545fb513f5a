// Convex hulls of point clouds (sim/contact/convex_hull.h), the shape a
// description's shape="hull" wraps a CAD part's mesh in: checked by what
// defines a hull, not by its triangulation.
#include <doctest/doctest.h>

#include <random>

#include "core/finding.h"
#include "sim/contact/convex_hull.h"

namespace MBX_UNITY_ID {

using namespace mbx::sim::contact;

namespace {

// Outward unit normal and offset of triangle f of the hull.
void plane(const ConvexHull& h, int f, Eigen::Vector3d& n, double& offset) {
    const Eigen::Vector3d& a = h.vertices[size_t(h.faces[size_t(4 * f + 1)])];
    const Eigen::Vector3d& b = h.vertices[size_t(h.faces[size_t(4 * f + 2)])];
    const Eigen::Vector3d& c = h.vertices[size_t(h.faces[size_t(4 * f + 3)])];
    n = (b - a).cross(c - a).normalized();
    offset = n.dot(a);
}

}  // namespace

TEST_CASE("convex hull: every point inside, faces outward, a closed surface, only hull vertices") {
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss;
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<Eigen::Vector3d> points;
        const int n = 20 + 50 * trial;
        // Coordinates drawn one statement at a time: the order in which a
        // call's arguments are evaluated differs between compilers.
        auto draw = [&](double sx, double sy, double sz) {
            const double x = sx * gauss(rng);
            const double y = sy * gauss(rng);
            const double z = sz * gauss(rng);
            return Eigen::Vector3d(x, y, z);
        };
        for (int i = 0; i < n; ++i) points.push_back(draw(1, 0.3, 2));
        // Points on a sphere are all on the hull, and the cloud (tens of
        // standard deviations inside it) hides none of them.
        for (int i = 0; i < 30; ++i) points.push_back(50 * draw(1, 1, 1).normalized());
        const ConvexHull h = convex_hull(points, "cloud");
        REQUIRE(h.faces.size() == size_t(4 * h.face_count));
        // A closed triangulated surface of genus 0: F = 2V - 4.
        CHECK(h.face_count == 2 * int(h.vertices.size()) - 4);
        CHECK(h.vertices.size() >= 30);
        for (int f = 0; f < h.face_count; ++f) {
            Eigen::Vector3d normal;
            double offset = 0;
            plane(h, f, normal, offset);
            for (const Eigen::Vector3d& p : points) CHECK(normal.dot(p) - offset <= 1e-9);
        }
    }
}

TEST_CASE("convex hull: a box mesh's corners, and degenerate clouds refused with the shape's name") {
    std::vector<Eigen::Vector3d> box;
    for (int k = 0; k < 8; ++k) box.emplace_back(k & 1 ? 0.5 : -0.5, k & 2 ? 0.2 : -0.2, k & 4 ? 0.1 : -0.1);
    box.emplace_back(0, 0, 0);    // the centre and a face centre: not on the hull
    box.emplace_back(0.5, 0, 0);
    const ConvexHull h = convex_hull(box, "box");
    CHECK(h.vertices.size() == 8);
    CHECK(h.face_count == 12);
    auto refuses = [](const std::vector<Eigen::Vector3d>& p, const char* why) {
        try {
            convex_hull(p, "part_7");
            FAIL("no error");
        } catch (const mbx::Error& e) {
            CHECK(std::string(e.what()).find("part_7") != std::string::npos);
            CHECK(std::string(e.what()).find(why) != std::string::npos);
        }
    };
    refuses({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, "fewer than four");
    refuses({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.2, 0}}, "one plane");
    refuses({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}, "one line");
    refuses({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, NAN}}, "not finite");
}
}  // namespace MBX_UNITY_ID
