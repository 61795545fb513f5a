#include "export/modelica/mechatronic_writer.h"

#include <algorithm>
#include <cmath>

#include "export/common/names.h"
#include "export/common/number_text.h"
#include "export/modelica/drive_blocks.h"
#include "export/modelica/model_text.h"
#include "export/modelica/modelica_text.h"

namespace mbx {

namespace {

const std::string kBlocks = "Modelica.Blocks.";
const std::string kAnalog = "Modelica.Electrical.Analog.";
const std::string kRotational = "Modelica.Mechanics.Rotational.";
const std::string kTranslational = "Modelica.Mechanics.Translational.";


// "[t1, q1; t2, q2; ...]"
std::string table_text(const std::vector<MotionPoint>& points) {
    std::string s = "[";
    for (size_t i = 0; i < points.size(); ++i)
        s += (i ? "; " : "") + number_text(points[i].time) + ", " + number_text(points[i].value);
    return s + "]";
}

int velocity_estimate_code(VelocityEstimate v) {
    switch (v) {
    case VelocityEstimate::Difference: return 1;
    case VelocityEstimate::FilteredDifference: return 2;
    case VelocityEstimate::Measured: break;
    }
    return 0;
}

class MechatronicBuilder {
public:
    MechatronicBuilder(ExportModel& model, const std::string& package, const std::vector<JointFlanges>& flanges)
        : model_(model), m_(model.mechanism()), package_(package), flanges_(flanges) {}

    MechatronicModel build();

private:
    void add_drive(int index);
    void add_joint_dynamics(int index);
    // Declares <prefix>_<role> and returns its name.
    std::string add(const std::string& role, const std::string& class_name,
                    std::vector<std::pair<std::string, std::string>> modifiers, const std::string& what);
    void connect(const std::string& a, const std::string& b) { connects_.push_back({{}, a, b}); }
    // y = sum of gain * signal, as a Gain, Add or Add3 (terms: 1 to 3).
    std::string weighted_sum(const std::string& role, const std::vector<std::pair<std::string, double>>& terms,
                             const std::string& what);

    ExportModel& model_;
    const Mechanism& m_;
    std::string package_;
    const std::vector<JointFlanges>& flanges_;
    NameTable names_;
    ModelicaModel out_;
    MechatronicModel result_;
    // The drive or joint dynamics being written, and how descriptions name it.
    const Drive* drive_ = nullptr;
    std::string owner_;
    std::string prefix_;
    ModelicaDriveComponents* parts_ = nullptr;
    size_t first_component_ = 0;
    std::vector<ModelicaConnect> connects_;
};

std::string MechatronicBuilder::add(const std::string& role, const std::string& class_name,
                                    std::vector<std::pair<std::string, std::string>> modifiers,
                                    const std::string& what) {
    ModelicaComponent c;
    c.class_name = class_name;
    c.name = names_.claim(prefix_ + "_" + role);
    c.modifiers = std::move(modifiers);
    c.description = owner_ + ": " + what;
    parts_->roles.emplace_back(role, c.name);
    out_.components.push_back(std::move(c));
    return out_.components.back().name;
}

std::string MechatronicBuilder::weighted_sum(const std::string& role,
                                             const std::vector<std::pair<std::string, double>>& terms,
                                             const std::string& what) {
    std::string name;
    if (terms.size() == 1) {
        name = add(role, kBlocks + "Math.Gain", {{"k", number_text(terms[0].second)}}, what);
        connect(terms[0].first, name + ".u");
        return name + ".y";
    }
    std::vector<std::pair<std::string, std::string>> gains;
    for (size_t i = 0; i < terms.size(); ++i) gains.emplace_back("k" + std::to_string(i + 1), number_text(terms[i].second));
    name = add(role, kBlocks + (terms.size() == 2 ? "Math.Add" : "Math.Add3"), std::move(gains), what);
    for (size_t i = 0; i < terms.size(); ++i) connect(terms[i].first, name + ".u" + std::to_string(i + 1));
    return name + ".y";
}

void MechatronicBuilder::add_drive(int index) {
    const Drive& d = model_.settings().drives[size_t(index)];
    const Joint* joint = d.joint >= 0 && size_t(d.joint) < m_.joints.size() ? &m_.joints[size_t(d.joint)] : nullptr;
    const bool has_flange = joint && size_t(d.joint) < flanges_.size() && !flanges_[size_t(d.joint)].axis.empty();
    if (!has_flange || (joint->type == MBX_PRIMITIVE_PRISMATIC) != d.linear) {
        model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION,
                    joint ? model_.joint_subject(d.joint) : Subject::model(model_.settings().model_name),
                    "Modelica: drive " + quoted_identifier(d.name) + " is left out of Mechatronic.mo: its joint" +
                        (joint ? " " + quoted_identifier(joint->name) : std::string()) +
                        " has no axis flange in Mechanics.mo (a cut joint or the revolute that carries a "
                        "planar-loop constraint)");
        return;
    }
    drive_ = &d;
    owner_ = "drive " + quoted_identifier(d.name);
    prefix_ = sanitize_identifier(d.name, "drive");
    result_.drives.push_back({index, prefix_, {}});
    parts_ = &result_.drives.back();
    first_component_ = out_.components.size();
    connects_.clear();

