// Drives in the loop: each drive's controller (mechatronics/drive_controller)
// runs on the simulated joint, its output reaches the motor through the
// amplifier, and the motor's torque, through the transmission, is an effort
// on the joint. Back-EMF acts continuously (it depends on the joint speed
// within a step); the controller output is held between its evaluations,
// as a real drive's is between its samples.
#pragma once
#include <cmath>
#include <vector>

#include "sim/transmission.h"

namespace mbx::sim {

// Armature current and joint effort of a drive for controller output u at joint speed qd.
inline void drive_effort(const Drive& d, double u, double qd, DriveSignals& s) {
    const double k = d.motor.torque_constant;
    if (d.spec.amplifier.mode == AmplifierMode::Current) {
        s.current = d.spec.amplifier.gain * u;
    } else {
        // Voltage across the armature resistance once the back-EMF is taken
        // (the inductance's microsecond lag is left out, as everywhere at joint level).
        s.current = d.armature_resistance > 0 ? (u - k * d.ratio * qd) / d.armature_resistance : 0.0;
    }
    s.effort = d.efficiency * d.ratio * k * s.current;
    s.output = u;
}

// Samples every controller at time t on (data.q, data.v): new held outputs.
// A drive on a joint with an elastic transmission reads and turns the motor.
inline void update_controllers(const ModelT<double>& m, DataT<double>& d, double t) {
    DriveLoop& loop = d.drives;
    for (size_t k = 0; k < m.drives.size(); ++k) {
        const Drive& drive = m.drives[k];
        const int dof = m.drive_dof[k];
        const double target =
            std::isnan(loop.target_override[k]) ? drive.spec.motion.at(t).position : loop.target_override[k];
        const double u = loop.controllers[k].update(t, target, sensed_position(m, d, dof), sensed_rate(m, d, dof)) + loop.output_add[k];
        loop.signals[k].target = target;
        loop.signals[k].output = u;
    }
}

// data.qfrc_drive from the held outputs and the current joint speeds.
inline void drive_forces(const ModelT<double>& m, DataT<double>& d) {
    DriveLoop& loop = d.drives;
    d.qfrc_drive.setZero(m.nv);
    for (size_t k = 0; k < m.drives.size(); ++k) {
        const int dof = m.drive_dof[k];
        drive_effort(m.drives[k], loop.signals[k].output, sensed_rate(m, d, dof), loop.signals[k]);
        d.qfrc_drive[dof] += loop.signals[k].effort;
    }
}

}  // namespace mbx::sim
