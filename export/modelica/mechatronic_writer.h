// The drives as a Modelica model (Mechatronic.mo), separate from the
// mechanical one it instantiates: `<package>.Mechanics mechanics`, and for
// each drive (ExportSettings::drives) a DC motor circuit, its gears and a
// controller built from MSL 4.0 components, on the driven joint's axis
// flange (Mechanics.mo's axis_<joint>).
//
// Per drive, components are named <drive>_<role>, <drive> being the drive's
// name as an identifier (unique ignoring case, a numeric suffix otherwise),
// and each description starts with "drive '<name>'":
//   target                motion: CombiTimeTable (linear: LinearSegments, step:
//                         ConstantSegments, HoldLastPoint outside), SmoothTarget
//                         (<package>.SmoothTarget, quintic) or Constant(k = 0)
//   position, speed       Rotational.Sensors.AngleSensor/SpeedSensor or
//                         Translational.Sensors.PositionSensor/SpeedSensor on the
//                         axis flange (speed only where the law uses a velocity)
//   continuous controller error (Feedback: target - q), error_integral
//                         (Integrator, ki > 0), position_law (Gain/Add/Add3:
//                         kp e + ki int(e) - kd qdot), velocity_error (Feedback:
//                         up - qdot) and velocity_law (kv, kvi) when kv > 0,
//                         limiter (Limiter +-output_limit), delay (FixedDelay,
//                         delay > 0)
//   discrete controller   controller (<package>.DiscreteDriveController: the whole
//                         sampled law, saturation and delay included)
//   amplifier             amplifier (Gain = amplifier gain, current mode only),
//                         source (SignalVoltage or SignalCurrent)
//   armature circuit      resistor (Ra), inductor (La; voltage mode with La > 0),
//                         emf (RotationalEMF, k = torque constant), ground
//   drive train           rotor (Inertia, J_rotor), motor_gear (IdealGear, the
//                         motor's built-in ratio), then for a gearbox
//                         transmission_inertia (its J, at its input) and
//                         transmission (LossyGear, ratio, efficiency); for a ball
//                         screw transmission_inertia (screw J), transmission
//                         (LossyGear, ratio 1, efficiency) and screw
//                         (IdealGearR2T, ratio 2 pi / lead) onto the prismatic
//                         joint's translational flange. An Inertia whose J is 0
//                         is left out.
//
// Efficiency: the LossyGear carries all of the transmission's loss
// (lossTable = [0, eta, eta, 0, 0]: the same efficiency driving and back-
// driven, no bearing friction) at the transmission's output side, after the
// rotor, the built-in gear and the transmission's own inertia. So the
// steady-state joint effort at the largest armature current is
// eta * ratio * k * I_max, exactly Drive::effort_limit, and the reflected
// inertia at zero loss is Drive::armature (J_rotor N^2 + J_transmission
// N_t^2); while accelerating, the lossy gear also scales the reflected
// inertia torque by eta (1/eta when back-driven), as a real gear does.
//
// Joint dynamics (ExportSettings::joint_dynamics), per joint on the same axis
// flange, components named <joint>_<role>, each description starting with
// "joint dynamics of '<joint>'":
//   spring_damper, spring, damper  Rotational (Translational) SpringDamper,
//                         Spring or Damper with c, d and the rest position
//                         (phi_rel0 or s_rel0) between support_<joint> and
//                         axis_<joint>: its relative coordinate is the joint's
//                         (damping: the mean of both directions)
//   friction              Rotational.Components.BearingFriction (tau_pos =
//                         [0, mean coulomb], or sampled Stribeck rows) or
//                         Translational.Components.SupportFriction (f_pos),
//                         peak 1, on the axis: MSL's stick/slip friction, no
//                         regularisation speed
//   offset                Rotational.Sources.ConstantTorque (tau_constant)
//                         or Translational.Sources.ConstantForce
//                         (f_constant), useSupport, between support and axis:
//                         -offset - (coulomb - coulomb_negative)/2
//   armature              Rotational Inertia (J) or Translational Mass (m) on
//                         the axis
// Limits have no MSL counterpart on a MultiBody joint: they become a note.
//
// The drive's housing is MSL's implicit fixed support (useSupport = false),
// which is where MSL's Revolute and Prismatic put their support flange too
// (fixed in the world), so support_<joint> is left free.
#pragma once
#include <string>
#include <vector>

#include "export/common/export_model.h"
#include "export/modelica/mechanics_writer.h"

namespace mbx {

// One drive's components in Mechatronic.mo.
struct ModelicaDriveComponents {
    int drive = -1;      // ExportSettings::drives index
    std::string prefix;  // <drive>
    std::vector<std::pair<std::string, std::string>> roles;  // role -> component name, in model order
    std::string component(const std::string& role) const;   // "" when the drive has no such part
};

struct MechatronicModel {
    std::string text;  // Mechatronic.mo; "" when no drive could be connected
    std::vector<ModelicaDriveComponents> drives;
    // Per joint with joint dynamics MSL can hold; `drive` is then the
    // ExportSettings::joint_dynamics index.
    std::vector<ModelicaDriveComponents> joint_dynamics;
    bool uses_discrete_controller = false;
    bool uses_smooth_target = false;
    double stop_time = 0;  // the experiment's StopTime
};

// Mechatronic.mo for model.settings().drives and joint_dynamics, given
// Mechanics.mo's flange names ("" text when neither has anything to write). A drive whose joint has no axis flange in Mechanics (a revolute
// that carries a planar-loop constraint) is left out with a note.
MechatronicModel write_mechatronic(ExportModel& model, const std::string& package,
                                   const std::vector<JointFlanges>& flanges);

}  // namespace mbx