    const ControllerSpec& c = d.spec.controller;
    const bool linear = d.linear;
    const bool discrete = c.sample_period > 0;
    const bool voltage = d.spec.amplifier.mode == AmplifierMode::Voltage;
    const std::string axis = "mechanics." + flanges_[size_t(d.joint)].axis;
    const std::string unit = linear ? "m" : "rad";

    // The motion target.
    const MotionProfile& motion = d.spec.motion;
    std::string target;
    if (motion.points().empty()) {
        target = add("target", kBlocks + "Sources.Constant", {{"k", "0"}}, "no motion given: holds 0") + ".y";
    } else if (motion.interpolation() == Interpolation::Smooth) {
        result_.uses_smooth_target = true;
        target = add("target", package_ + "." + kSmoothTargetBlock, {{"table", table_text(motion.points())}},
                     "motion target (smooth: rest-to-rest quintic segments), " + unit) +
                 ".y";
    } else {
        const bool step = motion.interpolation() == Interpolation::Step;
        target = add("target", kBlocks + "Sources.CombiTimeTable",
                     {{"table", table_text(motion.points())},
                      {"smoothness", kBlocks + (step ? "Types.Smoothness.ConstantSegments"
                                                     : "Types.Smoothness.LinearSegments")},
                      {"extrapolation", kBlocks + "Types.Extrapolation.HoldLastPoint"}},
                     std::string("motion target (") + interpolation_name(motion.interpolation()) + "), " + unit) +
                 ".y[1]";
    }

    // Sensors on the joint side.
    const std::string& mechanics_joint = joint->name;
    const std::string position =
        add("position", linear ? kTranslational + "Sensors.PositionSensor" : kRotational + "Sensors.AngleSensor", {},
            std::string("joint ") + (linear ? "position" : "angle") + " of " + quoted_identifier(mechanics_joint) + ", " + unit);
    connect(position + ".flange", axis);
    const std::string q = position + (linear ? ".s" : ".phi");
    std::string qd;
    if (discrete || c.kd > 0 || c.kv > 0) {
        const std::string speed =
            add("speed", linear ? kTranslational + "Sensors.SpeedSensor" : kRotational + "Sensors.SpeedSensor", {},
                "joint velocity of " + quoted_identifier(mechanics_joint) + ", " + unit + "/s");
        connect(speed + ".flange", axis);
        qd = speed + (linear ? ".v" : ".w");
    }

