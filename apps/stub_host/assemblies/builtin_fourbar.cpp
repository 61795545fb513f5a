// fourbar: a planar four-bar served in millimetres and grams (inertia factor
// 0, so g*mm^2), the way Pro/E exports its "RootPart" assemblies:
//
//   ground (MBX_BODY_GROUND) =weld= RootPart (MBX_BODY_HELPER, massless)
//   =weld= ground_link -rev_A- crank -rev_B- coupler -rev_C- rocker -rev_D- ground_link
//
// Pivots (mm, plane z = 10): A (0,0), B (24,32), C (114,62), D (120,0); a
// generic quadrilateral, so the linkage is not at a singular pose.
// rev_C's axis is -z (a flipped mate): antiparallel axes are still planar.
//
// Hand-derived translation (constraints in host order: weld_root, weld_link,
// rev_A, rev_B, rev_C, rev_D):
//   parts 6; the three welded parts merge into the ground body, so
//   rigid bodies 3 (crank, coupler, rocker); welds 2; joints 4, all revolute.
//   rev_D joins ground_link and rocker, already connected through A-B-C:
//   it is the cut joint, loop 0 = {rev_A, rev_B, rev_C, rev_D}.
//   Mobility: 4 joint rates, closure twists of 4 parallel axes span 3
//   dimensions (planar motions) -> rank 3, dof 4 - 3 = 1, redundant 6 - 3 = 3.
//   The loop is planar with normal +-z; planar Gruebler 4 - 3 = 1.
#include <cmath>

#include "builder.h"
#include "builtins.h"

namespace mbx_stub {
namespace builtins {

using namespace build;

Assembly fourbar() {
    Assembly a;
    a.name = "fourbar";
    a.source = "mbx_stub builtin fourbar (mm, g)";
    const mbx_units mm_g{1e-3, 1e-3, 0};
    Builder b(a, "fourbar", mm_g, mm_g);

    const double z = 0.010;
    const Vec3 A(0, 0, z), B(0.024, 0.032, z), C(0.114, 0.062, z), D(0.120, 0, z);
    const Mat3 I = Mat3::Identity();
    const Vec3 up = Vec3::UnitZ();

    b.body("ground", "Ground", MBX_BODY_GROUND, 2.0, I, Vec3::Zero(), Vec3(0.06, 0, -0.01),
           box_inertia(2.0, 0.3, 0.1, 0.02));
    b.body("RootPart", "RootPart", MBX_BODY_HELPER, 0.0, I, Vec3::Zero(), Vec3::Zero(), Mat3::Zero());
    const Vec3 mid_ad = (A + D) / 2;
    b.body("ground_link", "Ground link", 0, 0.060, I, mid_ad, mid_ad, box_inertia(0.060, 0.14, 0.02, 0.01));

    // Crank: body frame at pivot A, x along the crank, CoM half-way.
    const Mat3 r_crank = rotation_x_to(B - A, up);
    b.body("crank", "Crank", 0, 0.020, r_crank, A, (A + B) / 2, box_inertia(0.020, 0.050, 0.008, 0.005));
    // Coupler: body frame at its CoM, turned along B->C.
    const Mat3 r_coupler = rotation_x_to(C - B, up);
    b.body("coupler", "Coupler", 0, 0.045, r_coupler, (B + C) / 2, (B + C) / 2,
           box_inertia(0.045, (C - B).norm() + 0.01, 0.008, 0.005));
    // Rocker: body frame at its ground pivot D.
    const Mat3 r_rocker = rotation_x_to(C - D, up);
    b.body("rocker", "Rocker", 0, 0.030, r_rocker, D, (C + D) / 2,
           box_inertia(0.030, (C - D).norm() + 0.01, 0.008, 0.005));

    b.joint("weld_root", "ground", "RootPart", Vec3::Zero(), I, {weld()}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_BODY);
    b.joint("weld_link", "RootPart", "ground_link", A, I, {weld()}, MBX_FRAME_IN_BODY, MBX_FRAME_IN_WORLD);
    b.joint("rev_A", "ground_link", "crank", A, rotation_z_to(up, 0.3), {revolute(up, MBX_AXIS_IN_WORLD)},
            MBX_FRAME_IN_BODY, MBX_FRAME_IN_WORLD);
    b.joint("rev_B", "crank", "coupler", B, rotation_z_to(Vec3(0.2, -0.1, 1), 1.1),
            {revolute(up, MBX_AXIS_IN_BASE_FRAME)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_BODY);
    b.joint("rev_C", "coupler", "rocker", C, rotation_z_to(-up, 0.0), {revolute(-up, MBX_AXIS_IN_WORLD)},
            MBX_FRAME_IN_BODY, MBX_FRAME_IN_BODY);
    b.joint("rev_D", "ground_link", "rocker", D, rotation_z_to(up, -0.7), {revolute(up, MBX_AXIS_IN_BASE_FRAME)},
            MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);

    b.mesh("ground", box_mesh("plate", Vec3(0.3, 0.1, 0.02), I, Vec3(0.06, 0, -0.01)));
    b.mesh("ground_link", box_mesh("bar", Vec3(0.14, 0.02, 0.01), I, Vec3::Zero()));
    b.mesh("crank", box_mesh("bar", Vec3(0.050, 0.008, 0.005), I, Vec3(0.020, 0, 0)));
    b.mesh("coupler", box_mesh("bar", Vec3((C - B).norm() + 0.01, 0.008, 0.005), I, Vec3::Zero()));
    b.mesh("coupler", box_mesh("pin", Vec3(0.006, 0.006, 0.012), I, Vec3((C - B).norm() / 2, 0, 0)));
    b.mesh("rocker", box_mesh("bar", Vec3((C - D).norm() + 0.01, 0.008, 0.005), I,
                              Vec3((C - D).norm() / 2, 0, 0)));
    return a;
}

}  // namespace builtins
}  // namespace mbx_stub
