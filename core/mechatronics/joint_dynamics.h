// Joint dynamics: what acts on a joint besides the bodies and its drive --
// viscous damping, Coulomb friction (direction-dependent if wanted, with a
// Stribeck peak), a constant effort offset, a spring about a rest position,
// position limits and armature (rotor or gear inertia not modelled as a body). Like
// drives they are user data keyed by CAD ids (JointRef), kept apart from the
// CAD model and resolved against a translated mechanism when a consumer (the
// simulator, an exporter) needs them. Format: docs/mechatronics.md.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "core/mechatronics/joint_dynamics_fields.h"
#include "core/mechatronics/joint_ref.h"
#include "core/mechatronics/object_library.h"

namespace mbx {

// An elastic transmission between the joint's motor side (where the drive
// acts and the encoder reads) and its link: a motor-side inertia, a spring
// and damper, and a dead band of `backlash` (0: none). Coefficients per rad
// or m; backlash in SI after the joint's unit.
struct TransmissionSpec {
    double stiffness = 0;      // N m/rad or N/m
    double damping = 0;        // N m s/rad or N s/m
    double motor_inertia = 0;  // kg m^2 or kg, the motor side as the joint sees it
    double backlash = 0;       // rad or m, the dead band's whole width
    int line = 0;
};

// As the user wrote it, in SI: efforts in N m (revolute) or N (prismatic),
// positions in rad or m. `unit` is the position unit the file used
// ("rad", "deg", "m", "mm"; "" = SI, no check), kept so that resolution can
// refuse an angle on a prismatic joint and a length on a revolute one.
struct JointDynamicsSpec {
    JointRef joint;
    double damping = 0;           // N m s/rad or N s/m
    double coulomb = 0;           // N m or N, friction effort while sliding
    double coulomb_velocity = 0;  // rad/s or m/s: regularisation speed of the fixed-step law; 0: the simulator's default
    // Given, they hold for qd < 0 and damping/coulomb for qd > 0 (calibrated
    // friction is often direction-dependent); absent, the law is symmetric.
    std::optional<double> coulomb_negative, damping_negative;
    double stribeck = 0;           // N m or N: static friction above the Coulomb level, decaying with speed
    double stribeck_velocity = 0;  // rad/s or m/s: its decay speed, exp(-(qd/stribeck_velocity)^2); > 0 with stribeck
    double offset = 0;             // N m or N, any sign: constant effort the actuator supplies besides the rest; acts as -offset
    double stiffness = 0;         // N m/rad or N/m
    double rest = 0;              // spring rest position, rad or m
    double armature = 0;          // kg m^2 or kg, added to the joint's inertia
    bool limited = false;         // lower/upper given (they replace the CAD joint's limits)
    double lower = 0, upper = 0;  // rad or m
    std::optional<TransmissionSpec> transmission;  // a <transmission> child
    std::string unit;
    std::string file;  // where it was declared, "" when set through the C API
    int line = 0;
};

// The numbers of a spec that must be finite and not negative, by the names
// the description file uses (offset and rest may be negative: they are only
// checked finite).
std::vector<std::pair<const char*, double>> joint_dynamics_coefficients(const JointDynamicsSpec& s);

// What is wrong with a spec beyond single coefficients (a Stribeck peak
// without a decay speed, a non-finite offset), one message each; empty when
// it is sound. Every entry point checks it: the file reader, resolution and
// the C API.
std::vector<std::string> joint_dynamics_problems(const JointDynamicsSpec& s);

// Joint dynamics resolved against a mechanism: the joint they act on and the
// same SI values, for the simulator (sim/resolved_dynamics.h) and every
// exporter alike.
struct ResolvedJointDynamics {
    JointDynamicsSpec spec;
    int joint = -1;       // Mechanism::joints index (a revolute or prismatic tree joint)
    int source = -1;      // MechatronicSpec::joint_dynamics index it was resolved from
    std::string name;     // the joint's name
    bool linear = false;  // prismatic joint
    double damping = 0, coulomb = 0, coulomb_velocity = 0, stiffness = 0, rest = 0, armature = 0;
    // Resolved: equal to damping and coulomb when the spec gave none.
    double damping_negative = 0, coulomb_negative = 0;
    double stribeck = 0, stribeck_velocity = 0, offset = 0;
    bool limited = false;
    double lower = 0, upper = 0;
    std::optional<TransmissionSpec> transmission;

    bool asymmetric() const { return damping_negative != damping || coulomb_negative != coulomb; }
    // The symmetric part of the law, what a format with one friction level
    // and one damping per joint (MJCF, URDF) is given: the mean of the two
    // directions. An asymmetric Coulomb law is exactly this mean plus a
    // constant effort (coulomb - coulomb_negative) / 2 against positive motion.
    double symmetric_coulomb() const { return (coulomb + coulomb_negative) / 2; }
    double symmetric_damping() const { return (damping + damping_negative) / 2; }
    // Any dry friction at all (either direction, or a Stribeck peak).
    bool dry_friction() const { return coulomb > 0 || coulomb_negative > 0 || stribeck > 0; }
};

// What a format with only symmetric damping and friction cannot hold, in
// words for its export note: the effort offset, the direction-dependent
// parts, the Stribeck peak; "" when there is none of them.
std::string joint_dynamics_beyond_symmetric(const ResolvedJointDynamics& r);

}  // namespace mbx
