// double_cardan: the thesis's double cardan shaft. An input shaft and an
// output shaft turn in bearings on a ground frame, parallel to world x and
// offset; a centre yoke joins them through two cardan (Hooke) joints and
// turns in a third bearing on the frame. Bodies are served in centimetres,
// kilograms and kg*cm^2; frames in millimetres (the SDK must convert each
// with its own units).
//
//   frame (ground) -bearing_in- input_shaft =weld= input_yoke -cross1_in-
//   cross1 -cross1_out- centre_yoke -cardan2 (2R chain: b2 then a2)- output_shaft
//   frame -bearing_centre- centre_yoke        frame -bearing_out- output_shaft
//
// Cardan 1 has its cross as a body; cardan 2 is one CAD joint whose chain of
// two revolutes leaves its cross as a massless joint node.
// Geometry (m): cardan centres P1 = (0.2,0,0) on the input axis and
// P2 = P1 + 0.3 c on the output axis, c = (cos 20deg, sin 20deg, 0) the centre
// yoke axis. Input fork a1 = (0, -sin 30deg, cos 30deg) (perpendicular to x),
// centre forks b1 = b2 = unit(c x a1) (perpendicular to c and a1: the centre yoke's
// forks in phase), output fork a2 = unit(x x b2).
//
// Hand-derived mobility (host order: bearing_in, weld_input_yoke, cross1_in,
// cross1_out, bearing_centre, bearing_out, cardan2):
//   parts 6 (frame, input_shaft, input_yoke, cross1, centre_yoke,
//   output_shaft), 1 weld -> rigid bodies 4 (input shaft+yoke, cross1,
//   centre yoke, output shaft) + 1 joint node (cardan2's cross); joints 7,
//   all revolute.
//   bearing_centre finds frame and centre_yoke already joined through
//   input shaft and cross1: cut, loop 0 = {bearing_in, cross1_in, cross1_out,
//   bearing_centre}. cardan2's J_N (centre_yoke -> node) is a tree edge; its
//   J_1 (node -> output_shaft) closes a cycle through bearing_out: cut,
//   loop 1 = {cardan2#0, cross1_out, cross1_in, bearing_in, bearing_out,
//   cardan2#1}. Neither loop is planar.
//   Loop 0 alone: four revolute axes x, a1, b1, c all through P1, a spherical
//     four-bar. Their twists are rotations about P1 and x, a1, b1 are
//     independent (b1 is not parallel to x), so rank 3:
//     dof 4 - 3 = 1, redundant 6 - 3 = 3, Gruebler 4 - 6 = -2.
//   Loop 1 alone: three rotations about P1 (x, a1, b1: span all rotations
//     about P1) and three about P2 (b2, a2, x: independent since b2 is not
//     parallel to x). Rotations about P1 and about P2 share exactly the
//     rotation about line P1P2, so rank 3 + 3 - 1 = 5:
//     dof 6 - 5 = 1 (the centre yoke spinning about P1P2), redundant 1,
//     Gruebler 6 - 6 = 0.
//   Whole mechanism, 7 joint rates: loop 0 makes the rotation Omega1 of the
//     three P1 joints equal to the bearing_centre rate about c; loop 1 needs
//     Omega1 about P1 and Omega2 about P2 to cancel, which forces
//     Omega2 = -Omega1, possible exactly because Omega1 is along P1P2. So
//     one free rate (bearing_centre) fixes all the others: dof 1.
//     rank = 7 - 1 = 6, redundant = 12 - 6 = 6. (Spatial Gruebler:
//     6 * 5 moving bodies incl. the node - 5 * 7 = -5.)
#include <cmath>

#include "builder.h"
#include "builtins.h"

