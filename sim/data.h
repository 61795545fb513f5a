// The mutable side of a simulation: state, inputs and every workspace buffer
// the algorithms need, sized once from a model so that stepping allocates
// nothing. One data object per rollout; any number may share a model.
#pragma once
#include <Eigen/Cholesky>
#include <memory>
#include <vector>

#include "sim/closure_factor.h"
#include "sim/drive_state.h"
#include "sim/model.h"

namespace mbx::sim {

// A factorisation kept in a data object for its allocations only. Copying a
// data object (a rollout forked from another, a trial state) gives the copy
// a fresh one: it holds no state the next solve does not recompute, and
// Eigen's decompositions copy members they leave uninitialised until used.
template <class T> struct Fresh : T {
    Fresh() = default;
    Fresh(const Fresh&) : T() {}
    Fresh& operator=(const Fresh&) { return *this; }
};

template <class S> struct DataT;

// Forces from outside the joint model (contact: sim/contact/contact_step.h).
// At every dynamics evaluation, with the kinematics at the evaluated state,
// apply() adds generalised efforts into data.qfrc_applied; step_taken()
// follows every step the integrator keeps (the fixed-step modes' every
// step, the accurate mode's accepted ones), for state that must change only
// then, such as friction-spring anchors. Not owned by the data object (a
// copy shares it).
struct AppliedForces {
    virtual ~AppliedForces() = default;
    virtual void apply(const ModelT<double>& m, DataT<double>& d) = 0;
    virtual void step_taken(const ModelT<double>& m, DataT<double>& d) { (void)m, (void)d; }
};

struct RunStats {
    long long steps = 0;
    long long evaluations = 0;     // forward dynamics calls
    long long mode_switches = 0;   // accurate mode: friction stick/slip switches
    double max_closure_residual = 0;  // m (or rad), after projection
};

template <class S> struct DataT {
    S time = S(0);
    VecXT<S> q, v;          // state
    VecXT<S> qacc;          // last computed acceleration
    VecXT<S> effort;        // external effort input per velocity coordinate (N m, N; free joints: world force, body moment)
    VecXT<S> qfrc_passive;  // joint dynamics (damping, friction, springs, limits) at the last evaluation
    VecXT<S> qfrc_drive;    // drives at the last evaluation
    VecXT<S> qfrc_total;    // everything applied: effort + passive + drive (+ applied)
    AppliedForces* applied_forces = nullptr;  // double only; see AppliedForces
    VecXT<S> qfrc_applied;  // from applied_forces at the last evaluation

    // Kinematics (per body; [0] is the world).
    std::vector<Transform<S>> x_parent;  // body in its parent
    std::vector<Transform<S>> x_world;   // body in world
    std::vector<SubspaceT<S>> subspace;  // joint motion subspace, body coordinates
    std::vector<Vec6T<S>> vel;           // spatial velocity, body coordinates
    std::vector<Vec6T<S>> acc;           // spatial acceleration, body coordinates
    std::vector<Vec6T<S>> bias_acc;      // velocity-product acceleration of each joint
    std::vector<Vec6T<S>> force;         // RNEA body forces

    // Articulated-body workspaces.
    std::vector<Mat6T<S>> articulated;
    std::vector<Vec6T<S>> bias_force;
    std::vector<SubspaceT<S>> U;
    std::vector<Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>> D_inv;
    std::vector<Eigen::Matrix<S, Eigen::Dynamic, 1, 0, 6, 1>> u;

    // Composite inertias and the joint-space matrices.
    std::vector<Inertia<S>> composite;
    MatXT<S> M;     // mass matrix (with armature)
    VecXT<S> bias;  // C(q, v) v + g(q): the effort that holds the state with zero acceleration

    // Loop closure rows at the current state.
    MatXT<S> J;         // closure_rows x nv
    VecXT<S> residual;  // closure_rows
    VecXT<S> gamma;     // -Jdot v
    std::vector<Vec6T<S>> world_motion;  // per velocity coordinate: its motion in world coordinates

    // Constrained solve workspaces.
    Fresh<ClosureFactor<S>> closure_factor;
    MatXT<S> reduced_mass;  // N^T M N
    MatXT<S> mass_null;     // M N
    VecXT<S> qacc_particular, reduced_rhs;
    VecXT<S> closure_step, closure_rhs;  // projections' workspaces
    Fresh<Eigen::LDLT<MatXT<S>>> reduced_ldlt;

    // The positions at which a fixed step left body poses, subspaces, J and
    // its factor after closing the loops (empty: none); the next step starts
    // from them when data.q is still exactly these.
    VecXT<S> q_closed;
    // Euler: the corrections that closing the loops needed on the last three
    // steps' predicted positions (velocity coordinates), how many of them
    // are known (steps that ended where the next began), and the current
    // step's. They change smoothly from step to step, so the next
    // prediction extrapolates them. closure_leftover: the minimum-norm
    // change that would remove the residual the last step left.
    VecXT<S> closure_carry, closure_carry_before, closure_carry_oldest, closure_moved, closure_leftover;
    int carry_count = 0;

    // Per-dof workspaces (integrators: start state, stage sums).
    VecXT<S> tmp_v, tmp_v2;
    VecXT<S> q_start, v_start, v_stage, v_sum, a_sum;

    // Elastic transmissions (model.transmissions): each motor's position and
    // rate (joint units), its acceleration at the last evaluation and the
    // integrators' copies, as for q and v above.
    VecXT<S> motor_q, motor_v, motor_acc;
    VecXT<S> motor_q_start, motor_v_start, motor_v_stage, motor_v_sum, motor_a_sum;

    // Drives in the loop (double models only) and run statistics.
    DriveLoop drives;
    RunStats stats;
    // The accurate mode's integrator session (sim/cvode_session.h: CVODE's
    // history, friction modes), opaque here so that only that file needs
    // SUNDIALS. It belongs to this object alone: a copied DataT starts a new one.
    std::shared_ptr<void> accurate_session;

    explicit DataT(const ModelT<S>& m) : drives(m.drives) {
        const size_t nb = m.bodies.size();
        q = m.q_reference;
        v = VecXT<S>::Zero(m.nv);
        qacc = effort = qfrc_passive = qfrc_drive = qfrc_total = qfrc_applied = tmp_v = tmp_v2 = VecXT<S>::Zero(m.nv);
        v_start = v_stage = v_sum = a_sum = VecXT<S>::Zero(m.nv);
        q_start = q;
        x_parent.resize(nb);
        x_world.resize(nb);
        subspace.resize(nb);
        vel.assign(nb, Vec6T<S>::Zero());
        acc.assign(nb, Vec6T<S>::Zero());
        bias_acc.assign(nb, Vec6T<S>::Zero());
        force.assign(nb, Vec6T<S>::Zero());
        articulated.assign(nb, Mat6T<S>::Zero());
        bias_force.assign(nb, Vec6T<S>::Zero());
        U.resize(nb);
        D_inv.resize(nb);
        u.resize(nb);
        for (size_t b = 1; b < nb; ++b) {
            subspace[b] = m.joints[b - 1].subspace;
            const int n = m.joints[b - 1].nv();
            U[b].setZero(6, n);
            D_inv[b].setZero(n, n);
            u[b].setZero(n);
        }
        composite.resize(nb);
        M = MatXT<S>::Zero(m.nv, m.nv);
        bias = VecXT<S>::Zero(m.nv);
        J = MatXT<S>::Zero(m.closure_rows, m.nv);
        residual = gamma = VecXT<S>::Zero(m.closure_rows);
        const Eigen::Index nt = Eigen::Index(m.transmissions.size());
        motor_q.resize(nt), motor_v.resize(nt);
        for (Eigen::Index i = 0; i < nt; ++i) {
            const JointT<S>& j = m.joints[size_t(m.transmissions[size_t(i)].joint)];
            motor_q[i] = q[j.q_index], motor_v[i] = S(0);
        }
        motor_acc = motor_v_stage = motor_v_sum = motor_a_sum = VecXT<S>::Zero(nt);
        motor_q_start = motor_q, motor_v_start = motor_v;
    }
};

using Data = DataT<double>;

}  // namespace mbx::sim
