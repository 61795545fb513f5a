// planar_sixbar: a Watt six-bar (the two ternary links, ground and rocker,
// share joint g_R), served in SI with every unit factor 0 ("already SI"),
// in a plane tilted away from every coordinate plane.
//
// Pivots in plane coordinates (m): O_A (0,0), P1 (.03,.04), P2 (.12,.06),
// O_R (.10,0), P3 (.15,.05), P4 (.22,.08), O_D (.20,0).
//   ground  (ternary: O_A, O_R, O_D)     crank   (O_A, P1)
//   coupler1 (P1, P2)                    rocker  (ternary: P2, O_R, P3)
//   coupler2 (P3, P4)                    lever   (P4, O_D)
// Host order: g_A, A_C1, C1_R, g_R, R_C2, C2_D, g_D.
//
// Hand-derived translation:
//   parts 6, rigid bodies 5, welds 0, joints 7 (all revolute, axes parallel
//   to the plane normal n; A_C1 is served as -n).
//   Planar Gruebler: 3 (6 - 1) - 2 * 7 = 1.
//   Cuts in host order: g_R closes ground-crank-coupler1-rocker (loop 0,
//   joints g_A, A_C1, C1_R, g_R: 4); g_D closes the path ground-crank-
//   coupler1-rocker-coupler2-lever (loop 1, joints g_A, A_C1, C1_R, R_C2,
//   C2_D, g_D: 6). Both planar.
//   Per loop alone: loop 0 dof 4 - 3 = 1, redundant 3; loop 1 dof 6 - 3 = 3,
//   redundant 3 (planar Gruebler 1 and 3).
//   Whole: 12 closure equations of rank 6 (3 per planar loop, independent
//   because each loop has a joint the other lacks) -> dof 7 - 6 = 1,
//   redundant 12 - 6 = 6.
#include "builder.h"
#include "builtins.h"

namespace mbx_stub {
namespace builtins {

using namespace build;

Assembly planar_sixbar() {
    Assembly a;
    a.name = "planar_sixbar";
    a.source = "mbx_stub builtin planar_sixbar (SI, unit factors 0)";
    const mbx_units si{0, 0, 0};
    Builder b(a, "planar_sixbar", si, si);

    const Mat3 plane = axis_angle(Vec3(1, -2, 0.5), 0.9);
    const Vec3 origin(0.3, -0.1, 0.25);
    const Vec3 n = plane.col(2);
    auto at = [&](double x, double y) { return Vec3(origin + plane * Vec3(x, y, 0)); };
    const Vec3 OA = at(0, 0), P1 = at(0.03, 0.04), P2 = at(0.12, 0.06), OR = at(0.10, 0), P3 = at(0.15, 0.05),
               P4 = at(0.22, 0.08), OD = at(0.20, 0);

    b.body("ground", "Ground", MBX_BODY_GROUND, 5.0, plane, origin, at(0.1, -0.02),
           box_inertia(5.0, 0.3, 0.08, 0.02));
    auto bar = [&](const std::string& local, const std::string& name, double mass, const Vec3& p, const Vec3& q,
                   bool frame_at_p) {
        const Mat3 r = rotation_x_to(q - p, n);
        const double len = (q - p).norm() + 0.012;
        b.body(local, name, 0, mass, r, frame_at_p ? p : Vec3((p + q) / 2), (p + q) / 2,
               box_inertia(mass, len, 0.01, 0.006));
        b.mesh(local, box_mesh("bar", Vec3(len, 0.01, 0.006), Mat3::Identity(),
                               frame_at_p ? Vec3((q - p).norm() / 2, 0, 0) : Vec3::Zero()));
    };
    bar("crank", "Crank", 0.08, OA, P1, true);
    bar("coupler1", "Coupler 1", 0.15, P1, P2, false);
    {
        const Vec3 centroid = (P2 + OR + P3) / 3;
        const Mat3 r = plane * axis_angle(Vec3::UnitZ(), 0.4);
        b.body("rocker", "Rocker", 0, 0.25, r, centroid, centroid, box_inertia(0.25, 0.07, 0.05, 0.006));
        b.mesh("rocker", box_mesh("plate", Vec3(0.07, 0.05, 0.006), Mat3::Identity(), Vec3::Zero()));
    }
    bar("coupler2", "Coupler 2", 0.12, P3, P4, false);
    bar("lever", "Lever", 0.10, OD, P4, true);
    b.mesh("ground", box_mesh("base", Vec3(0.3, 0.08, 0.02), Mat3::Identity(), Vec3(0.1, -0.02, 0)));

    const mbx_frame_reference W = MBX_FRAME_IN_WORLD, B = MBX_FRAME_IN_BODY;
    b.joint("g_A", "ground", "crank", OA, rotation_z_to(n, 0.2), {revolute(n, MBX_AXIS_IN_WORLD)}, W, B);
    b.joint("A_C1", "crank", "coupler1", P1, rotation_z_to(-n, 0.5), {revolute(-n, MBX_AXIS_IN_BASE_FRAME)}, B, W);
    b.joint("C1_R", "coupler1", "rocker", P2, rotation_z_to(n, 1.0), {revolute(n, MBX_AXIS_IN_BASE_FRAME)}, B, B);
    b.joint("g_R", "ground", "rocker", OR, rotation_z_to(n, 0.0), {revolute(n, MBX_AXIS_IN_WORLD)}, W, W);
    b.joint("R_C2", "rocker", "coupler2", P3, rotation_z_to(n, 2.0), {revolute(n, MBX_AXIS_IN_BASE_FRAME)}, B, W);
    b.joint("C2_D", "coupler2", "lever", P4, rotation_z_to(n, -1.0), {revolute(n, MBX_AXIS_IN_WORLD)}, W, B);
    b.joint("g_D", "ground", "lever", OD, rotation_z_to(n, 0.7), {revolute(n, MBX_AXIS_IN_BASE_FRAME)}, B, B);
    return a;
}

}  // namespace builtins
}  // namespace mbx_stub
