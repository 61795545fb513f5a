// Small assemblies for the MJCF tests, built in SI with the stub builder:
// each exercises something the built-ins do not (spherical joints, a
// prismatic cut, a free body, odd names) or has an analytic answer (pendulum).
#pragma once
#include "apps/stub_host/assemblies/builder.h"
#include "apps/stub_host/assemblies/stub_assembly.h"

namespace xtest {
namespace mjcf_assemblies {

using namespace mbx_stub::build;

inline Prim prismatic(const Vec3& axis) {
    Prim p;
    p.type = MBX_PRIMITIVE_PRISMATIC;
    p.axis = axis.normalized();
    return p;
}

constexpr mbx_units kSI{1, 1, 1};
constexpr mbx_frame_reference kWorld = MBX_FRAME_IN_WORLD;

// A spatial mechanism: ground (posed away from the identity) -universal
// (revolute, node, revolute)- crank -spherical- coupler -spherical (cut)-
// ground; a cylindrical joint (prismatic, node, revolute) from the crank to a
// slider; a floating body with an arm on a revolute.
inline mbx_stub::Assembly spatial() {
    mbx_stub::Assembly a;
    a.name = "spatial";
    Builder b(a, "spatial", kSI, kSI);
    const Mat3 I = Mat3::Identity();
    const Vec3 P0(0, 0, 0.2), P1(0.1, 0.05, 0.25), P2(0.2, 0.1, 0.15), P3(0.06, 0, 0.21);
    const Vec3 d = Vec3(1, 0.2, 0.1).normalized();

    b.body("ground", "Ground", MBX_BODY_GROUND, 3.0, axis_angle(Vec3(1, 1, 0), 0.3), Vec3(0.05, -0.02, 0.1),
           Vec3(0.1, 0, 0.05), box_inertia(3.0, 0.3, 0.2, 0.05));
    b.body("crank", "Crank", 0, 0.5, rotation_z_to(Vec3(0.3, 0.2, 1), 0.4), P0, P0 + Vec3(0.05, 0.02, 0.02),
           box_inertia(0.5, 0.12, 0.03, 0.02));
    b.body("coupler", "Coupler", 0, 0.3, rotation_x_to(P2 - P1, Vec3::UnitZ()), (P1 + P2) / 2, (P1 + P2) / 2,
           box_inertia(0.3, (P2 - P1).norm(), 0.02, 0.02));
    b.body("slider", "Slider", 0, 0.2, axis_angle(Vec3(0, 1, 1), -0.5), P3 + 0.02 * d, P3 + 0.03 * d,
           box_inertia(0.2, 0.04, 0.03, 0.03));
    b.body("float", "Float", 0, 1.0, axis_angle(Vec3(1, -1, 2), 1.0), Vec3(0.5, 0.5, 0.5), Vec3(0.5, 0.52, 0.5),
           box_inertia(1.0, 0.1, 0.1, 0.2));
    b.body("float_arm", "Float arm", 0, 0.4, I, Vec3(0.55, 0.5, 0.5), Vec3(0.6, 0.5, 0.5),
           box_inertia(0.4, 0.1, 0.02, 0.02));

    b.joint("u", "ground", "crank", P0, rotation_z_to(Vec3(0, 0, 1), 0.2),
            {revolute(Vec3(0, 0, 1)), revolute(Vec3(1, 0.3, 0))}, kWorld, kWorld);
    b.joint("s1", "crank", "coupler", P1, I, {spherical()}, kWorld, kWorld);
    b.joint("cyl", "crank", "slider", P3, I, {prismatic(d), revolute(d)}, kWorld, kWorld);
    b.joint("arm", "float", "float_arm", Vec3(0.55, 0.5, 0.5), I, {revolute(Vec3(0, 1, 0.5))}, kWorld, kWorld);
    b.joint("s2", "coupler", "ground", P2, I, {spherical()}, kWorld, kWorld);

    b.mesh("ground", box_mesh("plate", Vec3(0.3, 0.2, 0.05), I, Vec3(0.1, 0, 0.05)));
    b.mesh("crank", box_mesh("bar", Vec3(0.12, 0.03, 0.02), I, Vec3(0.05, 0, 0)));
    b.mesh("coupler", box_mesh("bar", Vec3((P2 - P1).norm(), 0.02, 0.02), I, Vec3::Zero()));
    b.mesh("float", box_mesh("block", Vec3(0.1, 0.1, 0.2), I, Vec3::Zero()));
    return a;
}

// A compound pendulum on a revolute about world y through `pivot`, its
// body frame turned and offset from the centre of mass, its inertia a full
// tensor in body axes.
struct Pendulum {
    double mass = 2.0;
    Vec3 pivot{0, 0, 1};
    Vec3 com{0, 0.03, 0.8};  // world; 0.2 m below the pivot, 0.03 m along the axis
    Mat3 rotation = axis_angle(Vec3(1, 2, 3), 0.7);
    Mat3 inertia_body = axis_angle(Vec3(0, 1, 2), 0.5) * box_inertia(2.0, 0.05, 0.08, 0.3) *
                        axis_angle(Vec3(0, 1, 2), 0.5).transpose();

