// Forward dynamics of the whole model: the tree by the articulated body
// algorithm when there are no loops, otherwise the mass matrix and the loop
// closures in a null-space solve that tolerates redundant closure rows and
// joints without inertia of their own (massless CAD joint nodes) as long as
// the closures determine their motion.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/finding.h"
#include "sim/loop_closure.h"

namespace mbx::sim {

// A joint whose acceleration nothing determines. Unless the state itself is
// no longer finite: an overflowed position, speed or effort leaves a mass
// matrix of NaN that no factorisation accepts, and blaming a joint's inertia
// would point the user the wrong way.
template <class S> [[noreturn]] void throw_undetermined(const ModelT<S>& m, const DataT<S>& d, int joint) {
    for (const JointT<S>& j : m.joints)
        for (int i = 0; i < j.nv(); ++i) {
            const int v = j.v_index + i;
            const std::pair<const char*, double> state[] = {
                {"position", value_of(d.q[j.q_index + std::min(i, j.nq() - 1)])},
                {"speed", value_of(d.v[v])},
                {"applied effort", value_of(d.qfrc_total[v])}};
            for (const auto& [what, value] : state)
                if (!std::isfinite(value))
                    throw Error(MBX_ERROR_SIMULATION, j.subject(),
                                std::string("the simulated state is no longer finite: joint '") + j.name + "''s " + what +
                                    " is " + (std::isnan(value) ? "nan" : value > 0 ? "inf" : "-inf") +
                                    " (an effort, a parameter or a step beyond what the dynamics can carry)");
        }
    const JointT<S>& j = m.joints[size_t(joint)];
    throw Error(MBX_ERROR_INVALID_INPUT, j.subject(),
                std::string("joint '") + j.name + "' moves no inertia and no loop closure determines its motion");
}

// data.qacc under data.qfrc_total at (data.q, data.v). Updates kinematics.
// `extra_rows`/`extra_bias`, when given, are further constraint rows
// J_e qacc = b_e solved with the closures (the accurate mode's stuck joints).
// `positions_ready`: body poses, subspaces and data.J are already those of
// data.q (a fixed step starting where the last one closed its loops).
template <class S>
void forward_dynamics(const ModelT<S>& m, DataT<S>& d, const MatXT<S>* extra_rows = nullptr,
                      const VecXT<S>* extra_bias = nullptr, bool positions_ready = false);

// Instances per scalar, as MBX_SIM_DYNAMICS_INSTANCES (sim/dynamics.h).
#define MBX_SIM_FORWARD_DYNAMICS_INSTANCES(EXTERN, S)                                                       \
    EXTERN template void forward_dynamics<S>(const ModelT<S>&, DataT<S>&, const MatXT<S>*, const VecXT<S>*, \
                                             bool);
MBX_SIM_FORWARD_DYNAMICS_INSTANCES(extern, double)

}  // namespace mbx::sim
