// Elastic transmissions (sim/model.h TransmissionT): the motor side of a
// joint as one more inertia, joined to the link by a spring and damper,
// through a dead band when the transmission has backlash. Written on the
// scalar, like the rest of the dynamics, so Jets pass through.
#pragma once
#include <cmath>

#include "sim/data.h"
#include "sim/dynamics.h"
#include "sim/joint_forces.h"

namespace mbx::sim {

// The effort a transmission passes to the link at deflection dq = motor -
// link and its rate: k dq + c dqd, or through a dead band of width b nothing
// while |dq| <= b/2 and against a stop a stiff spring-damper that pushes and
// never pulls (the stop law of the simulation fit, calibration/nonlinear_fit).
template <class S> S transmitted_effort(const TransmissionT<S>& t, const S& dq, const S& dqd) {
    if (!(t.backlash > S(0))) return t.stiffness * dq + t.damping * dqd;
    const S half = t.backlash / S(2);
    if (dq > half) {
        const S f = t.stop_stiffness * (dq - half) + t.stop_damping * dqd;
        return f > S(0) ? f : S(0);
    }
    if (dq < -half) {
        const S f = t.stop_stiffness * (dq + half) + t.stop_damping * dqd;
        return f < S(0) ? f : S(0);
    }
    return S(0);
}

// Moves the efforts that act on the motor side (data.effort and the
// drives' data.qfrc_drive) off the joints with a transmission in
// data.qfrc_total, puts the transmitted effort there instead, and sets each
// motor's acceleration. Called once qfrc_total holds effort + passive + drive.
template <class S> void apply_transmissions(const ModelT<S>& m, DataT<S>& d) {
    for (size_t i = 0; i < m.transmissions.size(); ++i) {
        const TransmissionT<S>& t = m.transmissions[i];
        const JointT<S>& j = m.joints[size_t(t.joint)];
        const Eigen::Index e = Eigen::Index(i);
        const S motor_side = d.effort[t.dof] + d.qfrc_drive[t.dof];
        const S link = transmitted_effort(t, d.motor_q[e] - d.q[j.q_index], d.motor_v[e] - d.v[t.dof]);
        d.qfrc_total[t.dof] += link - motor_side;
        d.motor_acc[e] = (motor_side - link) / t.motor_inertia;
    }
}

// What the encoder of coordinate `dof` reads: the motor's position where a
// transmission is (the drive and the sensor are on the motor side), else
// the joint's. Likewise the rate.
template <class S> S sensed_position(const ModelT<S>& m, const DataT<S>& d, int dof) {
    const int t = m.transmission_of_dof.empty() ? -1 : m.transmission_of_dof[size_t(dof)];
    return t >= 0 ? d.motor_q[t] : d.q[m.joints[size_t(m.dof_joint[size_t(dof)])].q_index];
}
template <class S> S sensed_rate(const ModelT<S>& m, const DataT<S>& d, int dof) {
    const int t = m.transmission_of_dof.empty() ? -1 : m.transmission_of_dof[size_t(dof)];
    return t >= 0 ? d.motor_v[t] : d.v[dof];
}

// The deflection at which transmission t carries its link's load at rest
// (gravity and the velocity products at data's state, less the joint's
// passive efforts), so that a run started there does not ring. Updates
// data's kinematics.
inline VecXT<double> static_deflections(const ModelT<double>& m, DataT<double>& d) {
    VecXT<double> out = VecXT<double>::Zero(Eigen::Index(m.transmissions.size()));
    if (m.transmissions.empty()) return out;
    update_kinematics(m, d);
    VecXT<double> zero = VecXT<double>::Zero(m.nv), tau(m.nv);
    inverse_dynamics(m, d, zero, tau);
    for (size_t i = 0; i < m.transmissions.size(); ++i) {
        const TransmissionT<double>& t = m.transmissions[i];
        const JointT<double>& j = m.joints[size_t(t.joint)];
        const JointDynamicsT<double>& jd = j.dynamics;
        const double q = d.q[j.q_index], qd = d.v[t.dof];
        // The link's passive efforts at rest on the load (friction left out:
        // at rest it takes whatever share it can, which is not determined).
        const double passive = -jd.offset - jd.stiffness * (q - jd.rest) + damping_effort(jd, qd);
        const double load = tau[t.dof] - passive;
        double dq = 0;
        if (t.backlash > 0)
            dq = load > 0 ? t.backlash / 2 + load / t.stop_stiffness : load < 0 ? -t.backlash / 2 + load / t.stop_stiffness : 0;
        else if (t.stiffness > 0)
            dq = load / t.stiffness;
        out[Eigen::Index(i)] = dq;
    }
    return out;
}

// Places every motor from its link's state (data.q, data.v): deflected by
// the static load, turning with the link.
inline void settle_transmissions(const ModelT<double>& m, DataT<double>& d) {
    const VecXT<double> dq = static_deflections(m, d);
    for (size_t i = 0; i < m.transmissions.size(); ++i) {
        const TransmissionT<double>& t = m.transmissions[i];
        d.motor_q[Eigen::Index(i)] = d.q[m.joints[size_t(t.joint)].q_index] + dq[Eigen::Index(i)];
        d.motor_v[Eigen::Index(i)] = d.v[t.dof];
    }
}

// The other way round, for a start from measured states: data.q and data.v
// hold on each transmission's joint what its encoder read (the motor);
// the motor is put there and the link behind it by the static deflection
// (on a tree; in a closed loop the link stays, which the loop fixed, and
// the motor is placed from it).
inline void start_from_motor_side(const ModelT<double>& m, DataT<double>& d) {
    if (m.transmissions.empty()) return;
    if (!m.closures.empty()) return settle_transmissions(m, d);
    const VecXT<double> dq = static_deflections(m, d);
    for (size_t i = 0; i < m.transmissions.size(); ++i) {
        const TransmissionT<double>& t = m.transmissions[i];
        const int qi = m.joints[size_t(t.joint)].q_index;
        d.motor_q[Eigen::Index(i)] = d.q[qi];
        d.motor_v[Eigen::Index(i)] = d.v[t.dof];
        d.q[qi] -= dq[Eigen::Index(i)];
    }
}

// The transmissions' energy: the motors' kinetic energy and the springs'
// (a dead band's stops counted as springs).
template <class S> S transmission_energy(const ModelT<S>& m, const DataT<S>& d) {
    S e = S(0);
    for (size_t i = 0; i < m.transmissions.size(); ++i) {
        const TransmissionT<S>& t = m.transmissions[i];
        const Eigen::Index k = Eigen::Index(i);
        const S dq = d.motor_q[k] - d.q[m.joints[size_t(t.joint)].q_index];
        e += S(0.5) * t.motor_inertia * d.motor_v[k] * d.motor_v[k];
        if (!(t.backlash > S(0))) {
            e += S(0.5) * t.stiffness * dq * dq;
        } else {
            const S half = t.backlash / S(2);
            const S over = dq > half ? dq - half : dq < -half ? dq + half : S(0);
            e += S(0.5) * t.stop_stiffness * over * over;
        }
    }
    return e;
}

}  // namespace mbx::sim
