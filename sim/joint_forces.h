// Joint dynamics as efforts on the joint coordinates: viscous damping and
// Coulomb friction (both direction-dependent if asked, Coulomb with a
// Stribeck peak), a constant effort offset, a spring about a rest position
// and position limits.
// New force elements are one more term here (or in the drives): each reads
// the state and adds to qfrc_passive.
#pragma once
#include <cmath>

#include "sim/data.h"

namespace mbx::sim {

// How the dry-friction term is evaluated.
enum class FrictionLaw {
    Regularised,  // smooth in qd (tanh), for fixed-step integration
    Slipping      // sign(qd): the accurate mode's slip phase (stick is a constraint there)
};

// The Stribeck part of the friction level, stribeck * exp(-(qd/vs)^2): the
// static friction above the Coulomb level, gone after a few vs.
template <class S> S stribeck_level(const JointDynamicsT<S>& jd, const S& qd) {
    using std::exp;
    if (jd.stribeck == S(0) || !(jd.stribeck_velocity > S(0))) return S(0);
    const S x = qd / jd.stribeck_velocity;
    return jd.stribeck * exp(-x * x);
}

// Sliding friction effort while slipping along `direction` (+1, -1) at speed
// qd: -direction * (coulomb_along(direction) + stribeck_level(qd)).
template <class S> S slip_friction(const JointDynamicsT<S>& jd, const S& qd, int direction) {
    return -S(direction) * (jd.coulomb_along(direction) + stribeck_level(jd, qd));
}

// The largest effort friction holds a joint against when the load pushes it
// along `direction`: that direction's Coulomb level plus the Stribeck peak.
template <class S> S static_friction(const JointDynamicsT<S>& jd, int direction) {
    return jd.coulomb_along(direction) + jd.stribeck;
}

// Dry friction effort of one joint under `law` (Coulomb, asymmetric, Stribeck).
// Slipping: slip_friction along sign(qd), 0 at qd = 0. Regularised, with
// t = tanh(qd / v_c):
//     -( c+ (1 + t)/2 + c- (1 - t)/2 + stribeck exp(-(qd/vs)^2) ) t
// which is c+ and c- beyond a few v_c, passes through 0 with a continuous
// slope, and is the old -coulomb tanh(qd/v_c) when c+ = c- and stribeck = 0.
// The law's slope at rest is never made stiffer than a step of `step`
// seconds can follow on the joint's own inertia (v_c >= (max(c+, c-) +
// stribeck) * step / inertia): a light joint with the default v_c would
// otherwise make RK4 at 1 ms unstable. step 0 leaves v_c as given.
template <class S>
S coulomb_effort(const ModelT<S>& m, const JointT<S>& j, const S& qd, FrictionLaw law, double step = 0) {
    using std::tanh;
    const JointDynamicsT<S>& jd = j.dynamics;
    if (!jd.dry_friction()) return S(0);
    if (law == FrictionLaw::Slipping)
        return qd > S(0) ? slip_friction(jd, qd, 1) : qd < S(0) ? slip_friction(jd, qd, -1) : S(0);
    const S& cp = jd.coulomb_along(1);
    const S& cn = jd.coulomb_along(-1);
    S vc = jd.coulomb_velocity > S(0) ? jd.coulomb_velocity : m.coulomb_velocity;
    if (step > 0 && j.reference_inertia > S(0)) {
        const S peak = (cp > cn ? cp : cn) + jd.stribeck;
        const S followable = peak * S(step) / j.reference_inertia;
        if (followable > vc) vc = followable;
    }
    const S t = tanh(qd / vc);
    return -(cp * (S(1) + t) / S(2) + cn * (S(1) - t) / S(2) + stribeck_level(jd, qd)) * t;
}

// Viscous effort: -damping * qd, with damping_negative for qd < 0 when
// asymmetric (continuous at rest, so no regularisation is needed).
template <class S> S damping_effort(const JointDynamicsT<S>& jd, const S& qd) {
    return -(qd < S(0) ? jd.damping_along(-1) : jd.damping_along(1)) * qd;
}

// Position limit: a spring-damper beyond the limit that pushes back and never pulls.
template <class S> S limit_effort(const JointDynamicsT<S>& jd, const S& q, const S& qd) {
    if (!jd.limited) return S(0);
    if (q > jd.upper) {
        const S f = -jd.limit_stiffness * (q - jd.upper) - jd.limit_damping * qd;
        return f < S(0) ? f : S(0);
    }
    if (q < jd.lower) {
        const S f = -jd.limit_stiffness * (q - jd.lower) - jd.limit_damping * qd;
        return f > S(0) ? f : S(0);
    }
    return S(0);
}

// data.qfrc_passive at (data.q, data.v). `skip_coulomb[dof]` leaves out the
// dry-friction term of joints the accurate mode holds stuck (null: none); `step`
// is the fixed step the regularised law must stay stable at (0: none).
template <class S>
void passive_forces(const ModelT<S>& m, DataT<S>& d, FrictionLaw law, const std::vector<char>* skip_coulomb = nullptr,
                    double step = 0) {
    d.qfrc_passive.setZero(m.nv);
    for (const JointT<S>& j : m.joints) {
        if (j.nv() != 1) continue;
        const JointDynamicsT<S>& jd = j.dynamics;
        const S q = d.q[j.q_index], qd = d.v[j.v_index];
        S f = damping_effort(jd, qd) - jd.offset - jd.stiffness * (q - jd.rest) + limit_effort(jd, q, qd);
        if (!(skip_coulomb && (*skip_coulomb)[size_t(j.v_index)])) f += coulomb_effort(m, j, qd, law, step);
        d.qfrc_passive[j.v_index] = f;
    }
}

}  // namespace mbx::sim
