// A drive on one joint (thesis section 2.8: actuators from the object library
// assigned to joints, plus motion targets). What the user specifies is kept
// apart from the CAD data and keyed by stable CAD ids (constraint id and
// primitive index), so it survives a re-export; it is resolved against a
// translated mechanism only when a consumer needs it.
#pragma once
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/mechatronics/mounting.h"
#include "core/mechatronics/body_mass.h"
#include "core/mechatronics/drive_quantities.h"
#include "core/mechatronics/contact_description.h"
#include "core/mechatronics/joint_dynamics.h"
#include "core/mechatronics/joint_ref.h"
#include "core/mechatronics/motion_profile.h"
#include "core/mechatronics/object_library.h"

namespace mbx {

// What the controller output u commands.
enum class AmplifierMode {
    Voltage,  // u is the armature voltage (V)
    Current   // an ideal current amplifier: armature current = gain * u
};

// How a discrete controller estimates the joint velocity from sampled
// positions (a continuous controller measures it).
enum class VelocityEstimate {
    Measured,           // the true joint velocity
    Difference,         // (q_k - q_{k-1}) / Ts
    FilteredDifference  // of qf_k = (q_k + q_{k-1}) / 2, i.e. (q_k - q_{k-2}) / (2 Ts): the EMPS rig
};

// Position loop on e = target - q, in joint units (rad or m):
//   u_p = kp e + ki integral(e) - kd qdot     (derivative on the measurement,
//                                              so a step target gives no kick)
// With a velocity loop (kv > 0), u_p is a velocity demand:
//   u = kv (u_p - qdot) + kvi integral(u_p - qdot)
// otherwise u = u_p. Then u is saturated to +-output_limit and reaches the
// amplifier after `delay` seconds. sample_period 0 means continuous time;
// otherwise u is computed at t = k Ts from the samples and held.
struct ControllerSpec {
    double kp = 0, ki = 0, kd = 0;
    double kv = 0, kvi = 0;
    double sample_period = 0;  // s; 0: continuous
    double delay = 0;          // s; a discrete controller's delay is a whole number of samples
    double output_limit = 0;   // |u| bound; 0: the amplifier's natural limit (VaNominal in voltage mode)
    VelocityEstimate velocity_estimate = VelocityEstimate::Measured;
};

// The controller's numbers by name, for the checks that treat them alike
// (finite, not negative) wherever a controller comes in.
std::array<std::pair<const char*, double>, 8> controller_values(const ControllerSpec& c);

// A discrete controller's delay is a whole number of samples (within 1e-9
// relative); always true for a continuous one.
bool delay_in_whole_samples(const ControllerSpec& c);

struct AmplifierSpec {
    AmplifierMode mode = AmplifierMode::Voltage;
    double gain = 1;  // Current mode: A per unit of u
};

struct DriveSpec {
    std::string name;  // display name; "" = the joint's name
    JointRef joint;
    std::string motor_id;         // ObjectLibrary ID of a dc_motor object
    std::string transmission_id;  // "" = none; else a gearbox or ball_screw object
    // Editable library parameters overridden for this drive, in the unit the
    // class declares ("Ratio" -> 100).
    std::map<std::string, double> overrides;
    AmplifierSpec amplifier;
    ControllerSpec controller;
    MotionProfile motion;  // SI (rad or m); default: hold 0
    // Unit the motion was written in ("rad", "deg", "m", "mm"; "" = SI, no
    // check): resolve_drives refuses an angle on a prismatic joint and a
    // length on a revolute one.
    std::string motion_unit;
    std::string file;      // where it was declared, "" when set through the C API
    int line = 0;
};

// What the user adds to a CAD model: the library the drives draw from, the
// drives and the joint dynamics. Independent of any mechanism.
struct MechatronicSpec {
    ObjectLibrary library;
    std::vector<DriveSpec> drives;
    std::vector<JointDynamicsSpec> joint_dynamics;
    std::vector<BodyMassSpec> body_masses;  // <body> corrections, e.g. written by mbx calibrate
    ContactSpec contact;                    // <collision> shapes and <contact> materials
    MountingSpec mounting;                  // <mounting>: gravity turned in the base frame
};

// The joint-level linear servo a drive amounts to, in continuous time and
// with the armature inductance neglected (La/Ra is microseconds for small DC
// motors): joint effort
//   tau = clamp(stiffness (target - q) - damping qdot, +-effort_limit) - emf_damping qdot
// emf_damping is the back-EMF's viscous braking of a voltage-driven motor;
// it acts outside the saturation. MJCF, and the tests' design predictions,
// use this form.
struct ServoEquivalent {
    double stiffness = 0;    // N m/rad or N/m
    double damping = 0;      // N m s/rad or N s/m, from kd and the velocity loop
    double emf_damping = 0;  // idem
    double effort_limit = 0; // N m or N, at the joint
    // What of the drive this servo leaves out ("" if nothing, La aside):
    // integral action, sampling, a transport delay.
    std::string approximation;
};

// A drive resolved against a mechanism: which joint it moves and every
// derived quantity at the joint, the same for every exporter.
struct Drive {
    DriveSpec spec;
    std::string name;   // spec.name, or the joint's name
    int joint = -1;     // Mechanism::joints index
    int source = -1;    // MechatronicSpec::drives index it was resolved from
    bool linear = false;  // prismatic joint (efforts in N, inertia in kg)
    std::string motor_name;
    std::string transmission_name, transmission_kind;  // "" when none
    DcMotorConstants motor;             // with the drive's overrides applied; motor.ratio is the built-in gear
    double armature_resistance = 0;     // Ra, Ohm
    double armature_inductance = 0;     // La, H
    double transmission_ratio = 1;      // gearbox ratio, or 2 pi / lead for a screw (rad/m)
    double transmission_inertia = 0;    // at the transmission input, kg m^2
    double efficiency = 1;              // transmission efficiency (1 without one)
    double ratio = 1;                   // motor shaft rad per joint unit: motor.ratio * transmission_ratio
    double armature = 0;                // rotor and transmission inertia at the joint, kg m^2 or kg
    double output_limit = 0;            // resolved controller output bound (V, or amplifier units)
    // efficiency * ratio * k * (largest armature current), N m or N at the joint
    double effort_limit = 0;
    // Joint speed at which the back-EMF alone takes the whole supply (output
    // limit in voltage mode, VaNominal in current mode), rad/s or m/s.
    double velocity_limit = 0;
    ServoEquivalent servo;
};

// One problem in a drive description (file, line, drive, message), the same
// shape as the library's errors.
using DriveError = LibraryError;

// Resolves every drive of `spec` against `m`. Problems (unknown constraint
// id, a weld or spherical joint, a joint driven twice, a missing or wrong
// kind of library object, an override of a parameter that is not editable or
// out of its bounds, a controller that cannot work) go to `errors`; a drive
// with a problem is left out.
struct Mechanism;
std::vector<Drive> resolve_drives(const MechatronicSpec& spec, const Mechanism& m, std::vector<DriveError>& errors);

// Resolves every joint dynamics entry of `spec` against `m`, in spec order.
// Problems (unknown constraint id, a weld, spherical or cut joint, a joint
// given twice, a unit of the wrong kind, values that are not finite or
// negative, lower > upper) go to `errors` with the entry's file and line;
// an entry with a problem is left out.
std::vector<ResolvedJointDynamics> resolve_joint_dynamics(const MechatronicSpec& spec, const Mechanism& m,
                                                          std::vector<DriveError>& errors);

// The servo equivalent of a resolved drive (used by resolve_drives).
ServoEquivalent servo_equivalent(const Drive& d);

}  // namespace mbx