    // Moment of inertia about the pivot axis (parallel-axis theorem).
    double pivot_inertia() const {
        const Vec3 y = Vec3::UnitY();
        const Vec3 r = com - pivot;
        const double d2 = r.squaredNorm() - std::pow(r.dot(y), 2);
        return y.dot(rotation * inertia_body * rotation.transpose() * y) + mass * d2;
    }
    double arm() const {  // distance from the axis to the centre of mass
        const Vec3 r = com - pivot;
        return std::sqrt(r.squaredNorm() - std::pow(r.y(), 2));
    }

    mbx_stub::Assembly assembly() const {
        mbx_stub::Assembly a;
        a.name = "pendulum";
        Builder b(a, "pendulum", kSI, kSI);
        b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, Mat3::Identity(), Vec3::Zero(), Vec3::Zero(),
               box_inertia(1.0, 0.1, 0.1, 0.1));
        b.body("bob", "Bob", 0, mass, rotation, Vec3(0.01, 0.03, 0.85), com, inertia_body);
        b.joint("hinge", "ground", "bob", pivot, Mat3::Identity(), {revolute(Vec3::UnitY())}, kWorld, kWorld);
        return a;
    }
};

// A body connected to nothing (a floating root with a free joint): its frame
// is away from its centre of mass and its inertia is a full tensor.
struct Tumbler {
    double mass = 1.5;
    Mat3 rotation = axis_angle(Vec3(2, -1, 1), 0.9);
    Vec3 position{0.2, 0.1, 0.3};
    Vec3 com_body{0.02, -0.01, 0.03};
    Mat3 inertia_body = axis_angle(Vec3(1, 1, 0), 0.4) * box_inertia(1.5, 0.1, 0.2, 0.3) *
                        axis_angle(Vec3(1, 1, 0), 0.4).transpose();

    mbx_stub::Assembly assembly() const {
        mbx_stub::Assembly a;
        a.name = "tumbler";
        Builder b(a, "tumbler", kSI, kSI);
        b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, Mat3::Identity(), Vec3::Zero(), Vec3::Zero(),
               box_inertia(1.0, 0.1, 0.1, 0.1));
        b.body("tumbler", "Tumbler", 0, mass, rotation, position, position + rotation * com_body, inertia_body);
        return a;
    }
};

// Two links on parallel revolutes (world y), hanging in the x-z plane.
inline mbx_stub::Assembly double_pendulum() {
    mbx_stub::Assembly a;
    a.name = "double_pendulum";
    Builder b(a, "double_pendulum", kSI, kSI);
    const Vec3 O(0, 0, 1), E(0.1, 0, 0.75), T(0.25, 0, 0.7);
    b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, Mat3::Identity(), Vec3::Zero(), Vec3::Zero(),
           box_inertia(1.0, 0.1, 0.1, 0.1));
    b.body("upper", "Upper", 0, 1.0, rotation_x_to(E - O, Vec3::UnitY()), O, (O + E) / 2,
           box_inertia(1.0, (E - O).norm(), 0.03, 0.03));
    b.body("lower", "Lower", 0, 0.6, rotation_x_to(T - E, Vec3::UnitY()), E, (E + T) / 2,
           box_inertia(0.6, (T - E).norm(), 0.03, 0.03));
    b.joint("shoulder", "ground", "upper", O, Mat3::Identity(), {revolute(Vec3::UnitY())}, kWorld, kWorld);
    b.joint("elbow", "upper", "lower", E, Mat3::Identity(), {revolute(Vec3::UnitY())}, kWorld, kWorld);
    return a;
}

