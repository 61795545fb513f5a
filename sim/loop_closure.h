// Loop closure: each cut joint keeps its frame A (on the tree-parent side)
// and frame B (on the tree-child side) together up to the joint's own
// motion. Residual, Jacobian and the velocity-product term at the current
// state, and the minimum-norm corrections that put a state back on the
// constraint manifold. Rows are scaled so that angular and linear rows
// weigh alike (linear rows divided by the model's size): rank decisions
// then do not depend on the unit of length.
#pragma once
#include <string>
#include <vector>

#include "sim/dynamics.h"

namespace mbx::sim {

template <class S> S closure_row_scale(const ModelT<S>& m, const LoopClosureT<S>& c, int r) {
    return c.row[size_t(r)].template tail<3>().squaredNorm() > S(0) ? S(1) / m.length_scale : S(1);
}

// data.residual (scaled rows). Needs update_positions.
template <class S> void update_closure_residual(const ModelT<S>& m, DataT<S>& d);

// data.J (scaled rows): rates of the residual rows. Needs update_positions.
template <class S> void update_closure_jacobian(const ModelT<S>& m, DataT<S>& d);

// data.gamma = -Jdot v (scaled rows): what J qacc must equal. Needs
// inverse_dynamics at zero qacc (data.acc: the bodies' velocity-product
// accelerations plus gravity's uniform field, which adds the same linear
// acceleration at both ends of a closure and so drops out of the rows).
template <class S> void update_closure_bias(const ModelT<S>& m, DataT<S>& d);

// The loop whose rows in `v` (a residual or J v) are the largest, for errors.
template <class S> int worst_closure(const ModelT<S>& m, const VecXT<S>& v);

// Moves the free coordinates (fixed[dof] == 0, or all when `fixed` is null)
// by Gauss-Newton minimum-norm steps (chord steps while they converge
// fast) until every closure holds within
// `tolerance` (scaled residual, i.e. metres / model size and radians).
// Returns false, leaving data.q at the last iterate, if it does not converge.
// `moved`, when given, gets the sum of the steps taken (added to it).
// `warm`: f already holds a factor of the closure rows at nearby positions
// (the step's last dynamics evaluation), good for the first chord steps.
template <class S>
bool project_positions(const ModelT<S>& m, DataT<S>& d, ClosureFactor<S>& f, double tolerance, int max_iterations = 50,
                       const std::vector<char>* fixed = nullptr, bool warm = false, VecXT<S>* moved = nullptr);

// Removes from data.v its component that violates the closures (minimum
// norm change of the free coordinates). Needs update_positions; returns the
// largest scaled J v left (nonzero when the fixed velocities admit none;
// not computed, 0, when `check` is false and nothing is fixed: then only
// round-off is left).
template <class S>
S project_velocities(const ModelT<S>& m, DataT<S>& d, ClosureFactor<S>& f, const std::vector<char>* fixed = nullptr,
                     bool check = true);

// Instances per scalar, as MBX_SIM_DYNAMICS_INSTANCES (sim/dynamics.h).
#define MBX_SIM_LOOP_CLOSURE_INSTANCES(EXTERN, S)                                                               \
    EXTERN template void update_closure_residual<S>(const ModelT<S>&, DataT<S>&);                               \
    EXTERN template void update_closure_jacobian<S>(const ModelT<S>&, DataT<S>&);                               \
    EXTERN template void update_closure_bias<S>(const ModelT<S>&, DataT<S>&);                                   \
    EXTERN template int worst_closure<S>(const ModelT<S>&, const VecXT<S>&);                                    \
    EXTERN template bool project_positions<S>(const ModelT<S>&, DataT<S>&, ClosureFactor<S>&, double, int,      \
                                              const std::vector<char>*, bool, VecXT<S>*);                       \
    EXTERN template S project_velocities<S>(const ModelT<S>&, DataT<S>&, ClosureFactor<S>&,                     \
                                            const std::vector<char>*, bool);
MBX_SIM_LOOP_CLOSURE_INSTANCES(extern, double)

}  // namespace mbx::sim
