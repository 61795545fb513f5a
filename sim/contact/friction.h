// Tangential contact force laws (thesis section 3.8). Regularised Coulomb:
// -mu N v_t / max(|v_t|, v_s) style smoothing lets a loaded body creep at a
// speed where the law's force balances the load, however small the load.
// The friction spring holds it: while sticking, the contact point is tied to
// an anchor by a tangential spring and damper; when the spring's force would
// exceed mu_s N the contact slips, with kinetic friction mu_k N against the sliding
// velocity, the anchor dragged along; at low sliding speed it sticks again.
// The anchor is state that persists between steps and must only be updated
// on accepted steps (the accurate integrator's rejected trials must not
// move it).
#pragma once
#include <Eigen/Dense>

namespace mbx::sim::contact {

struct FrictionLaw {
    double mu_static = 0.5, mu_kinetic = 0.4;
    double stiffness = 1e4;   // tangential spring while sticking, N/m
    double damping = 0;       // tangential damper while sticking, N s/m
    double stick_speed = 1e-3;  // sliding slower than this re-sticks, m/s
};

// Per-contact state of the friction spring.
struct FrictionState {
    bool sticking = false;
    // The point the contact is tied to: a world point for spring_friction;
    // ContactWorld keeps it in the frame of the body it rides on.
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
    bool active = false;                               // false: a new contact (anchor at its point)
};

// The regularised Coulomb force on a contact sliding at tangential velocity
// v_t (world, perpendicular to the normal) under normal force n >= 0.
Eigen::Vector3d regularised_friction(const FrictionLaw& law, double normal_force, const Eigen::Vector3d& v_t,
                                     double smoothing_speed);

// The friction-spring force for a contact at world point `point` with
// normal `normal`, tangential velocity v_t and normal force n, from `state`
// as it was at the last accepted step; `next` gets the state to keep if
// this step is accepted (it may alias `state` in fixed-step use).
Eigen::Vector3d spring_friction(const FrictionLaw& law, const FrictionState& state, const Eigen::Vector3d& point,
                                const Eigen::Vector3d& normal, const Eigen::Vector3d& v_t, double normal_force,
                                FrictionState& next);

}  // namespace mbx::sim::contact
