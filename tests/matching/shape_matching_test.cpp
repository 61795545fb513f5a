// match_shapes on hand-built scenes: each rule of thesis section 2.7.2 in
// isolation, then the transform that brings vertices into the body frame.
#include <cmath>

#include <doctest/doctest.h>

#include "scene_builder.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace matching_test;
using mbx_files::BodyPose;
using mbx_files::match_shapes;
using mbx_files::MatchIssue;
using mbx_files::MatchOptions;
using mbx_files::MatchResult;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

const double kPi = 3.14159265358979323846;

size_t count_issues(const MatchResult& r, MatchIssue::Kind kind) {
    size_t n = 0;
    for (const MatchIssue& i : r.issues) n += i.kind == kind;
    return n;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("each node on one body's part frame gets that body's shapes") {
    const std::vector<BodyPose> bodies = {body("1", "BASE", Vector3d(0, 0, 0)), body("2", "CRANK", Vector3d(1, 0, 0)),
                                          body("3", "ROCKER", Vector3d(0, 2, 0))};
    SceneBuilder s;
    // VRML order differs from body order on purpose.
    const int rocker = s.add(-1, pose(Vector3d(0, 2, 0)));
    const int base = s.add(-1, pose(Vector3d(0, 0, 0)));
    const int crank = s.add(-1, pose(Vector3d(1, 0, 0)));
    s.mesh(rocker, tetra("rocker_shape"));
    s.mesh(base, tetra());
    s.mesh(crank, tetra());

    const MatchResult r = match_shapes(s.scene, bodies);
    CHECK(r.issues.empty());
    CHECK(r.matched_nodes == 3);
    CHECK(r.vrml_scale == 1);
    REQUIRE(r.meshes.size() == 3);
    CHECK(r.meshes[0].body == 2);
    CHECK(r.meshes[0].node == rocker);
    CHECK(r.meshes[0].name == "rocker_shape");
    CHECK(r.meshes[1].body == 0);
    CHECK(r.meshes[2].body == 1);
    CHECK(r.meshes[2].triangles == tetra().triangles);
    // The node sits on the body frame, so local coordinates are body coordinates.
    for (const auto& m : r.meshes) CHECK(m.vertices == tetra().vertices);
}

TEST_CASE("positions coincide within the tolerance, and only within it") {
    // Bounding-box diagonal 10 -> default tolerance 1e-3.
    const std::vector<BodyPose> bodies = {body("a", "A", Vector3d(0, 0, 0)), body("b", "B", Vector3d(10, 0, 0))};
    SceneBuilder s;
    const int near = s.add(-1, pose(Vector3d(10 + 6e-4, -3e-4, 0)));
    const int far = s.add(-1, pose(Vector3d(10 + 2e-3, 0, 0)));
    s.mesh(near, tetra());
    s.mesh(far, tetra());
    MatchResult r = match_shapes(s.scene, bodies);
    REQUIRE(r.meshes.size() == 1);
    CHECK(r.meshes[0].node == near);
    CHECK(r.meshes[0].body == 1);
    CHECK(count_issues(r, MatchIssue::unmatched) == 1);

    MatchOptions wide;
    wide.position_tolerance = 0.01;
    r = match_shapes(s.scene, bodies, wide);
    CHECK(r.meshes.size() == 2);
    CHECK(r.issues.empty());
}

TEST_CASE("orientation separates bodies that share a position") {
    const Matrix3d rz = rot(Vector3d::UnitZ(), kPi / 2);
    const std::vector<BodyPose> bodies = {body("p1", "Plate", Vector3d(1, 1, 0)),
                                          body("p2", "Plate", Vector3d(1, 1, 0), rz),
                                          body("far", "Far", Vector3d(5, 5, 5))};
    SceneBuilder s;
    const int turned = s.add(-1, pose(Vector3d(1, 1, 0), rz));
    // The same orientation under a uniform VRML scale: the polar factor of
    // the node's linear part is still rz.
    const int scaled = s.add(-1, pose(Vector3d(1, 1, 0), rz, 2.5));
    const int straight = s.add(-1, pose(Vector3d(1, 1, 0)));
    // Rounded the way a 6-digit exporter rounds: well inside 1e-3 rad.
    Matrix3d rounded = rz;
    rounded(0, 1) = -0.999999;
    rounded(1, 0) = 1.000001;
    const int rounded_node = s.add(-1, pose(Vector3d(1, 1, 0), rounded));
    for (int n : {turned, scaled, straight, rounded_node}) s.mesh(n, tetra());

    const MatchResult r = match_shapes(s.scene, bodies);
    CHECK(r.issues.empty());
    REQUIRE(r.meshes.size() == 4);
    CHECK(r.meshes[0].body == 1);
    CHECK(r.meshes[1].body == 1);
    CHECK(r.meshes[2].body == 0);
    CHECK(r.meshes[3].body == 1);
}

TEST_CASE("name prefixes separate bodies that share a pose") {
    const Vector3d p(0.3, -0.2, 0.1);
    const std::vector<BodyPose> bodies = {body("10", "Bracket", p), body("11", "Obj", p), body("12", "Washer-1", p)};
    SceneBuilder s;
    // Model_Info part name with an instance number, DEF name differently numbered.
    const int a = s.add(-1, pose(p), "", "OBJ01");
    const int b = s.add(-1, pose(p), "Obj_2");
    const int c = s.add(-1, pose(p), "", "washer");
    // The part name decides over a misleading DEF name.
    const int d = s.add(-1, pose(p), "Washer_7", "Bracket02");
    for (int n : {a, b, c, d}) s.mesh(n, tetra());

    const MatchResult r = match_shapes(s.scene, bodies);
    CHECK(r.issues.empty());
    REQUIRE(r.meshes.size() == 4);
    CHECK(bodies[size_t(r.meshes[0].body)].name == "Obj");
    CHECK(bodies[size_t(r.meshes[1].body)].name == "Obj");
    CHECK(bodies[size_t(r.meshes[2].body)].name == "Washer-1");
    CHECK(bodies[size_t(r.meshes[3].body)].name == "Bracket");
}

TEST_CASE("an exact name wins over a shared prefix") {
    const std::vector<BodyPose> bodies = {body("1", "Obj01", Vector3d::Zero()), body("2", "Obj02", Vector3d::Zero())};
    SceneBuilder s;
    const int n = s.add(-1, pose(Vector3d::Zero()), "", "obj02");
    s.mesh(n, tetra());
    const MatchResult r = match_shapes(s.scene, bodies);
    CHECK(r.issues.empty());
    REQUIRE(r.meshes.size() == 1);
    CHECK(r.meshes[0].body == 1);
}

TEST_CASE("a rigid sub-assembly's parts under one body's Transform all go to that body") {
    // The thesis's Mitsubishi arm: segment 2 is ONE body in the PMXML and a
    // Transform with three part Transforms in the VRML, at poses no body has.
    const Matrix3d r2 = rot(Vector3d(0, 1, 1), 0.7);
    const Vector3d p2(0.1, 0.0, 0.45);
    const std::vector<BodyPose> bodies = {body("base", "BASE", Vector3d::Zero()),
                                          body("seg1", "SEGMENT1", Vector3d(0, 0, 0.3)),
                                          body("seg2", "SEGMENT2_ASM", p2, r2),
                                          body("seg3", "SEGMENT3", Vector3d(0.5, 0, 0.7))};
    SceneBuilder s;
    s.mesh(s.add(-1, pose(Vector3d::Zero()), "BASE"), tetra());
    s.mesh(s.add(-1, pose(Vector3d(0, 0, 0.3)), "SEGMENT1"), tetra());
    const int asm2 = s.add(-1, pose(p2, r2), "SEGMENT2_ASM");
    const int housing = s.add(asm2, pose(Vector3d(0.05, 0, 0), rot(Vector3d::UnitX(), 0.3)), "", "HOUSING");
    const int tube = s.add(asm2, pose(Vector3d(0.15, 0.01, 0)), "", "TUBE");
    const int inl = s.add(tube, pose(Vector3d::Zero()), "", "", "Inline");
    const int elbow = s.add(asm2, pose(Vector3d(0.3, 0, 0.02), rot(Vector3d::UnitZ(), -0.4)), "", "ELBOW");
    s.mesh(housing, tetra("housing"));
    s.mesh(inl, tetra("tube"));
    s.mesh(elbow, tetra("elbow"));
    s.mesh(s.add(-1, pose(Vector3d(0.5, 0, 0.7)), "SEGMENT3"), tetra());

    const MatchResult r = match_shapes(s.scene, bodies);
    CHECK(r.issues.empty());
    CHECK(r.matched_nodes == 4);
    REQUIRE(r.meshes.size() == 6);
    size_t seg2_meshes = 0;
    for (const auto& m : r.meshes) seg2_meshes += m.body == 2;
    CHECK(seg2_meshes == 3);
    CHECK(r.meshes[2].name == "housing");
    CHECK(r.meshes[3].name == "tube");
    CHECK(r.meshes[4].name == "elbow");
    CHECK(r.meshes[5].body == 3);
    // The tube's origin lies 0.15 along the sub-assembly's x, 0.01 along its y.
    CHECK((first_vertex(r.meshes[3]) - Vector3d(0.15, 0.01, 0)).norm() < 1e-12);
}

TEST_CASE("shapes under no body are reported with the node's names and location") {
    const std::vector<BodyPose> bodies = {body("1", "BASE", Vector3d::Zero()), body("2", "ARM", Vector3d(1, 0, 0))};
    SceneBuilder s("robot_a.wrl");
    const int stray = s.add(-1, pose(Vector3d(0.4, 0.4, 0)), "LOOSE_SCREW", "SCREW_M4");
    s.mesh(stray, tetra());
    s.mesh(stray, tetra());
    const int ok = s.add(-1, pose(Vector3d(1, 0, 0)));
    s.mesh(ok, tetra());

    const MatchResult r = match_shapes(s.scene, bodies);
    REQUIRE(r.meshes.size() == 1);
    CHECK(r.meshes[0].body == 1);
    REQUIRE(r.issues.size() == 1);
    const MatchIssue& issue = r.issues[0];
    CHECK(issue.kind == MatchIssue::unmatched);
    CHECK(issue.node == stray);
    CHECK(contains(issue.message, "LOOSE_SCREW"));
    CHECK(contains(issue.message, "SCREW_M4"));
    CHECK(contains(issue.message, "robot_a.wrl:10"));
    CHECK(contains(issue.message, "2 shape(s)"));
}

TEST_CASE("a pose and name that fit several bodies is reported and keeps the parent's body") {
    const Vector3d p(0.2, 0, 0);
    const std::vector<BodyPose> bodies = {body("frame", "FRAME", Vector3d::Zero()), body("l", "LEFT_PIN", p),
                                          body("r", "RIGHT_PIN", p)};
    SceneBuilder s;
    const int frame = s.add(-1, pose(Vector3d::Zero()), "FRAME");
    const int pin = s.add(frame, pose(p), "PIN_1", "PIN");
    s.mesh(pin, tetra("pin"));
    // The pin's Inline on the same pose asks the same question: not reported twice.
    const int inl = s.add(pin, pose(Vector3d::Zero()), "", "", "Inline");
    s.mesh(inl, tetra("pin_geometry"));

    const MatchResult r = match_shapes(s.scene, bodies);
    REQUIRE(r.issues.size() == 1);
    const MatchIssue& issue = r.issues[0];
    CHECK(issue.kind == MatchIssue::ambiguous);
    CHECK(issue.node == pin);
    CHECK(contains(issue.message, "PIN_1"));
    CHECK(contains(issue.message, "'PIN'"));
    CHECK(contains(issue.message, "LEFT_PIN"));
    CHECK(contains(issue.message, "RIGHT_PIN"));
    CHECK(contains(issue.message, "FRAME"));
    CHECK(contains(issue.message, "position and orientation"));
    REQUIRE(r.meshes.size() == 2);
    CHECK(r.meshes[0].body == 0);
    CHECK(r.meshes[1].body == 0);
    // In the frame's coordinates the pin node sits at p.
    CHECK((first_vertex(r.meshes[0]) - p).norm() < 1e-12);
}

TEST_CASE("the VRML unit is found automatically: millimetres against metres and back") {
    const Matrix3d r1 = rot(Vector3d(1, 2, 3), 0.9);
    const std::vector<BodyPose> metres = {body("g", "GROUND", Vector3d(0.1, 0.2, 0)),
                                          body("a", "ARM", Vector3d(0.4, 0.25, 0.05), r1),
                                          body("b", "BAR", Vector3d(0.7, -0.1, 0.3))};
    SceneBuilder mm;
    // Pro/E writes VRML in the part unit: translations and vertices in mm.
    const int g = mm.add(-1, pose(Vector3d(100, 200, 0)));
    const int a = mm.add(-1, pose(Vector3d(400, 250, 50), r1));
    const int b = mm.add(-1, pose(Vector3d(700, -100, 300)));
    for (int n : {g, a, b}) mm.mesh(n, tetra("", 20));

    MatchResult r = match_shapes(mm.scene, metres);
    CHECK(r.vrml_scale == mbx_test::relative(0.001, 1e-6));
    CHECK(r.matched_nodes == 3);
    CHECK(r.issues.empty());
    REQUIRE(r.meshes.size() == 3);
    CHECK(r.meshes[1].body == 1);
    // 20 mm along the node's x is 0.02 m along the body's x.
    CHECK(r.meshes[1].vertices[3] == mbx_test::relative(0.02, 1e-6));
    CHECK(std::abs(r.meshes[1].vertices[4]) < 1e-12);

    // The other way: a model in millimetres, VRML in metres (stl2vrml).
    std::vector<BodyPose> millimetres = metres;
    for (BodyPose& p : millimetres) p.world.translation() *= 1000;
    SceneBuilder m;
    const int g2 = m.add(-1, pose(Vector3d(0.1, 0.2, 0)));
    const int a2 = m.add(-1, pose(Vector3d(0.4, 0.25, 0.05), r1));
    m.mesh(g2, tetra());
    m.mesh(a2, tetra());
    r = match_shapes(m.scene, millimetres);
    CHECK(r.vrml_scale == 1000);
    CHECK(r.matched_nodes == 2);
    CHECK(r.issues.empty());

    // Inches against millimetres.
    SceneBuilder in;
    const int g3 = in.add(-1, pose(Vector3d(100, 200, 0) / 25.4));
    in.mesh(g3, tetra());
    r = match_shapes(in.scene, millimetres);
    CHECK(r.vrml_scale == 25.4);

    // A stated scale is used as is, even when another would match more.
    MatchOptions stated;
    stated.vrml_scale = 1;
    r = match_shapes(mm.scene, metres, stated);
    CHECK(r.vrml_scale == 1);
    CHECK(r.matched_nodes == 0);
    CHECK(count_issues(r, MatchIssue::unmatched) == 3);
}

TEST_CASE("vertices land in the body frame of a rotated, displaced body") {
    // Body frame: origin (1, 2, 3), axes turned 90 deg about world z
    // (body x = world y, body y = -world x).
    const Matrix3d rz = rot(Vector3d::UnitZ(), kPi / 2);
    const std::vector<BodyPose> bodies = {body("arm", "ARM", Vector3d(1, 2, 3), rz)};
    SceneBuilder s;
    const int arm = s.add(-1, pose(Vector3d(1, 2, 3), rz), "ARM");
    // A child part shifted 0.5 along the arm's x and scaled by 2 (VRML scale).
    const int part = s.add(arm, pose(Vector3d(0.5, 0, 0), Matrix3d::Identity(), 2.0));
    mbx_files::VrmlMesh m;
    m.vertices = {0, 1, 0};  // local vertex
    m.triangles = {};
    s.mesh(part, m);

    MatchResult r = match_shapes(s.scene, bodies);
    REQUIRE(r.meshes.size() == 1);
    // By hand: scaled (0, 2, 0), shifted (0.5, 2, 0) in the arm's frame;
    // in world (1, 2, 3) + Rz(90)(0.5, 2, 0) = (1 - 2, 2 + 0.5, 3) = (-1, 2.5, 3).
    const Vector3d in_body = first_vertex(r.meshes[0]);
    CHECK((in_body - Vector3d(0.5, 2, 0)).norm() < 1e-12);
    CHECK((bodies[0].world * in_body - Vector3d(-1, 2.5, 3)).norm() < 1e-12);
    CHECK((s.scene.nodes[size_t(part)].world * Vector3d(0, 1, 0) - Vector3d(-1, 2.5, 3)).norm() < 1e-12);

    // The same scene written in millimetres: the body-frame point is in
    // model units (metres), not VRML units.
    SceneBuilder mm;
    const int arm_mm = mm.add(-1, pose(Vector3d(1000, 2000, 3000), rz), "ARM");
    const int part_mm = mm.add(arm_mm, pose(Vector3d(500, 0, 0), Matrix3d::Identity(), 2.0));
    m.vertices = {0, 1000, 0};
    mm.mesh(part_mm, m);
    r = match_shapes(mm.scene, bodies);
    CHECK(r.vrml_scale == mbx_test::relative(0.001, 1e-6));
    REQUIRE(r.meshes.size() == 1);
    CHECK((first_vertex(r.meshes[0]) - Vector3d(0.5, 2, 0)).norm() < 1e-12);
}

TEST_CASE("a deeper node that hits another body takes over its subtree") {
    const std::vector<BodyPose> bodies = {body("a", "A", Vector3d::Zero()), body("b", "B", Vector3d(0, 0, 1))};
    SceneBuilder s;
    const int a = s.add(-1, pose(Vector3d::Zero()));
    const int b = s.add(a, pose(Vector3d(0, 0, 1)));
    const int under_b = s.add(b, pose(Vector3d(0.3, 0, 0)));
    const int under_a = s.add(a, pose(Vector3d(0.3, 0, 0)));
    for (int n : {a, b, under_b, under_a}) s.mesh(n, tetra());
    const MatchResult r = match_shapes(s.scene, bodies);
    REQUIRE(r.meshes.size() == 4);
    CHECK(r.meshes[0].body == 0);
    CHECK(r.meshes[1].body == 1);
    CHECK(r.meshes[2].body == 1);
    CHECK(r.meshes[3].body == 0);
}

TEST_CASE("empty and degenerate input") {
    SceneBuilder s;
    const int n = s.add(-1, pose(Vector3d(1, 1, 1)));
    s.mesh(n, tetra());
    // No bodies: every shape is unmatched, nothing crashes.
    MatchResult r = match_shapes(s.scene, {});
    CHECK(r.meshes.empty());
    CHECK(count_issues(r, MatchIssue::unmatched) == 1);

    // A NaN pose matches nothing; one body alone still matches exactly.
    const std::vector<BodyPose> one = {body("1", "ONLY", Vector3d(1, 1, 1))};
    const int bad = s.add(-1, pose(Vector3d(NAN, 0, 0)));
    s.mesh(bad, tetra());
    r = match_shapes(s.scene, one);
    REQUIRE(r.meshes.size() == 1);
    CHECK(r.meshes[0].node == n);
    CHECK(count_issues(r, MatchIssue::unmatched) == 1);

    // Empty scene.
    r = match_shapes(mbx_files::VrmlScene{}, one);
    CHECK(r.meshes.empty());
    CHECK(r.issues.empty());
    CHECK(r.matched_nodes == 0);
}
}  // namespace MBX_UNITY_ID