    // The controller.
    std::string u;
    if (discrete) {
        result_.uses_discrete_controller = true;
        const long delay_samples = std::lround(c.delay / c.sample_period);
        const std::string ctl =
            add("controller", package_ + "." + kDiscreteControllerBlock,
                {{"kp", number_text(c.kp)},
                 {"ki", number_text(c.ki)},
                 {"kd", number_text(c.kd)},
                 {"kv", number_text(c.kv)},
                 {"kvi", number_text(c.kvi)},
                 {"Ts", number_text(c.sample_period)},
                 {"delaySamples", std::to_string(delay_samples)},
                 {"uMax", number_text(d.output_limit)},
                 {"velocityEstimate", std::to_string(velocity_estimate_code(c.velocity_estimate))}},
                "sampled controller (velocityEstimate 0 measured, 1 difference, 2 filtered difference)");
        connect(target, ctl + ".q_ref");
        connect(q, ctl + ".q");
        connect(qd, ctl + ".qd");
        u = ctl + ".y";
    } else {
        const std::string error = add("error", kBlocks + "Math.Feedback", {}, "position error e = target - q");
        connect(target, error + ".u1");
        connect(q, error + ".u2");
        std::vector<std::pair<std::string, double>> terms{{error + ".y", c.kp}};
        if (c.ki > 0) {
            const std::string integral =
                add("error_integral", kBlocks + "Continuous.Integrator", {{"k", "1"}}, "integral of e");
            connect(error + ".y", integral + ".u");
            terms.emplace_back(integral + ".y", c.ki);
        }
        if (c.kd > 0) terms.emplace_back(qd, -c.kd);
        u = weighted_sum("position_law", terms, "position loop u_p = kp e + ki int(e) - kd qdot");
        if (c.kv > 0) {
            const std::string verror =
                add("velocity_error", kBlocks + "Math.Feedback", {}, "velocity error u_p - qdot");
            connect(u, verror + ".u1");
            connect(qd, verror + ".u2");
            std::vector<std::pair<std::string, double>> vterms{{verror + ".y", c.kv}};
            if (c.kvi > 0) {
                const std::string integral = add("velocity_error_integral", kBlocks + "Continuous.Integrator",
                                                 {{"k", "1"}}, "integral of u_p - qdot");
                connect(verror + ".y", integral + ".u");
                vterms.emplace_back(integral + ".y", c.kvi);
            }
            u = weighted_sum("velocity_law", vterms, "velocity loop u = kv (u_p - qdot) + kvi int(u_p - qdot)");
        }
        const std::string limiter =
            add("limiter", kBlocks + "Nonlinear.Limiter",
                {{"uMax", number_text(d.output_limit)}, {"uMin", number_text(-d.output_limit)}},
                std::string("controller output bound, ") + (voltage ? "V" : "amplifier input units"));
        connect(u, limiter + ".u");
        u = limiter + ".y";
        if (c.delay > 0) {
            const std::string delay =
                add("delay", kBlocks + "Nonlinear.FixedDelay", {{"delayTime", number_text(c.delay)}}, "transport delay");
            connect(u, delay + ".u");
            u = delay + ".y";
        }
        // Where MSL's blocks and mbx's own controller (DriveController) part.
        std::string differs;
        if (c.ki > 0 || c.kvi > 0)
            differs = "MSL's Integrator keeps integrating while the output is saturated (mbx's controller holds an "
                      "integral that pushes further into saturation)";
        if (c.delay > 0)
            differs += std::string(differs.empty() ? "" : "; ") + "FixedDelay gives the controller's initial output, not 0, "
                       "during the first " + number_text(c.delay) + " s";
        if (!differs.empty())
            model_.note(MBX_SEVERITY_INFO, MBX_FINDING_EXPORT_APPROXIMATION, model_.joint_subject(d.joint),
                        "Modelica: drive " + quoted_identifier(d.name) + " has a continuous controller of MSL blocks: " + differs);
    }

