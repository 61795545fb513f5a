// Converters between mbx's contact parameters and the ones users bring from
// other engines (docs/contact.md, "Parameters from other engines").
// Header-only closed forms, so the exporters can use them without linking
// the contact library.
//
// MuJoCo: a contact is a soft constraint. Along its normal, with impedance d
// (constant when solimp's dmin = dmax) and penetration dynamics written for
// the constraint's own (mass-normalised) coordinate,
//   r'' = (1 - d) a0 - d B r' - d^2 K r,
// where a0 is the unconstrained acceleration and, for solref = (timeconst,
// dampratio) > 0, B = 2 / (dmax timeconst), K = 1 / (dmax timeconst
// dampratio)^2; for solref = (-stiffness, -damping), B = damping / dmax,
// K = stiffness / dmax^2. So with d = dmax the penetration is a damped
// oscillator of angular frequency 1/(timeconst dampratio), damping ratio
// dampratio, which carries only (1 - d) of the load: a body of mass m resting
// on it sinks (1 - d) g (timeconst dampratio)^2.
// mbx's linear spring-damper (k, c) on mass m: m r'' + c r' + k r = m a0,
// rest depth m g / k, damping ratio c / (2 sqrt(k m)).
// mbx_to_mujoco keeps the rest depth and the damping ratio (so the rebound:
// both cut the force at zero); the oscillation is slower by sqrt(1 - d).
//
// Drake: compliant point contact f = k x (1 + d x') (Hunt-Crossley, linear
// in x) with point_contact_stiffness k and hunt_crossley_dissipation d; two
// materials combine as k = k1 k2 / (k1 + k2), d = (k2 d1 + k1 d2) / (k1 + k2).
// That is mbx's Hunt-Crossley law with exponent 1 and chi = d.
#pragma once
#include <algorithm>
#include <cmath>

namespace mbx::sim::contact {

struct MujocoSolref {
    double timeconst = 0.02, dampratio = 1;  // solref > 0: MuJoCo's standard form
};

struct LinearContact {
    double stiffness = 0;  // k, N/m
    double damping = 0;    // c, N s/m
};

// Damping ratio of a linear contact on mass m, and back.
inline double damping_ratio(const LinearContact& c, double mass) { return c.damping / (2 * std::sqrt(c.stiffness * mass)); }

// The restitution of a linear damped contact that cannot pull (the force is
// cut at zero while the bodies separate), for damping ratio zeta < 1:
// exp(-zeta pi / sqrt(1 - zeta^2)) to first order (the cut ends the contact
// a little before the spring's half period, so it is slightly larger; the
// same in mbx and MuJoCo). And its inverse.
inline double restitution_of_damping_ratio(double zeta) {
    if (!(zeta < 1)) return 0;
    return std::exp(-zeta * M_PI / std::sqrt(1 - zeta * zeta));
}
inline double damping_ratio_of_restitution(double e) {
    if (!(e > 0)) return 1;
    if (e >= 1) return 0;
    const double l = std::log(e);
    return -l / std::sqrt(M_PI * M_PI + l * l);
}

// The same, exactly: the linear contact lets go where its force k x + c x'
// reaches zero (before x does), and leaves at the speed it has there.
inline double restitution_with_cut(double zeta) {
    if (!(zeta > 0)) return 1;
    if (!(zeta < 1)) return 0;
    const double wd = std::sqrt(1 - zeta * zeta);  // time in units of 1/omega
    auto x = [&](double t) { return std::exp(-zeta * t) * std::sin(wd * t) / wd; };
    auto v = [&](double t) { return std::exp(-zeta * t) * (std::cos(wd * t) - zeta * std::sin(wd * t) / wd); };
    // The force is positive from touch-down until the root, which lies in (0, pi/wd].
    double lo = 0, hi = M_PI / wd;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (mid > 0 && x(mid) + 2 * zeta * v(mid) > 0 ? lo : hi) = mid;
    }
    return std::max(0.0, -v(lo));
}
// Its inverse (the restitution falls monotonically with zeta) over the
// underdamped range: below restitution_with_cut(1) ~ 0.135 (a critically
// damped contact that cannot pull still throws the body back at 13.5 % of
// its speed) it gives zeta -> 1.
inline double damping_ratio_for_restitution_with_cut(double e) {
    if (!(e > 0)) return 1;
    if (e >= 1) return 0;
    double lo = 0, hi = 1;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (restitution_with_cut(mid) > e ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// mbx linear contact on mass `mass` -> MuJoCo solref with constant impedance
// d (solimp = d d width): the same rest depth and damping ratio.
inline MujocoSolref mbx_to_mujoco(const LinearContact& c, double mass, double impedance) {
    const double zeta = damping_ratio(c, mass);
    const double period = std::sqrt(mass / ((1 - impedance) * c.stiffness));  // timeconst * dampratio
    return {period / zeta, zeta};
}

// And back: the mbx linear contact on mass `mass` that MuJoCo's solref and
// impedance amount to (same rest depth and damping ratio).
inline LinearContact mujoco_to_mbx(const MujocoSolref& s, double mass, double impedance) {
    const double period = s.timeconst * s.dampratio;
    LinearContact c;
    c.stiffness = mass / ((1 - impedance) * period * period);
    c.damping = 2 * s.dampratio * std::sqrt(c.stiffness * mass);
    return c;
}

// MuJoCo's direct form solref = (-stiffness, -damping) -> its standard form,
// at impedance d = dmax (K d^2 = 1/(timeconst dampratio)^2, d B = 2/timeconst).
inline MujocoSolref mujoco_direct_to_standard(double stiffness, double damping) {
    const double timeconst = 2 / damping;
    return {timeconst, 1 / (timeconst * std::sqrt(stiffness))};
}

// MuJoCo's rest depth of mass on a contact at impedance d, gravity g.
inline double mujoco_rest_depth(const MujocoSolref& s, double impedance, double gravity) {
    const double period = s.timeconst * s.dampratio;
    return (1 - impedance) * gravity * period * period;
}

struct DrakeContact {
    double stiffness = 0;    // point_contact_stiffness, N/m
    double dissipation = 0;  // hunt_crossley_dissipation, s/m
};

// Drake's combination of two materials' parameters into the pair's.
inline DrakeContact drake_combine(const DrakeContact& a, const DrakeContact& b) {
    const double sum = a.stiffness + b.stiffness;
    return {a.stiffness * b.stiffness / sum, (b.stiffness * a.dissipation + a.stiffness * b.dissipation) / sum};
}

}  // namespace mbx::sim::contact
