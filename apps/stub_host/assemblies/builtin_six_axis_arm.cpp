// six_axis_arm: a 6R industrial arm with a spherical wrist, in SI with every
// unit factor stated explicitly (1, 1, 1). Link 2 is a rigid sub-assembly
// of THREE parts welded together (shoulder housing, tube, elbow housing);
// the tube's and the elbow's body frames are rotated and the elbow's inertia
// is a full (non-diagonal) tensor, so the compound inertia needs the tensor
// rotated into a common frame before the parallel-axis shift.
//
// Axes at the assembly pose: J1 world z; J2, J3 world y (parallel, as in a
// real arm); J4 along the forearm d3 = (cos 10deg, 0, -sin 10deg); J5 y;
// J6 along d6 = unit(1, 0, -1). J4 and J6 meet J5 at the wrist centre W.
// The pose is away from the elbow and wrist singularities (d3 != d6).
// J5 is served reversed (base frame on link 5, follower on link 4), as
// CAD users often mate it.
//
// Hand-derived translation: parts 9 (base, link1, 3 parts of link 2, links
// 3..6), welds 2, rigid bodies 6, joints 6 revolute, no loops, dof 6,
// redundant 0, J5 reversed. Link 2: mass 6 + 9 + 4 = 19 kg; its CoM and
// inertia are recomputed independently in the integration test.
#include "builder.h"
#include "builtins.h"