    // Amplifier and armature circuit.
    std::string source;
    if (voltage) {
        source = add("source", kAnalog + "Sources.SignalVoltage", {}, "voltage amplifier: armature voltage = u");
        connect(u, source + ".v");
    } else {
        const std::string amplifier = add("amplifier", kBlocks + "Math.Gain",
                                          {{"k", number_text(d.spec.amplifier.gain)}}, "current amplifier gain, A per unit of u");
        connect(u, amplifier + ".u");
        source = add("source", kAnalog + "Sources.SignalCurrent", {}, "current amplifier: armature current");
        connect(amplifier + ".y", source + ".i");
    }
    const std::string resistor = add("resistor", kAnalog + "Basic.Resistor", {{"R", number_text(d.armature_resistance)}},
                                     "armature resistance of motor " + quoted_identifier(d.motor_name));
    // An ideal current source imposes the current: an inductor would only ask
    // a Modelica tool to differentiate the controller output.
    std::string inductor;
    if (voltage && d.armature_inductance > 0)
        inductor = add("inductor", kAnalog + "Basic.Inductor", {{"L", number_text(d.armature_inductance)}},
                       "armature inductance of motor " + quoted_identifier(d.motor_name));
    const std::string emf = add("emf", kAnalog + "Basic.RotationalEMF", {{"k", number_text(d.motor.torque_constant)}},
                                "torque and back-EMF constant of motor " + quoted_identifier(d.motor_name) + ", N m/A");
    const std::string ground = add("ground", kAnalog + "Basic.Ground", {}, "electrical ground of the armature circuit");
    // Current flows from the source through the resistor (and inductor) into
    // emf.p: SignalVoltage drives it out of p, SignalCurrent out of n.
    const std::string out_pin = source + (voltage ? ".p" : ".n");
    const std::string return_pin = source + (voltage ? ".n" : ".p");
    connect(out_pin, resistor + ".p");
    if (!inductor.empty()) {
        connect(resistor + ".n", inductor + ".p");
        connect(inductor + ".n", emf + ".p");
    } else {
        connect(resistor + ".n", emf + ".p");
    }
    connect(emf + ".n", return_pin);
    connect(return_pin, ground + ".p");

    // Drive train: motor shaft -> built-in gear -> transmission -> joint.
    std::string shaft = emf + ".flange";
    if (d.motor.rotor_inertia > 0) {
        const std::string rotor = add("rotor", kRotational + "Components.Inertia",
                                      {{"J", number_text(d.motor.rotor_inertia)}}, "rotor inertia of motor " + quoted_identifier(d.motor_name));
        connect(shaft, rotor + ".flange_a");
        shaft = rotor + ".flange_b";
    }
    const std::string gear = add("motor_gear", kRotational + "Components.IdealGear",
                                 {{"ratio", number_text(d.motor.ratio)}},
                                 "built-in gear of motor " + quoted_identifier(d.motor_name) + " (motor turns per output turn)");
    connect(shaft, gear + ".flange_a");
    shaft = gear + ".flange_b";
    const bool gearbox = d.transmission_kind == "gearbox";
    const bool screw = d.transmission_kind == "ball_screw";
    if (gearbox || screw) {
        const std::string what = std::string(gearbox ? "gearbox " : "ball screw ") + quoted_identifier(d.transmission_name);
        if (d.transmission_inertia > 0) {
            const std::string inertia = add("transmission_inertia", kRotational + "Components.Inertia",
                                            {{"J", number_text(d.transmission_inertia)}}, "own inertia of " + what + " at its input");
            connect(shaft, inertia + ".flange_a");
            shaft = inertia + ".flange_b";
        }
        const std::string eta = number_text(d.efficiency);
        const std::string lossy =
            add("transmission", kRotational + "Components.LossyGear",
                {{"ratio", gearbox ? number_text(d.transmission_ratio) : "1"},
                 {"lossTable", "[0, " + eta + ", " + eta + ", 0, 0]"}},
                what + ": " + (gearbox ? "ratio and " : "") + "efficiency (driving and back-driven)");
        connect(shaft, lossy + ".flange_a");
        shaft = lossy + ".flange_b";
        if (screw) {
            const std::string r2t = add("screw", kRotational + "Components.IdealGearR2T",
                                        {{"ratio", number_text(d.transmission_ratio)}}, what + ": 2 pi / lead, rad/m");
            connect(shaft, r2t + ".flangeR");
            shaft = r2t + ".flangeT";
        }
    }
    connect(shaft, axis);

