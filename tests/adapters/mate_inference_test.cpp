// Joints from mates (host_adapters/simscape/mate_inference): each mate
// combination a CAD export gives, alone and in pairs, against the joint a
// hand derivation gives (type, axis, anchor), redundant mates named, and a
// mate that cannot hold at the exported pose an error naming it. The
// geometry is placed off the origin and turned, so that a wrong moment arm
// or axis shows.
#include <cmath>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "host_adapters/simscape/mate_inference.h"

namespace MBX_UNITY_ID {

using Eigen::Vector3d;
using mbx_files::Mate;
using mbx_files::MateGeometry;
using mbx_files::MateProblem;

namespace {

// A hinge axis a through p, and directions across it.
const Vector3d p(0.31, -0.12, 0.47);
const Vector3d a = Vector3d(0.3, 0.8, -0.2).normalized();
const Vector3d u = a.unitOrthogonal(), w = a.cross(u);

Mate mate(const char* type, const char* name, MateGeometry first, MateGeometry second) {
    Mate m;
    m.type = type;
    m.name = name;
    m.first = first;
    m.second = second;
    return m;
}

MateGeometry g(const char* type, const Vector3d& at, const Vector3d& axis) { return {type, at, axis}; }

Mate concentric(const Vector3d& at, const Vector3d& axis, const char* name = "Concentric1") {
    // (the second geometry elsewhere on the same axis, as a real bore's far end)
    return mate("Concentric", name, g("cylinder", at, axis), g("cylinder", at + 0.05 * axis, -axis));
}
Mate coincident_planes(const Vector3d& at, const Vector3d& n, const char* name = "Coincident1") {
    // (a point elsewhere in the plane; the faces touch, normals opposed)
    return mate("Coincident", name, g("plane", at, n), g("plane", at + 0.03 * n.unitOrthogonal(), -n));
}

struct Result {
    mbx_files::InferredJoint joint;
    std::vector<MateProblem> problems;
};

Result infer(const std::vector<Mate>& mates) {
    Result r;
    r.joint = mbx_files::infer_joint(mates, 1.0, r.problems);
    return r;
}

bool along(const Vector3d& x, const Vector3d& direction) { return x.normalized().cross(direction.normalized()).norm() < 1e-9; }
// The distance of point x from the line through `at` along `direction`.
double off_line(const Vector3d& x, const Vector3d& at, const Vector3d& direction) {
    return (x - at).cross(direction.normalized()).norm();
}

}  // namespace

TEST_CASE("mates: a concentric pair leaves a cylindrical joint on the axis, with a coincident face a revolute one") {
    const Result cylinder = infer({concentric(p, a)});
    CHECK(cylinder.joint.type == "Cylindrical");
    CHECK(cylinder.joint.freedoms == 2);
    CHECK(along(cylinder.joint.frame.linear().col(2), a));
    CHECK(off_line(cylinder.joint.frame.translation(), p, a) < 1e-9);
    // The face across the axis holds the slide: a turn about the axis is left.
    const Result hinge = infer({concentric(p, a), coincident_planes(p + 0.02 * a, a)});
    CHECK(hinge.joint.type == "Revolute");
    CHECK(hinge.joint.freedoms == 1);
    CHECK(hinge.joint.frame.linear().col(2).dot(a) > 1 - 1e-12);  // the way the first mate's axis points
    CHECK(off_line(hinge.joint.frame.translation(), p, a) < 1e-9);
    CHECK((hinge.joint.frame.translation() - p).norm() < 1e-9);  // anchored at the first mate's point
    CHECK(hinge.joint.redundant.empty());
    CHECK(hinge.problems.empty());
}

TEST_CASE("mates: coincident faces leave a planar joint, two a prismatic one, three a weld with the repeats named") {
    const Result planar = infer({coincident_planes(p, a)});
    CHECK(planar.joint.type == "Planar");
    CHECK(along(planar.joint.frame.linear().col(2), a));
    // Two faces at an angle: the slide along their common line is left.
    const Result slide = infer({coincident_planes(p, a), coincident_planes(p, u, "Coincident2")});
    CHECK(slide.joint.type == "Prismatic");
    CHECK(along(slide.joint.frame.linear().col(2), a.cross(u)));
    // Both faces hold the turn about the third direction, but each holds
    // something new: neither is redundant; a face repeated is.
    CHECK(slide.joint.redundant.empty());
    const Result weld = infer({coincident_planes(p, a), coincident_planes(p, u, "Coincident2"),
                               coincident_planes(p, w, "Coincident3")});
    CHECK(weld.joint.type == "Weld");
    CHECK(weld.joint.freedoms == 0);
    CHECK(weld.joint.redundant.empty());
    const Result repeated = infer({coincident_planes(p, a), coincident_planes(p, u, "Coincident2"),
                                   coincident_planes(p + 0.1 * u, a, "Coincident3")});
    CHECK(repeated.joint.type == "Prismatic");
    CHECK(repeated.joint.redundant == std::vector<int>{2});
}

TEST_CASE("mates: coincident points leave a spherical joint, with a face through them a revolute one about its normal") {
    const Result ball = infer({mate("Coincident", "Point1", g("point", p, a), g("point", p, u))});
    CHECK(ball.joint.type == "Spherical");
    CHECK((ball.joint.frame.translation() - p).norm() < 1e-9);
    const Result hinge = infer({mate("Coincident", "Point1", g("point", p, a), g("point", p, u)), coincident_planes(p, w)});
    CHECK(hinge.joint.type == "Revolute");
    CHECK(along(hinge.joint.frame.linear().col(2), w));
    CHECK(off_line(hinge.joint.frame.translation(), p, w) < 1e-9);
    CHECK(hinge.joint.redundant.empty());  // the face holds two turns the point does not
}

TEST_CASE("mates: parallel, perpendicular, angle and distance mates hold turns, and slides where they say") {
    // Parallel faces hold only the two turns across their normal: four
    // freedoms, which no joint type has.
    const Result parallel = infer({mate("Parallel", "Parallel1", g("plane", p, a), g("plane", p + u, a))});
    CHECK(parallel.joint.type.empty());
    CHECK(parallel.joint.freedoms == 4);
    // A concentric pair with parallel faces along the axis: only the slide along it is left.
    const Result slider = infer({concentric(p, a), mate("Parallel", "Parallel1", g("plane", p, u), g("plane", p + a, u))});
    CHECK(slider.joint.type == "Prismatic");
    CHECK(slider.joint.frame.linear().col(2).dot(a) > 1 - 1e-12);
    CHECK(slider.joint.redundant.empty());
    // A face on a face, and a perpendicular pair of edges holding the turn about the face's normal.
    const Result rectangular = infer({coincident_planes(p, a), mate("Perpendicular", "Perpendicular1", g("line", p, u), g("line", p, w))});
    CHECK(rectangular.joint.type == "Rectangular");
    CHECK(along(rectangular.joint.frame.linear().col(2), a));
    // The same with an angle mate between directions at 40 degrees.
    const Vector3d tilted = std::cos(0.7) * u + std::sin(0.7) * w;
    const Result angled = infer({coincident_planes(p, a), mate("Angle", "Angle1", g("line", p, u), g("line", p, tilted))});
    CHECK(angled.joint.type == "Rectangular");
    // Faces kept apart by a distance mate: a planar joint as for touching faces.
    const Result apart = infer({mate("Distance", "Distance1", g("plane", p, a), g("plane", p + 0.01 * a, a))});
    CHECK(apart.joint.type == "Planar");
    CHECK(apart.problems.empty());
}

TEST_CASE("mates: two concentric pairs on parallel axes leave a slide along them, a third on one of them is redundant") {
    const Result r = infer({concentric(p, a), concentric(p + 0.08 * u, a, "Concentric2")});
    CHECK(r.joint.type == "Prismatic");
    CHECK(r.joint.frame.linear().col(2).dot(a) > 1 - 1e-12);
    CHECK(r.joint.redundant.empty());
    const Result again = infer({concentric(p, a), concentric(p + 0.08 * u, a, "Concentric2"), concentric(p + 0.3 * a, a, "Concentric3")});
    CHECK(again.joint.type == "Prismatic");
    CHECK(again.joint.redundant == std::vector<int>{2});
}

TEST_CASE("mates: a line on a line is an axis pair, and a parallel mate on the same directions repeats its turns") {
    const Result r = infer({mate("Coincident", "Line1", g("line", p, a), g("line", p + 0.04 * a, a)),
                            mate("Parallel", "Parallel1", g("line", p, a), g("line", p, a))});
    CHECK(r.joint.type == "Cylindrical");
    CHECK(r.joint.redundant == std::vector<int>{1});
}

TEST_CASE("mates: a mate that cannot hold at the exported pose is an error naming it, an unknown one is left out") {
    std::vector<Mate> mates = {concentric(p, a), coincident_planes(p, a)};
    mates[1].second.position += 0.002 * a;  // the faces 2 mm apart
    const Result apart = infer(mates);
    REQUIRE(apart.problems.size() == 1);
    CHECK(apart.problems[0].error);
    CHECK(apart.problems[0].mate == 1);
    CHECK(apart.problems[0].message.find("Coincident mate 'Coincident1'") != std::string::npos);
    CHECK(apart.joint.type == "Cylindrical");  // what the mates that hold leave
    std::vector<Mate> skew = {concentric(p, a)};
    skew[0].second.position += 0.001 * u;
    const Result off = infer(skew);
    REQUIRE(off.problems.size() == 1);
    CHECK(off.problems[0].error);
    CHECK(off.problems[0].message.find("do not coincide") != std::string::npos);
    const Result tangent = infer({concentric(p, a), mate("Tangent", "Tangent1", g("plane", p, u), g("cylinder", p, a))});
    REQUIRE(tangent.problems.size() == 1);
    CHECK_FALSE(tangent.problems[0].error);
    CHECK(tangent.problems[0].message.find("does not read") != std::string::npos);
    CHECK(tangent.joint.type == "Cylindrical");
    Mate nan = concentric(p, a);
    nan.first.position.x() = NAN;
    const Result bad = infer({nan});
    REQUIRE(bad.problems.size() == 1);
    CHECK(bad.problems[0].error);
    CHECK(bad.joint.freedoms == 6);
    CHECK(bad.joint.type.empty());
}

}  // namespace MBX_UNITY_ID
