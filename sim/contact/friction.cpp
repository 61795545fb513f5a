#include "sim/contact/friction.h"

#include <algorithm>
#include <cmath>

namespace mbx::sim::contact {

Eigen::Vector3d regularised_friction(const FrictionLaw& law, double n, const Eigen::Vector3d& v_t, double vs) {
    const double speed = v_t.norm();
    if (!(n > 0) || speed == 0) return Eigen::Vector3d::Zero();
    // mu_k N tanh(|v| / v_s) against the motion: smooth through zero speed.
    return -law.mu_kinetic * n * std::tanh(speed / vs) * (v_t / speed);
}

Eigen::Vector3d spring_friction(const FrictionLaw& law, const FrictionState& state, const Eigen::Vector3d& point,
                                const Eigen::Vector3d& normal, const Eigen::Vector3d& v_t, double n,
                                FrictionState& next) {
    FrictionState s = state;
    if (!(n > 0)) {
        next = FrictionState{};
        return Eigen::Vector3d::Zero();
    }
    const double speed = v_t.norm();
    // A new contact sticks where it touched, unless it touches down sliding.
    if (!s.active) s = {speed < law.stick_speed, point, true};
    // The spring's stretch, in the tangent plane.
    Eigen::Vector3d stretch = point - s.anchor;
    stretch -= normal * normal.dot(stretch);
    // Re-sticking keeps the dragged anchor: the spring goes on carrying the
    // kinetic force it had, rather than dropping to zero and letting the
    // load creep the contact along one stretch at a time.
    if (!s.sticking && speed < law.stick_speed) s.sticking = true;
    // The spring carries the static friction; its damper only calms the
    // stick phase (counting it would break a contact loose on the damping
    // of a sudden, holdable load).
    Eigen::Vector3d f = -law.stiffness * stretch - law.damping * v_t;
    if (s.sticking && law.stiffness * stretch.norm() <= law.mu_static * n) {
        next = s;
        // Within the friction cone, damper included (a stick-phase damper
        // must not throw the contact with more than static friction).
        const double cap = law.mu_static * n, size = f.norm();
        return size > cap ? Eigen::Vector3d(f * (cap / size)) : f;
    }
    // Slipping: kinetic friction against the sliding velocity (or, at the
    // moment of breaking away, against the spring's pull); the anchor is
    // dragged to where the spring carries exactly the kinetic force.
    // Slower than the re-stick speed the velocity's direction is noise:
    // the contact breaks away the way the spring was stretched.
    const Eigen::Vector3d direction = speed >= law.stick_speed ? Eigen::Vector3d(v_t / speed)
                                      : stretch.norm() > 0     ? Eigen::Vector3d(stretch.normalized())
                                                               : Eigen::Vector3d::Zero();
    f = -law.mu_kinetic * n * direction;
    s.sticking = false;
    s.anchor = point - direction * (law.mu_kinetic * n / law.stiffness);
    next = s;
    return f;
}

}  // namespace mbx::sim::contact