    out_.components[first_component_].comment =
        "Drive " + quoted_identifier(d.name) + " on " + (linear ? "prismatic " : "revolute ") + quoted_identifier(mechanics_joint) +
        ": motor " + quoted_identifier(d.motor_name) +
        (d.transmission_name.empty() ? std::string()
                                        : std::string(d.transmission_kind == "gearbox" ? ", gearbox " : ", ball screw ") +
                                              quoted_identifier(d.transmission_name)) +
        (discrete ? ", sampled controller" : ", continuous controller") + (voltage ? ", voltage" : ", current") +
        " amplifier";
    connects_.front().comment = "Drive " + quoted_identifier(d.name);
    for (ModelicaConnect& cn : connects_) out_.connects.push_back(std::move(cn));
}

// Damping and spring as one compliant element between the joint's support
// (fixed in the world inside MSL's Revolute and Prismatic) and its axis, so
// its relative coordinate is the joint coordinate; Coulomb friction as MSL's
// bearing (support) friction with stick/slip; armature as an inertia (mass)
// on the axis. MultiBody joints have no limits: they become a note.
//
// MSL's friction is symmetric, but an asymmetric Coulomb law is exactly the
// mean level plus the constant effort -(coulomb - coulomb_negative)/2, in
// slip and in stick alike; that and the effort offset become one constant
// torque (force) source between support and axis. A Stribeck peak is the
// friction table's value at rest (peak = 1, so the static friction is
// exact) decaying along sampled points of exp(-(w/vs)^2). Only asymmetric
// damping has no MSL element: the mean damping and a note.
void MechatronicBuilder::add_joint_dynamics(int index) {
    const ResolvedJointDynamics& jd = model_.settings().joint_dynamics[size_t(index)];
    const Joint* joint = jd.joint >= 0 && size_t(jd.joint) < m_.joints.size() ? &m_.joints[size_t(jd.joint)] : nullptr;
    const bool has_flange = joint && size_t(jd.joint) < flanges_.size() && !flanges_[size_t(jd.joint)].axis.empty();
    if (!has_flange) {
        model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION,
                    joint ? model_.joint_subject(jd.joint) : Subject::model(model_.settings().model_name),
                    "Modelica: the joint dynamics of " + quoted_identifier(jd.name) +
                        " are left out of Mechatronic.mo: the joint has no axis flange in Mechanics.mo (the "
                        "revolute that carries a planar-loop constraint)");
        return;
    }
    if (jd.limited)
        model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, model_.joint_subject(jd.joint),
                    "Modelica MultiBody joints have no position limits: the limits [" + number_text(jd.lower) + ", " +
                        number_text(jd.upper) + "] of joint " + quoted_identifier(jd.name) + " are not in Mechatronic.mo");
    const bool linear = jd.linear;
    const std::string axis = "mechanics." + flanges_[size_t(jd.joint)].axis;
    const std::string support = "mechanics." + flanges_[size_t(jd.joint)].support;
    const std::string lib = linear ? kTranslational : kRotational;
    const std::string rest = linear ? "s_rel0" : "phi_rel0";
    const std::string effort_unit = linear ? "N" : "N m", position_unit = linear ? "m" : "rad";

    drive_ = nullptr;
    owner_ = "joint dynamics of " + quoted_identifier(jd.name);
    prefix_ = sanitize_identifier(jd.name, "joint");
    result_.joint_dynamics.push_back({index, prefix_, {}});
    parts_ = &result_.joint_dynamics.back();
    first_component_ = out_.components.size();
    connects_.clear();

    std::string compliant;
    const std::string damping_text =
        "damping " + number_text(jd.symmetric_damping()) + " " + effort_unit + " s/" + position_unit +
        (jd.damping_negative != jd.damping ? " (mean of both directions)" : "");
    const std::string spring_text = "stiffness " + number_text(jd.stiffness) + " " + effort_unit + "/" + position_unit +
                                    " about " + number_text(jd.rest) + " " + position_unit;
    const double damping = jd.symmetric_damping();
    if (jd.damping_negative != jd.damping)
        model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, model_.joint_subject(jd.joint),
                    "Modelica: MSL's dampers are symmetric: joint " + quoted_identifier(jd.name) + " gets the mean damping " +
                        number_text(damping) + " of " + number_text(jd.damping) + " (q' > 0) and " +
                        number_text(jd.damping_negative) + " (q' < 0)");
    if (damping > 0 && jd.stiffness > 0)
        compliant = add("spring_damper", lib + "Components.SpringDamper",
                        {{"c", number_text(jd.stiffness)}, {"d", number_text(damping)}, {rest, number_text(jd.rest)}},
                        spring_text + ", " + damping_text);
    else if (jd.stiffness > 0)
        compliant = add("spring", lib + "Components.Spring", {{"c", number_text(jd.stiffness)}, {rest, number_text(jd.rest)}},
                        spring_text);
    else if (damping > 0)
        compliant = add("damper", lib + "Components.Damper", {{"d", number_text(damping)}}, damping_text);
    if (!compliant.empty()) {
        connect(support, compliant + ".flange_a");
        connect(compliant + ".flange_b", axis);
    }
    const double coulomb = jd.symmetric_coulomb();
    if (coulomb > 0 || jd.stribeck > 0) {
        std::string table = "[0, " + number_text(coulomb + jd.stribeck);
        std::string what = "Coulomb friction " + number_text(coulomb) + " " + effort_unit;
        if (jd.stribeck > 0) {
            // Rows every vs/4 up to 2.5 vs, then flat from 3 vs (where the
            // peak is down to 1e-4 of itself): MSL extrapolates the last
            // segment, which must not keep falling.
            for (int k = 1; k <= 10; ++k) {
                const double x = 0.25 * k;
                table += "; " + number_text(x * jd.stribeck_velocity) + ", " +
                         number_text(coulomb + jd.stribeck * std::exp(-x * x));
            }
            table += "; " + number_text(3 * jd.stribeck_velocity) + ", " + number_text(coulomb);
            table += "; " + number_text(4 * jd.stribeck_velocity) + ", " + number_text(coulomb);
            what += " with a Stribeck peak " + number_text(jd.stribeck) + " " + effort_unit + " decaying over " +
                    number_text(jd.stribeck_velocity) + (linear ? " m/s" : " rad/s");
        }
        table += "]";
        if (jd.coulomb_negative != jd.coulomb) what += " (mean of both directions)";
        const std::string friction =
            add("friction", lib + (linear ? "Components.SupportFriction" : "Components.BearingFriction"),
                {{linear ? "f_pos" : "tau_pos", table}, {"peak", "1"}}, what + " (stick and slip)");
        connect(friction + ".flange_a", axis);
    }
    // The effort on the joint: -offset, and the asymmetric Coulomb law's
    // constant part. MSL's sources drive their flange with +tau_constant
    // (+f_constant) and put the reaction on their support.
    const double constant = -jd.offset - (jd.coulomb - jd.coulomb_negative) / 2;
    if (constant != 0) {
        std::string what = "constant effort " + number_text(constant) + " " + effort_unit + " on the joint (";
        if (jd.offset != 0) what += "offset " + number_text(jd.offset) + " " + effort_unit + " acting as -offset";
        if (jd.offset != 0 && jd.coulomb_negative != jd.coulomb) what += "; ";
        if (jd.coulomb_negative != jd.coulomb)
            what += "asymmetric Coulomb friction " + number_text(jd.coulomb) + " (q' > 0) / " +
                    number_text(jd.coulomb_negative) + " (q' < 0) = their mean plus this constant";
        what += ")";
        const std::string source =
            add("offset", lib + (linear ? "Sources.ConstantForce" : "Sources.ConstantTorque"),
                {{linear ? "f_constant" : "tau_constant", number_text(constant)}, {"useSupport", "true"}}, what);
        connect(source + ".flange", axis);
        connect(source + ".support", support);
    }
    if (jd.armature > 0) {
        const std::string armature =
            add("armature", lib + (linear ? "Components.Mass" : "Components.Inertia"),
                {{linear ? "m" : "J", number_text(jd.armature)}},
                "armature " + number_text(jd.armature) + (linear ? " kg" : " kg m2") + " on the joint");
        connect(armature + ".flange_a", axis);
    }
    if (out_.components.size() == first_component_) {  // nothing MSL needs (limits only, or all zero)
        result_.joint_dynamics.pop_back();
        return;
    }
    out_.components[first_component_].comment =
        "Joint dynamics of " + std::string(linear ? "prismatic " : "revolute ") + quoted_identifier(jd.name);
    connects_.front().comment = "Joint dynamics of " + quoted_identifier(jd.name);
    for (ModelicaConnect& cn : connects_) out_.connects.push_back(std::move(cn));
}

