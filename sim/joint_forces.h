// Joint dynamics as efforts on the joint coordinates: viscous damping,
// Coulomb friction, a spring about a rest position and position limits.
// New force elements are one more term here (or in the drives): each reads
// the state and adds to qfrc_passive.
#pragma once
#include <cmath>

#include "sim/data.h"

namespace mbx::sim {

// How the Coulomb term is evaluated.
enum class FrictionLaw {
    Regularised,  // -coulomb * tanh(qd / v_c): smooth, for fixed-step integration
    Slipping      // -coulomb * sign(qd): the accurate mode's slip phase (stick is a constraint there)
};

// Coulomb friction effort of one joint under `law`. The regularised law's
// slope coulomb / v_c is never made stiffer than a step of `step` seconds
// can follow on the joint's own inertia (v_c >= coulomb * step / inertia):
// a light joint with the default v_c would otherwise make RK4 at 1 ms
// unstable. step 0 leaves v_c as given.
template <class S>
S coulomb_effort(const ModelT<S>& m, const JointT<S>& j, const S& qd, FrictionLaw law, double step = 0) {
    using std::tanh;
    const JointDynamicsT<S>& jd = j.dynamics;
    if (jd.coulomb == S(0)) return S(0);
    if (law == FrictionLaw::Slipping) return qd > S(0) ? -jd.coulomb : qd < S(0) ? jd.coulomb : S(0);
    S vc = jd.coulomb_velocity > S(0) ? jd.coulomb_velocity : m.coulomb_velocity;
    if (step > 0 && j.reference_inertia > S(0)) {
        const S followable = jd.coulomb * S(step) / j.reference_inertia;
        if (followable > vc) vc = followable;
    }
    return -jd.coulomb * tanh(qd / vc);
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
// Coulomb term of joints the accurate mode holds stuck (null: none); `step`
// is the fixed step the regularised law must stay stable at (0: none).
template <class S>
void passive_forces(const ModelT<S>& m, DataT<S>& d, FrictionLaw law, const std::vector<char>* skip_coulomb = nullptr,
                    double step = 0) {
    d.qfrc_passive.setZero(m.nv);
    for (const JointT<S>& j : m.joints) {
        if (j.nv() != 1) continue;
        const JointDynamicsT<S>& jd = j.dynamics;
        const S q = d.q[j.q_index], qd = d.v[j.v_index];
        S f = -jd.damping * qd - jd.stiffness * (q - jd.rest) + limit_effort(jd, q, qd);
        if (!(skip_coulomb && (*skip_coulomb)[size_t(j.v_index)])) f += coulomb_effort(m, j, qd, law, step);
        d.qfrc_passive[j.v_index] = f;
    }
}

}  // namespace mbx::sim