// A slider-crank in the vertical x-z plane whose prismatic joint (slider on
// the ground's x line) is the cut, so MJCF needs its helper slider.
inline mbx_stub::Assembly slider_crank() {
    mbx_stub::Assembly a;
    a.name = "slider_crank";
    Builder b(a, "slider_crank", kSI, kSI);
    const Vec3 A(0, 0, 0.5), B(0.05, 0, 0.53), C(0.2, 0, 0.5);
    const Vec3 y = Vec3::UnitY();
    const Mat3 I = Mat3::Identity();
    b.body("ground", "Ground", MBX_BODY_GROUND, 5.0, I, Vec3::Zero(), Vec3(0.1, 0, 0.45),
           box_inertia(5.0, 0.3, 0.05, 0.05));
    b.body("crank", "Crank", 0, 0.2, rotation_x_to(B - A, y), A, A + 0.7 * (B - A), box_inertia(0.2, 0.07, 0.01, 0.01));
    b.body("rod", "Rod", 0, 0.3, rotation_x_to(C - B, y), B, (B + C) / 2, box_inertia(0.3, 0.16, 0.01, 0.01));
    b.body("slider", "Slider", 0, 0.5, I, C, C, box_inertia(0.5, 0.04, 0.03, 0.03));
    b.joint("rev_a", "ground", "crank", A, I, {revolute(y)}, kWorld, kWorld);
    b.joint("rev_b", "crank", "rod", B, I, {revolute(y)}, kWorld, kWorld);
    b.joint("rev_c", "rod", "slider", C, I, {revolute(y)}, kWorld, kWorld);
    Prim slide = prismatic(Vec3::UnitX());
    slide.has_limits = true;
    slide.lower = -0.1;
    slide.upper = 0.05;
    b.joint("slide", "slider", "ground", C, I, {slide}, kWorld, kWorld);
    return a;
}

// Names that collide once sanitized (and with MuJoCo's "world").
inline mbx_stub::Assembly odd_names() {
    mbx_stub::Assembly a;
    a.name = "odd names";
    Builder b(a, "odd", kSI, kSI);
    const Mat3 I = Mat3::Identity();
    b.body("ground", "world", MBX_BODY_GROUND, 1.0, I, Vec3::Zero(), Vec3::Zero(), box_inertia(1.0, 0.1, 0.1, 0.1));
    b.body("a", "Link 1", 0, 1.0, I, Vec3(0.1, 0, 0), Vec3(0.1, 0, 0), box_inertia(1.0, 0.1, 0.02, 0.02));
    b.body("b", "link-1", 0, 1.0, I, Vec3(0.2, 0, 0), Vec3(0.2, 0, 0), box_inertia(1.0, 0.1, 0.02, 0.02));
    b.body("c", "world", 0, 1.0, I, Vec3(0.3, 0, 0), Vec3(0.3, 0, 0), box_inertia(1.0, 0.1, 0.02, 0.02));
    b.body("d", "<&\"'>", 0, 1.0, I, Vec3(0.4, 0, 0), Vec3(0.4, 0, 0), box_inertia(1.0, 0.1, 0.02, 0.02));
    b.joint("j1", "ground", "a", Vec3(0.05, 0, 0), I, {revolute(Vec3::UnitY())}, kWorld, kWorld);
    b.joint("j2", "a", "b", Vec3(0.15, 0, 0), I, {revolute(Vec3::UnitY())}, kWorld, kWorld);
    b.joint("j3", "b", "c", Vec3(0.25, 0, 0), I, {revolute(Vec3::UnitY())}, kWorld, kWorld);
    b.joint("j4", "c", "d", Vec3(0.35, 0, 0), I, {revolute(Vec3::UnitY())}, kWorld, kWorld);
    a.constraints[0].name = "hinge 1";
    a.constraints[1].name = "hinge-1";
    a.constraints[2].name = "Hinge_1";
    a.constraints[3].name = "9 <lives>";
    for (size_t k = 0; k < a.bodies.size(); ++k)
        b.mesh(a.bodies[k].id.substr(4), box_mesh("m", Vec3(0.05, 0.02, 0.02), I, Vec3::Zero()));
    return a;
}

}  // namespace mjcf_assemblies
}  // namespace xtest