MechatronicModel MechatronicBuilder::build() {
    const ExportSettings& settings = model_.settings();
    for (const char* fixed : {"mechanics", "Modelica", "ModelicaServices", "Complex", "Mechanics", "Mechatronic",
                              "UserModel", "time"})
        names_.reserve(fixed);
    names_.reserve(package_);
    names_.reserve(kDiscreteControllerBlock);
    names_.reserve(kSmoothTargetBlock);

    out_.header = "Generated by mbx from " + quoted_identifier(settings.model_name) +
                  ". Do not edit: every export rewrites this file.\n"
                  "The drives and joint dynamics of the mechanism acting on Mechanics; put your changes in "
                  "UserModel.mo.";
    out_.within = package_;
    out_.name = "Mechatronic";
    out_.description = "Drives and joint dynamics of " + quoted_identifier(settings.model_name) +
                       " on its multibody model (generated by mbx)";
    ModelicaComponent mechanics;
    mechanics.class_name = package_ + ".Mechanics";
    mechanics.name = "mechanics";
    mechanics.description = "the mechanical model; drives act on its axis_* flanges";
    out_.components.push_back(std::move(mechanics));

    double stop = settings.stop_time > 0 ? settings.stop_time : 10;
    for (size_t i = 0; i < settings.drives.size(); ++i) {
        const size_t before = result_.drives.size();
        add_drive(int(i));
        if (result_.drives.size() == before) continue;
        const std::vector<MotionPoint>& points = settings.drives[i].spec.motion.points();
        if (!points.empty()) stop = std::max(stop, points.back().time);
    }
    for (size_t i = 0; i < settings.joint_dynamics.size(); ++i) add_joint_dynamics(int(i));
    if (result_.drives.empty() && result_.joint_dynamics.empty()) return {};
    out_.annotation = "experiment(StopTime = " + number_text(stop) + ", Interval = " + number_text(stop / 500) +
                      ", Tolerance = 1e-06)";
    result_.stop_time = stop;
    result_.text = format_model(out_);
    return std::move(result_);
}

}  // namespace

std::string ModelicaDriveComponents::component(const std::string& role) const {
    for (const auto& [r, name] : roles)
        if (r == role) return name;
    return {};
}

MechatronicModel write_mechatronic(ExportModel& model, const std::string& package,
                                   const std::vector<JointFlanges>& flanges) {
    MechatronicBuilder builder(model, package, flanges);
    return builder.build();
}

}  // namespace mbx