namespace mbx_stub {
namespace builtins {

using namespace build;

Assembly six_axis_arm() {
    Assembly a;
    a.name = "six_axis_arm";
    a.source = "mbx_stub builtin six_axis_arm (SI, explicit unit factors)";
    const mbx_units si{1, 1, 1};
    Builder b(a, "six_axis_arm", si, si);

    const Mat3 I = Mat3::Identity();
    const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
    const Vec3 S(0.15, 0, 0.6);
    const Vec3 d2(std::sin(30 * kDeg), 0, std::cos(30 * kDeg));
    const Vec3 E = S + 0.6 * d2;
    const Vec3 d3(std::cos(10 * kDeg), 0, -std::sin(10 * kDeg));
    const Vec3 Q4 = E + 0.3 * d3;
    const Vec3 W = E + 0.5 * d3;
    const Vec3 d6 = Vec3(1, 0, -1).normalized();
    const Vec3 F = W + 0.08 * d6;

    b.body("base", "Base", MBX_BODY_GROUND, 30.0, I, Vec3::Zero(), Vec3(0, 0, 0.15),
           box_inertia(30.0, 0.4, 0.4, 0.3));
    b.body("link1", "Turret", 0, 12.0, I, Vec3(0, 0, 0.45), Vec3(0.04, 0, 0.45), box_inertia(12.0, 0.3, 0.25, 0.3));

    // Link 2: three parts, three different body frames.
    const Mat3 r_housing = axis_angle(x, 90 * kDeg);
    b.body("link2_housing", "Shoulder housing", 0, 6.0, r_housing, S, S + Vec3(0, 0.05, 0),
           box_inertia(6.0, 0.16, 0.2, 0.16));
    const Mat3 r_tube = rotation_x_to(d2, y);
    b.body("link2_tube", "Upper arm tube", 0, 9.0, r_tube, S, S + 0.3 * d2, box_inertia(9.0, 0.6, 0.12, 0.10));
    const Mat3 r_elbow = axis_angle(Vec3(1, 1, 1), 40 * kDeg);
    const Mat3 q_elbow = axis_angle(Vec3(0, 1, 2), 0.5);
    b.body("link2_elbow", "Elbow housing", 0, 4.0, r_elbow, E, E + Vec3(0.02, -0.01, 0.03),
           q_elbow * box_inertia(4.0, 0.18, 0.14, 0.12) * q_elbow.transpose());

    const Mat3 r_d3 = rotation_x_to(d3, y);
    b.body("link3", "Forearm", 0, 5.0, I, E, E + 0.15 * d3, r_d3 * box_inertia(5.0, 0.32, 0.1, 0.1) * r_d3.transpose());
    b.body("link4", "Wrist roll", 0, 2.0, r_d3, Q4, Q4 + 0.1 * d3, box_inertia(2.0, 0.2, 0.08, 0.08));
    b.body("link5", "Wrist pitch", 0, 1.0, I, W, W + 0.02 * d6, box_inertia(1.0, 0.08, 0.1, 0.08));
    const Mat3 r_d6 = rotation_x_to(d6, y);
    b.body("link6", "Flange", 0, 0.3, r_d6, F, F + 0.01 * d6, box_inertia(0.3, 0.02, 0.08, 0.08));

    const mbx_frame_reference Wd = MBX_FRAME_IN_WORLD, Bd = MBX_FRAME_IN_BODY;
    b.joint("J1", "base", "link1", Vec3(0, 0, 0.3), I, {revolute(z, MBX_AXIS_IN_WORLD, -170 * kDeg, 170 * kDeg)}, Wd,
            Wd);
    b.joint("J2", "link1", "link2_housing", S, rotation_z_to(y, 0.5),
            {revolute(y, MBX_AXIS_IN_BASE_FRAME, -90 * kDeg, 150 * kDeg)}, Bd, Wd);
    b.joint("weld_tube", "link2_housing", "link2_tube", S, r_tube, {weld()}, Wd, Bd);
    b.joint("weld_elbow", "link2_tube", "link2_elbow", E, r_elbow, {weld()}, Bd, Bd);
    b.joint("J3", "link2_elbow", "link3", E, rotation_z_to(y, -0.4),
            {revolute(y, MBX_AXIS_IN_BASE_FRAME, -160 * kDeg, 70 * kDeg)}, Bd, Wd);
    b.joint("J4", "link3", "link4", Q4, rotation_z_to(d3, 0.0),
            {revolute(d3, MBX_AXIS_IN_WORLD, -185 * kDeg, 185 * kDeg)}, Wd, Bd);
    b.joint("J5", "link5", "link4", W, rotation_z_to(y, 1.2),
            {revolute(y, MBX_AXIS_IN_BASE_FRAME, -125 * kDeg, 125 * kDeg)}, Bd, Bd);
    b.joint("J6", "link5", "link6", F, rotation_z_to(d6, 0.3),
            {revolute(d6, MBX_AXIS_IN_WORLD, -360 * kDeg, 360 * kDeg)}, Wd, Wd);

    b.mesh("base", box_mesh("pedestal", Vec3(0.4, 0.4, 0.3), I, Vec3(0, 0, 0.15)));
    b.mesh("link1", box_mesh("turret", Vec3(0.3, 0.25, 0.3), I, Vec3(0.04, 0, 0)));
    b.mesh("link2_housing", box_mesh("motor", Vec3(0.16, 0.2, 0.16), I, Vec3(0, 0, -0.05)));
    b.mesh("link2_tube", box_mesh("tube", Vec3(0.6, 0.12, 0.10), I, Vec3(0.3, 0, 0)));
    b.mesh("link2_tube", box_mesh("flange", Vec3(0.02, 0.2, 0.2), axis_angle(x, 0.3), Vec3(0.0, 0, 0)));
    b.mesh("link2_elbow", box_mesh("housing", Vec3(0.18, 0.14, 0.12), q_elbow, Vec3(0.01, 0.0, 0.02)));
    b.mesh("link3", box_mesh("forearm", Vec3(0.32, 0.1, 0.1), r_d3, 0.15 * d3));
    b.mesh("link4", box_mesh("roll", Vec3(0.2, 0.08, 0.08), I, Vec3(0.1, 0, 0)));
    b.mesh("link5", box_mesh("pitch", Vec3(0.08, 0.1, 0.08), I, Vec3::Zero()));
    b.mesh("link6", box_mesh("flange", Vec3(0.02, 0.08, 0.08), I, Vec3(0.01, 0, 0)));
    return a;
}

}  // namespace builtins
}  // namespace mbx_stub