namespace mbx_stub {
namespace builtins {

using namespace build;

Assembly double_cardan() {
    Assembly a;
    a.name = "double_cardan";
    a.source = "mbx_stub builtin double_cardan (bodies cm, kg, kg*cm^2; frames mm)";
    const mbx_units cm_kg{0.01, 1.0, 1e-4};
    const mbx_units mm{1e-3, 1.0, 0};
    Builder b(a, "double_cardan", cm_kg, mm);

    const double deg = kDeg;
    const Vec3 x = Vec3::UnitX();
    const Vec3 P1(0.2, 0, 0);
    const Vec3 c(std::cos(20 * deg), std::sin(20 * deg), 0);
    const Vec3 P2 = P1 + 0.3 * c;
    const Vec3 a1(0, -std::sin(30 * deg), std::cos(30 * deg));
    const Vec3 b1 = c.cross(a1).normalized();
    const Vec3 b2 = b1;
    const Vec3 a2 = x.cross(b2).normalized();
    const Mat3 I = Mat3::Identity();

    b.body("frame", "Frame", MBX_BODY_GROUND, 20.0, I, Vec3::Zero(), Vec3(0.3, 0.05, -0.1),
           box_inertia(20.0, 0.8, 0.3, 0.05));
    b.body("input_shaft", "Input shaft", 0, 1.2, I, Vec3(0.09, 0, 0), Vec3(0.09, 0, 0),
           box_inertia(1.2, 0.18, 0.03, 0.03));
    const Mat3 r_yoke = axis_angle(x, 30 * deg);
    b.body("input_yoke", "Input yoke", 0, 0.3, r_yoke, P1 - 0.02 * x, P1 - 0.025 * x,
           box_inertia(0.3, 0.04, 0.05, 0.06));
    b.body("cross1", "Cross 1", 0, 0.1, rotation_x_to(a1, b1), P1, P1, box_inertia(0.1, 0.05, 0.05, 0.015));
    b.body("centre_yoke", "Centre yoke", 0, 1.5, rotation_x_to(c, b1), P1 + 0.15 * c, P1 + 0.15 * c,
           box_inertia(1.5, 0.3, 0.04, 0.04));
    b.body("output_shaft", "Output shaft", 0, 1.2, I, P2, P2 + 0.1 * x, box_inertia(1.2, 0.2, 0.03, 0.03));

    const mbx_frame_reference W = MBX_FRAME_IN_WORLD, B = MBX_FRAME_IN_BODY;
    b.joint("bearing_in", "frame", "input_shaft", Vec3(0.05, 0, 0), rotation_z_to(x, 0.4),
            {revolute(x, MBX_AXIS_IN_WORLD)}, W, B);
    b.joint("weld_input_yoke", "input_shaft", "input_yoke", P1 - 0.04 * x, r_yoke, {weld()}, B, W);
    b.joint("cross1_in", "input_yoke", "cross1", P1, rotation_z_to(a1, 0.9), {revolute(a1, MBX_AXIS_IN_BASE_FRAME)},
            W, B);
    b.joint("cross1_out", "cross1", "centre_yoke", P1, rotation_z_to(b1, -0.3), {revolute(b1, MBX_AXIS_IN_WORLD)},
            B, B);
    b.joint("bearing_centre", "frame", "centre_yoke", P1 + 0.15 * c, rotation_z_to(c, 1.3),
            {revolute(c, MBX_AXIS_IN_BASE_FRAME)}, W, W);
    b.joint("bearing_out", "frame", "output_shaft", P2 + 0.15 * x, rotation_z_to(x, -0.2),
            {revolute(x, MBX_AXIS_IN_WORLD)}, B, W);
    b.joint("cardan2", "centre_yoke", "output_shaft", P2, rotation_z_to(b2, 0.6),
            {revolute(b2, MBX_AXIS_IN_BASE_FRAME), revolute(a2, MBX_AXIS_IN_WORLD)}, B, B);

    b.mesh("frame", box_mesh("bed", Vec3(0.8, 0.3, 0.05), I, Vec3(0.3, 0.05, -0.1)));
    b.mesh("input_shaft", box_mesh("shaft", Vec3(0.18, 0.03, 0.03), I, Vec3::Zero()));
    b.mesh("input_yoke", box_mesh("fork", Vec3(0.04, 0.05, 0.06), I, Vec3(-0.005, 0, 0)));
    b.mesh("cross1", box_mesh("arm_a", Vec3(0.05, 0.012, 0.012), I, Vec3::Zero()));
    b.mesh("cross1", box_mesh("arm_b", Vec3(0.012, 0.05, 0.012), I, Vec3::Zero()));
    b.mesh("centre_yoke", box_mesh("tube", Vec3(0.3, 0.04, 0.04), I, Vec3::Zero()));
    b.mesh("output_shaft", box_mesh("shaft", Vec3(0.2, 0.03, 0.03), I, Vec3(0.1, 0, 0)));
    return a;
}

}  // namespace builtins
}  // namespace mbx_stub
