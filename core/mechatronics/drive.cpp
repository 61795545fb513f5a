#include "core/mechatronics/drive.h"

#include <cmath>
#include <cstdio>
#include <functional>

#include "core/mechatronics/joint_lookup.h"
#include "core/translator/mechanism.h"

namespace mbx {

namespace {

std::string short_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

// The object with the drive's overrides applied, each checked against its
// declaration (editable, bounds); a refused one is reported and not applied.
LibraryObject apply_overrides(const ObjectLibrary::Found& f, const std::map<std::string, double>& overrides,
                              const std::function<void(std::string)>& error) {
    LibraryObject o = *f.object;
    for (const auto& [name, value] : overrides) {
        const ParameterDecl* d = f.cls->parameter(name);
        if (!d) continue;  // belongs to the other object of the drive (motor or transmission)
        if (!d->editable) {
            error("parameter '" + name + "' of '" + f.object->name + "' is not editable");
            continue;
        }
        if (!std::isfinite(value) || (d->lower && value < *d->lower) || (d->upper && value > *d->upper)) {
            error("override " + name + " = " + short_number(value) + " " + d->unit + " is outside the bounds of '" +
                  f.cls->name + "'");
            continue;
        }
        ParameterValue& v = o.values[name];
        v.number = value;
        v.text = std::to_string(value);
    }
    return o;
}

bool valid_controller(const ControllerSpec& c, std::string& why) {
    for (const auto& [name, v] : controller_values(c))
        if (!std::isfinite(v) || v < 0) {
            why = "controller gains, sample period, delay and output limit must be finite and not negative";
            return false;
        }
    if (c.kp <= 0) {
        why = "controller kp must be positive (a position loop is required)";
        return false;
    }
    if (c.kvi > 0 && c.kv <= 0) {
        why = "controller kvi needs a velocity loop (kv > 0)";
        return false;
    }
    if (c.sample_period == 0 && c.velocity_estimate != VelocityEstimate::Measured) {
        why = "a velocity estimate from samples needs a sample period";
        return false;
    }
    if (!delay_in_whole_samples(c)) {
        why = "a discrete controller's delay must be a whole number of sample periods";
        return false;
    }
    return true;
}

// The one prismatic or revolute tree joint `ref` names, or -1 with `why`.
int find_drivable_joint(const JointRef& ref, const JointIndex& joints_of, const Mechanism& m, std::string& why) {
    const int j = find_joint(ref, joints_of, m, why);
    if (j < 0) return -1;
    const Joint& joint = m.joints[size_t(j)];
    if (joint.type != MBX_PRIMITIVE_REVOLUTE && joint.type != MBX_PRIMITIVE_PRISMATIC) {
        why = "joint '" + joint.name + "' is " + (joint.type == MBX_PRIMITIVE_SPHERICAL ? "spherical" : "a weld") +
              ": only prismatic and revolute joints can be driven";
        return -1;
    }
    if (joint.cut) {
        why = "joint '" + joint.name + "' closes a loop (cut joint): drive a tree joint of the loop instead";
        return -1;
    }
    return j;
}

}  // namespace

std::array<std::pair<const char*, double>, 8> controller_values(const ControllerSpec& c) {
    return {{{"kp", c.kp},
             {"ki", c.ki},
             {"kd", c.kd},
             {"kv", c.kv},
             {"kvi", c.kvi},
             {"sample_period", c.sample_period},
             {"delay", c.delay},
             {"output_limit", c.output_limit}}};
}

bool delay_in_whole_samples(const ControllerSpec& c) {
    if (!(c.sample_period > 0)) return true;
    const double samples = c.delay / c.sample_period;
    return std::fabs(samples - std::round(samples)) <= 1e-9 * std::max(1.0, samples);
}

ServoEquivalent servo_equivalent(const Drive& d) {
    ServoEquivalent s;
    const ControllerSpec& c = d.spec.controller;
    const double k = d.motor.torque_constant;
    const bool voltage = d.spec.amplifier.mode == AmplifierMode::Voltage;
    // Joint effort per unit of controller output.
    const double gain =
        d.efficiency * d.ratio * k * (voltage ? 1 / d.armature_resistance : d.spec.amplifier.gain);
    if (c.kv > 0) {
        s.stiffness = gain * c.kv * c.kp;
        s.damping = gain * c.kv * (c.kd + 1);
    } else {
        s.stiffness = gain * c.kp;
        s.damping = gain * c.kd;
    }
    if (voltage) s.emf_damping = d.efficiency * d.ratio * d.ratio * k * k / d.armature_resistance;
    s.effort_limit = gain * d.output_limit;
    std::string why;
    auto add = [&why](const std::string& part) { why += (why.empty() ? "" : ", ") + part; };
    if (c.ki > 0 || c.kvi > 0) add("integral action left out");
    if (c.sample_period > 0) add("sampling at " + short_number(c.sample_period) + " s");
    if (c.delay > 0) add("a transport delay of " + short_number(c.delay) + " s");
    // The armature inductance is always neglected: La/Ra is microseconds for
    // the motors this serves, far below any mechanical time constant.
    s.approximation = why;
    return s;
}

std::vector<Drive> resolve_drives(const MechatronicSpec& spec, const Mechanism& m, std::vector<DriveError>& errors) {
    std::vector<Drive> out;
    out.reserve(spec.drives.size());
    const JointIndex joints_of = index_joints_by_constraint(m);
    std::vector<char> driven(m.joints.size(), 0);
    for (size_t index = 0; index < spec.drives.size(); ++index) {
        const DriveSpec& s = spec.drives[index];
        const std::string who = s.name.empty() ? s.joint.constraint_id : s.name;
        bool good = true;
        auto error = [&](std::string message) {
            errors.push_back({s.file, s.line, who, std::move(message)});
            good = false;
        };
        std::string why;

        // The joint.
        Drive d;
        d.source = int(index);
        d.joint = find_drivable_joint(s.joint, joints_of, m, why);
        if (d.joint < 0) {
            error(why);
            continue;
        }
        const Joint& joint = m.joints[size_t(d.joint)];
        if (driven[size_t(d.joint)]) {
            error("joint '" + joint.name + "' is driven twice");
            continue;
        }
        d.spec = s;
        d.name = s.name.empty() ? joint.name : s.name;
        d.linear = joint.type == MBX_PRIMITIVE_PRISMATIC;
        const bool angle_unit = s.motion_unit == "rad" || s.motion_unit == "deg";
        const bool length_unit = s.motion_unit == "m" || s.motion_unit == "mm";
        if ((d.linear && angle_unit) || (!d.linear && length_unit)) {
            error("motion in '" + s.motion_unit + "' for the " + (d.linear ? "prismatic" : "revolute") + " joint '" +
                  joint.name + "'");
            continue;
        }

        // The motor.
        const ObjectLibrary::Found motor = spec.library.find(s.motor_id);
        if (!motor.object) {
            error("motor '" + s.motor_id + "' is not in the object library");
            continue;
        }
        if (motor.cls->kind != "dc_motor") {
            error("object '" + motor.object->name + "' (" + s.motor_id + ") is a '" + motor.cls->name +
                  "', not a dc_motor");
            continue;
        }
        ObjectLibrary::Found transmission;
        if (!s.transmission_id.empty()) {
            transmission = spec.library.find(s.transmission_id);
            if (!transmission.object) {
                error("transmission '" + s.transmission_id + "' is not in the object library");
                continue;
            }
            if (transmission.cls->kind != "gearbox" && transmission.cls->kind != "ball_screw") {
                error("object '" + transmission.object->name + "' is a '" + transmission.cls->name +
                      "', not a gearbox or ball_screw");
                continue;
            }
        }
        for (const auto& [name, value] : s.overrides) {
            (void)value;
            const bool declared = motor.cls->parameter(name) || (transmission.cls && transmission.cls->parameter(name));
            if (!declared) error("override of unknown parameter '" + name + "'");
        }
        const LibraryObject motor_object = apply_overrides(motor, s.overrides, error);
        const ObjectLibrary::Found motor_found{motor.cls, &motor_object};
        const std::optional<DcMotorConstants> mc = dc_motor_constants(spec.library, motor_found, why);
        if (!mc) error("motor '" + motor.object->name + "': " + why);
        if (!good) continue;
        d.motor = *mc;
        d.motor_name = motor.object->name;
        d.armature_resistance = spec.library.value_in_si(motor_found, "Ra").value_or(0);
        d.armature_inductance = spec.library.value_in_si(motor_found, "La").value_or(0);

        if (transmission.object) {
            const LibraryObject transmission_object = apply_overrides(transmission, s.overrides, error);
            const ObjectLibrary::Found t_found{transmission.cls, &transmission_object};
            const std::optional<TransmissionConstants> tc = transmission_constants(spec.library, t_found, why);
            if (!tc) error("transmission '" + transmission.object->name + "': " + why);
            if (!good) continue;
            if (tc->linear != d.linear) {
                error(std::string("a ") + (tc->linear ? "ball screw" : "gearbox") + " cannot drive the " +
                      (d.linear ? "prismatic" : "revolute") + " joint '" + joint.name + "'");
                continue;
            }
            d.transmission_name = transmission.object->name;
            d.transmission_kind = transmission.cls->kind;
            d.transmission_ratio = tc->ratio;
            d.transmission_inertia = tc->inertia;
            d.efficiency = tc->efficiency;
        } else if (d.linear) {
            error("the prismatic joint '" + joint.name + "' needs a ball_screw transmission to turn motor rotation into travel");
            continue;
        }
        d.ratio = d.motor.ratio * d.transmission_ratio;
        d.armature = d.motor.rotor_inertia * d.ratio * d.ratio +
                     d.transmission_inertia * d.transmission_ratio * d.transmission_ratio;

        // Amplifier and controller.
        if (!valid_controller(s.controller, why)) {
            error(why);
            continue;
        }
        const bool voltage = s.amplifier.mode == AmplifierMode::Voltage;
        if (!voltage && !(std::isfinite(s.amplifier.gain) && s.amplifier.gain > 0)) {
            error("a current amplifier needs a positive gain (A per unit of controller output)");
            continue;
        }
        double va_nominal = spec.library.value_in_si(motor_found, "VaNominal").value_or(0);
        d.output_limit = s.controller.output_limit > 0 ? s.controller.output_limit : voltage ? va_nominal : 0;
        if (!(d.output_limit > 0)) {
            error("a current-mode drive needs an output limit (the amplifier's input range)");
            continue;
        }
        const double max_current = voltage ? d.output_limit / d.armature_resistance : s.amplifier.gain * d.output_limit;
        d.effort_limit = d.efficiency * d.ratio * d.motor.torque_constant * max_current;
        d.velocity_limit = (voltage ? d.output_limit : va_nominal) / d.motor.torque_constant / d.ratio;
        d.servo = servo_equivalent(d);
        driven[size_t(d.joint)] = 1;  // only a drive that resolved claims its joint
        out.push_back(std::move(d));
    }
    return out;
}

}  // namespace mbx
