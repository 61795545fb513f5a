// The drives in the Modelica export: Mechatronic.mo (and the package's
// helper blocks) read back by the independent parser, checked against the
// MSL 4.0 class index, and its parameters traced along the connect graph from
// each driven joint's flange back to the motor: the inertia and joint effort
// limit they add up to must be the drive's own (Drive::armature,
// Drive::effort_limit), the controller's block diagram must compute the law
// of ControllerSpec, and the motion target must hold the profile's points.
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <set>

#include "apps/stub_host/assemblies/builder.h"
#include "tests/common/file_text.h"
#include "core/mechatronics/drive.h"
#include "export/modelica/mechanics_writer.h"
#include "export/modelica/mechatronic_writer.h"
#include "modelica_support.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

const std::string kRot = "Modelica.Mechanics.Rotational.";
const std::string kTrans = "Modelica.Mechanics.Translational.";
const std::string kBlocks = "Modelica.Blocks.";
const std::string kAnalog = "Modelica.Electrical.Analog.";
constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------
// Drives built by hand, their derived quantities as resolve_drives derives them
// ---------------------------------------------------------------------------
struct Motor {
    std::string name;
    double J, Va, Ia, rpm, Ra, La, ratio;
};
// Kondo KRS-784ICS (the bundled library's values) and a 150 W, 48 V motor.
const Motor kKrs{"KRS-784ICS", 1.2e-7, 8, 1.2, 8200, 0.78, 2.1e-5, 251};
const Motor kMotor150{"DC 150 W 48 V", 1.42e-5, 48, 3.17, 6930, 0.299, 8.2e-5, 1};

struct Transmission {
    std::string name, kind;  // "gearbox" or "ball_screw"
    double ratio;            // gearbox ratio, or 2 pi / lead
    double efficiency, J;
};
const Transmission kHarmonic{"strain-wave 100:1", "gearbox", 100, 0.75, 1.5e-6};
const Transmission kScrew{"ball screw 5 mm", "ball_screw", 2 * kPi / 0.005, 0.9, 4e-5};

int joint_named(const Mechanism& m, const std::string& name) {
    for (size_t j = 0; j < m.joints.size(); ++j)
        if (m.joints[j].name == name) return int(j);
    FAIL("no joint " << name);
    return -1;
}

Drive make_drive(const Mechanism& m, const std::string& name, const std::string& joint, const Motor& motor,
                 const Transmission* transmission, AmplifierSpec amplifier, ControllerSpec controller,
                 MotionProfile motion) {
    Drive d;
    d.spec.name = name;
    d.spec.amplifier = amplifier;
    d.spec.controller = controller;
    d.spec.motion = std::move(motion);
    d.name = name;
    d.joint = joint_named(m, joint);
    d.linear = m.joints[size_t(d.joint)].type == MBX_PRIMITIVE_PRISMATIC;
    d.motor_name = motor.name;
    const double w = motor.rpm * 2 * kPi / 60;
    d.motor.torque_constant = (motor.Va - motor.Ra * motor.Ia) / w;
    d.motor.stall_torque = d.motor.torque_constant * motor.Va / motor.Ra;
    d.motor.no_load_speed = motor.Va / d.motor.torque_constant;
    d.motor.rotor_inertia = motor.J;
    d.motor.ratio = motor.ratio;
    d.motor.reflected_inertia = motor.J * motor.ratio * motor.ratio;
    d.armature_resistance = motor.Ra;
    d.armature_inductance = motor.La;
    if (transmission) {
        d.transmission_name = transmission->name;
        d.transmission_kind = transmission->kind;
        d.transmission_ratio = transmission->ratio;
        d.transmission_inertia = transmission->J;
        d.efficiency = transmission->efficiency;
    }
    d.ratio = d.motor.ratio * d.transmission_ratio;
    d.armature = d.motor.rotor_inertia * d.ratio * d.ratio +
                 d.transmission_inertia * d.transmission_ratio * d.transmission_ratio;
    const bool voltage = amplifier.mode == AmplifierMode::Voltage;
    d.output_limit = controller.output_limit > 0 ? controller.output_limit : motor.Va;
    const double max_current = voltage ? d.output_limit / motor.Ra : amplifier.gain * d.output_limit;
    d.effort_limit = d.efficiency * d.ratio * d.motor.torque_constant * max_current;
    d.velocity_limit = (voltage ? d.output_limit : motor.Va) / d.motor.torque_constant / d.ratio;
    d.servo = servo_equivalent(d);
    return d;
}

ControllerSpec pid(double kp, double ki, double kd, double kv, double kvi, double limit, double delay = 0) {
    ControllerSpec c;
    c.kp = kp;
    c.ki = ki;
    c.kd = kd;
    c.kv = kv;
    c.kvi = kvi;
    c.output_limit = limit;
    c.delay = delay;
    return c;
}

// The EMPS rig's controller: P position loop, P velocity loop on the filtered
// difference of sampled positions, 1 ms sampling, one sample of delay, +-10 V.
ControllerSpec emps_controller() {
    ControllerSpec c;
    c.kp = 160.18;
    c.kv = 243.45;
    c.sample_period = 1e-3;
    c.delay = 1e-3;
    c.output_limit = 10;
    c.velocity_estimate = VelocityEstimate::FilteredDifference;
    return c;
}

AmplifierSpec voltage_amp() { return {}; }
AmplifierSpec current_amp(double gain) {
    AmplifierSpec a;
    a.mode = AmplifierMode::Current;
    a.gain = gain;
    return a;
}

// The six-axis arm with four drives that cover every variant on revolutes.
std::vector<Drive> arm_drives(const Mechanism& m) {
    std::vector<Drive> drives;
    drives.push_back(make_drive(m, "waist", "J1", kMotor150, &kHarmonic, voltage_amp(),
                                pid(20, 5, 0.5, 3, 1, 48, 0.002),
                                MotionProfile({{0, 0}, {1, 0.5}, {2, 0.5}, {3, 0}}, Interpolation::Linear)));
    drives.push_back(make_drive(m, "shoulder", "J2", kMotor150, &kHarmonic, current_amp(2.5), pid(30, 0, 0, 0, 0, 4),
                                MotionProfile({{0, 0}, {1, 0.2}, {4, -0.1}}, Interpolation::Step)));
    drives.push_back(make_drive(m, "wrist pitch", "J5", kKrs, nullptr, voltage_amp(), pid(50, 0, 0.1, 0, 0, 0),
                                MotionProfile({{0, 0}, {0.5, 0}, {1.3, 0.7}, {12.5, -0.2}}, Interpolation::Smooth)));
    Motor no_inductance = kKrs;
    no_inductance.La = 0;
    ControllerSpec sampled = pid(40, 2, 0.05, 0, 0, 6);
    sampled.sample_period = 0.002;
    sampled.velocity_estimate = VelocityEstimate::Difference;
    drives.push_back(make_drive(m, "hand", "J6", no_inductance, nullptr, voltage_amp(), sampled, MotionProfile()));
    return drives;
}

// ---------------------------------------------------------------------------
// A linear axis: a carriage on a prismatic joint (ball screw) and an arm on it
// ---------------------------------------------------------------------------
using mbx_stub::build::Builder;
using mbx_stub::build::Mat3;
using mbx_stub::build::Prim;
using mbx_stub::build::Vec3;

const mbx_units kSI{1, 1, 1};

void box_body(Builder& b, const std::string& local, const std::string& name, uint32_t flags, const Vec3& at,
              const Vec3& size) {
    const double mass = 1.0 + size.sum();
    b.body(local, name, flags, mass, Mat3::Identity(), at, at + Vec3(0.01, 0, 0.005),
           mbx_stub::build::box_inertia(mass, size.x(), size.y(), size.z()));
    b.mesh(local, mbx_stub::build::box_mesh(name, size, Mat3::Identity(), Vec3::Zero()));
}

mbx_memory::Assembly linear_axis() {
    mbx_memory::Assembly a;
    a.name = "linear axis";
    Builder b(a, "lin", kSI, kSI);
    box_body(b, "base", "Base", MBX_BODY_GROUND, Vec3(0, 0, -0.05), Vec3(1, 0.2, 0.1));
    box_body(b, "carriage", "Carriage", 0, Vec3(0, 0, 0.05), Vec3(0.2, 0.2, 0.05));
    box_body(b, "arm", "Arm", 0, Vec3(0.1, 0, 0.12), Vec3(0.2, 0.03, 0.03));
    Prim slide;
    slide.type = MBX_PRIMITIVE_PRISMATIC;
    slide.axis = Vec3(1, 0, 0);
    b.joint("slide", "base", "carriage", Vec3(0, 0, 0), Mat3::Identity(), {slide}, MBX_FRAME_IN_WORLD,
            MBX_FRAME_IN_WORLD);
    b.joint("pivot", "carriage", "arm", Vec3(0, 0, 0.1), Mat3::Identity(), {mbx_stub::build::revolute(Vec3(0, 0, 1))},
            MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    return a;
}

std::vector<Drive> axis_drives(const Mechanism& m) {
    std::vector<Drive> drives;
    drives.push_back(make_drive(m, "carriage", "slide", kMotor150, &kScrew, current_amp(2), emps_controller(),
                                MotionProfile({{0, 0}, {0.5, 0.1}, {2, 0.1}, {2.5, -0.05}}, Interpolation::Linear)));
    drives.push_back(make_drive(m, "pivot", "pivot", kKrs, nullptr, voltage_amp(), pid(30, 0, 0, 0, 0, 0),
                                MotionProfile({{0, 0.3}}, Interpolation::Step)));
    return drives;
}

// ---------------------------------------------------------------------------
// Reading the package back
// ---------------------------------------------------------------------------
struct Exported {
    mtest::Package package;
    msl::Model mechatronic;
    msl::Index index;  // MSL plus the package's own classes
    std::map<std::string, msl::Model> blocks;
};

Exported export_with(xtest::Translated& t, const std::string& name, std::vector<Drive> drives, double stop = 10) {
    ExportSettings s;
    s.model_name = name;
    s.stop_time = stop;
    s.drives = std::move(drives);
    Exported e{mtest::export_package(t, s), {}, mtest::msl_index(), {}};
    const OutputFile* f = e.package.file("Mechatronic.mo");
    REQUIRE_MESSAGE(f, "no Mechatronic.mo");
    e.mechatronic = msl::parse_model(f->contents);
    const std::string& pkg = e.package.name;
    e.index.add(pkg + ".Mechanics", msl::class_info(e.package.mechanics));
    for (const char* block : {"DiscreteDriveController", "SmoothTarget"}) {
        const OutputFile* b = e.package.file(std::string(block) + ".mo");
        REQUIRE_MESSAGE(b, "no " << block << ".mo");
        CHECK_FALSE(b->keep_existing);
        msl::Model model = msl::parse_model(b->contents);
        CHECK(model.within == pkg);
        CHECK(model.name == block);
        CHECK(model.kind == "block");
        e.index.add(pkg + "." + block, msl::class_info(model));
        e.blocks[block] = std::move(model);
    }
    return e;
}

void check_structure(const Exported& e) {
    for (const auto& [name_, block] : e.blocks) {
        const std::string& name = name_;  // (CAPTURE cannot capture a structured binding)
        CAPTURE(name);
        for (const std::string& err : msl::check_model(e.index, block)) FAIL_CHECK(err);
    }
    for (const std::string& err : msl::check_model(mtest::msl_index(), e.package.mechanics)) FAIL_CHECK(err);
    for (const std::string& err : msl::check_model(e.index, e.mechatronic)) FAIL_CHECK(err);
}

// Connection sets of a model's connects.
struct Graph {
    std::map<std::string, std::string> parent;
    std::map<std::string, std::vector<std::string>> members;

    explicit Graph(const msl::Model& m) {
        for (const auto& [a, b] : m.connects) parent[find(a)] = find(b);
        for (const auto& [ref, p] : parent) members[find(ref)].push_back(ref);
    }
    std::string find(const std::string& x) {
        auto it = parent.find(x);
        if (it == parent.end()) return parent[x] = x;
        if (it->second == x) return x;
        return parent[x] = find(it->second);
    }
    // The other connectors in `ref`'s set.
    std::vector<std::string> others(const std::string& ref) {
        std::vector<std::string> out;
        if (!parent.count(ref)) return out;
        for (const std::string& r : members[find(ref)])
            if (r != ref) out.push_back(r);
        return out;
    }
};

std::string component_of(const std::string& ref) { return ref.substr(0, ref.find('.')); }
std::string connector_of(const std::string& ref) {
    const size_t dot = ref.find('.');
    return dot == std::string::npos ? std::string() : ref.substr(dot + 1);
}

// The Mechanics flange wired to joint j's axis (axis_<joint>), "" when none.
std::string axis_flange(const Mechanism& m, const msl::Model& mechanics, int j) {
    for (const msl::Component& c : mechanics.components) {
        if (mtest::joint_of(m, c) != j) continue;
        for (const auto& [a, b] : mechanics.connects) {
            if (a == c.name + ".axis") return b;
            if (b == c.name + ".axis") return a;
        }
    }
    return {};
}

double number(const msl::Component& c, const std::string& modifier) {
    const std::string v = c.value(modifier);
    REQUIRE_MESSAGE(!v.empty(), c.name << " has no " << modifier);
    const double x = msl::parse_number(v);
    REQUIRE_MESSAGE(std::isfinite(x), c.name << "." << modifier << " = " << v);
    return x;
}

std::vector<std::vector<double>> matrix(const std::string& text) {
    std::vector<std::vector<double>> rows;
    REQUIRE(text.size() >= 2);
    REQUIRE(text.front() == '[');
    REQUIRE(text.back() == ']');
    std::string row;
    const auto flush = [&] {
        std::vector<double> r;
        size_t start = 0;
        while (start <= row.size()) {
            size_t end = row.find(',', start);
            if (end == std::string::npos) end = row.size();
            r.push_back(msl::parse_number(row.substr(start, end - start)));
            start = end + 1;
        }
        rows.push_back(r);
        row.clear();
    };
    for (char c : text.substr(1, text.size() - 2)) {
        if (c == ';') flush();
        else row += c;
    }
    flush();
    return rows;
}

bool close(double a, double b, double rel = 1e-9) { return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)); }

// A signal as a linear form over named inputs: the reference r, the joint
// position q and velocity qd, and integrals int{...} of other forms.
using Form = std::map<std::string, double>;

std::string form_text(const Form& f) {
    std::string s = "{";
    for (const auto& [k, v] : f)
        if (v != 0) s += k + ":" + std::to_string(v) + ",";
    return s + "}";
}

Form scaled(const Form& f, double k) {
    Form out;
    for (const auto& [key, v] : f) out[key] = v * k;
    return out;
}

Form sum(const Form& a, const Form& b) {
    Form out = a;
    for (const auto& [key, v] : b) out[key] += v;
    for (auto it = out.begin(); it != out.end();) it = it->second == 0 ? out.erase(it) : std::next(it);
    return out;
}

bool same_form(const Form& a, const Form& b) {
    std::set<std::string> keys;
    for (const auto& [k, v] : a) keys.insert(k);
    for (const auto& [k, v] : b) keys.insert(k);
    for (const std::string& k : keys) {
        const double x = a.count(k) ? a.at(k) : 0, y = b.count(k) ? b.at(k) : 0;
        if (!(x == y || close(x, y, 1e-12))) return false;
    }
    return true;
}

// What one drive's components read back as, found by tracing from the
// joint's flange (drive train), the EMF (circuit) and the source (controller).
struct DriveReadback {
    double reflected_inertia = 0;  // sum of J * (shaft rad per joint unit)^2
    double ratio = 1;              // motor shaft rad per joint unit
    double efficiency = 1;
    double k = 0, resistance = 0, inductance = 0;
    bool voltage = true;
    double amplifier_gain = 1;
    double output_limit = 0;
    double delay = 0;
    const msl::Component* controller = nullptr;  // discrete
    const msl::Component* target = nullptr;
    const msl::Component* position_sensor = nullptr;
    const msl::Component* speed_sensor = nullptr;
    Form law;  // continuous controller output before the limiter
    std::set<std::string> components;  // every component reached
};

class Tracer {
public:
    Tracer(const msl::Model& model, const std::string& package) : model_(model), graph_(model), package_(package) {}

    DriveReadback trace(const std::string& axis, bool linear) {
        DriveReadback r;
        axis_ = axis;
        // Drive train, from the joint towards the motor.
        std::string at = axis;
        double g = 1;  // rad at the current shaft per joint unit
        while (true) {
            std::vector<std::string> next;
            for (const std::string& o : graph_.others(at)) {
                const msl::Component* c = find(component_of(o));
                if (c && c->class_name.find(".Sensors.") != std::string::npos) {
                    if (at == axis) sensor(r, *c, o, linear);
                    continue;
                }
                next.push_back(o);
            }
            REQUIRE_MESSAGE(next.size() == 1, at << " leads to " << next.size() << " drive-train parts");
            const msl::Component* c = find(component_of(next[0]));
            REQUIRE(c);
            r.components.insert(c->name);
            const std::string port = connector_of(next[0]);
            const std::string& cls = c->class_name;
            if (cls == kRot + "Components.IdealGearR2T") {
                CHECK(linear);
                REQUIRE(port == "flangeT");
                g *= number(*c, "ratio");
                at = c->name + ".flangeR";
            } else if (cls == kRot + "Components.LossyGear") {
                REQUIRE(port == "flange_b");
                g *= number(*c, "ratio");
                const std::vector<std::vector<double>> table = matrix(c->value("lossTable"));
                REQUIRE(table.size() == 1);
                REQUIRE(table[0].size() == 5);
                CHECK(table[0][0] == 0);
                CHECK(table[0][1] == table[0][2]);  // the same efficiency both ways
                CHECK(table[0][3] == 0);
                CHECK(table[0][4] == 0);
                r.efficiency *= table[0][1];
                at = c->name + ".flange_a";
            } else if (cls == kRot + "Components.IdealGear") {
                REQUIRE(port == "flange_b");
                g *= number(*c, "ratio");
                at = c->name + ".flange_a";
            } else if (cls == kRot + "Components.Inertia") {
                REQUIRE(port == "flange_b");
                r.reflected_inertia += number(*c, "J") * g * g;
                at = c->name + ".flange_a";
            } else if (cls == kAnalog + "Basic.RotationalEMF") {
                REQUIRE(port == "flange");
                r.k = number(*c, "k");
                circuit(r, *c);
                break;
            } else {
                FAIL("unexpected drive-train part " << c->name << " (" << cls << ")");
            }
        }
        r.ratio = g;
        return r;
    }

    const msl::Component* find(const std::string& name) const { return model_.find(name); }

private:
    void sensor(DriveReadback& r, const msl::Component& c, const std::string& ref, bool linear) {
        r.components.insert(c.name);
        CHECK(connector_of(ref) == "flange");
        if (c.class_name == (linear ? kTrans + "Sensors.PositionSensor" : kRot + "Sensors.AngleSensor")) {
            CHECK_FALSE(r.position_sensor);
            r.position_sensor = &c;
        } else if (c.class_name == (linear ? kTrans + "Sensors.SpeedSensor" : kRot + "Sensors.SpeedSensor")) {
            CHECK_FALSE(r.speed_sensor);
            r.speed_sensor = &c;
        } else {
            FAIL("sensor " << c.name << " (" << c.class_name << ") on the " << (linear ? "prismatic" : "revolute")
                           << " joint's flange");
        }
    }

    // Armature circuit: emf.p back through inductor and resistor to the source.
    void circuit(DriveReadback& r, const msl::Component& emf) {
        std::string at = emf.name + ".p";
        const msl::Component* source = nullptr;
        std::string source_pin;
        while (!source) {
            const std::vector<std::string> o = graph_.others(at);
            REQUIRE_MESSAGE(o.size() == 1, at << " joins " << o.size() << " pins");
            const msl::Component* c = find(component_of(o[0]));
            REQUIRE(c);
            r.components.insert(c->name);
            if (c->class_name == kAnalog + "Basic.Inductor") {
                CHECK(connector_of(o[0]) == "n");
                r.inductance = number(*c, "L");
                at = c->name + ".p";
            } else if (c->class_name == kAnalog + "Basic.Resistor") {
                CHECK(connector_of(o[0]) == "n");
                r.resistance = number(*c, "R");
                at = c->name + ".p";
            } else {
                source = c;
                source_pin = connector_of(o[0]);
            }
        }
        // Positive u drives positive current into emf.p.
        if (source->class_name == kAnalog + "Sources.SignalVoltage") {
            r.voltage = true;
            CHECK(source_pin == "p");
        } else {
            REQUIRE(source->class_name == kAnalog + "Sources.SignalCurrent");
            r.voltage = false;
            CHECK(source_pin == "n");
        }
        // The return path: emf.n to the source's other pin, grounded.
        const std::string other = source->name + (source_pin == "p" ? ".n" : ".p");
        bool grounded = false, closed = false;
        for (const std::string& o : graph_.others(emf.name + ".n")) {
            closed = closed || o == other;
            const msl::Component* c = find(component_of(o));
            if (c && c->class_name == kAnalog + "Basic.Ground") {
                grounded = true;
                r.components.insert(c->name);
            }
        }
        CHECK(closed);
        CHECK(grounded);
        signal_chain(r, source->name + (r.voltage ? ".v" : ".i"));
    }

    // Signal outputs: blocks' y (y[i] of a table) and the sensors' readings.
    bool is_output(const std::string& ref) const {
        const std::string port = connector_of(ref);
        if (port == "y" || port.rfind("y[", 0) == 0) return true;
        const msl::Component* c = find(component_of(ref));
        return c && c->class_name.find(".Sensors.") != std::string::npos &&
               (port == "phi" || port == "w" || port == "s" || port == "v");
    }

    // The output driving an input.
    std::string source_of(const std::string& input) {
        std::vector<std::string> drivers;
        for (const std::string& o : graph_.others(input))
            if (is_output(o)) drivers.push_back(o);
        REQUIRE_MESSAGE(drivers.size() == 1, input << " has " << drivers.size() << " drivers");
        return drivers[0];
    }

    // From the amplifier input back to the controller.
    void signal_chain(DriveReadback& r, const std::string& input) {
        std::string at = source_of(input);
        if (!r.voltage) {
            // A current amplifier: its gain first.
            const msl::Component* c = find(component_of(at));
            REQUIRE(c);
            REQUIRE(c->class_name == kBlocks + "Math.Gain");
            r.components.insert(c->name);
            r.amplifier_gain = number(*c, "k");
            at = source_of(c->name + ".u");
        }
        while (true) {
            const msl::Component* c = find(component_of(at));
            REQUIRE(c);
            r.components.insert(c->name);
            const std::string& cls = c->class_name;
            if (cls == kBlocks + "Nonlinear.FixedDelay") {
                r.delay = number(*c, "delayTime");
                at = source_of(c->name + ".u");
            } else if (cls == kBlocks + "Nonlinear.Limiter") {
                r.output_limit = number(*c, "uMax");
                CHECK(number(*c, "uMin") == -r.output_limit);
                r.law = form(source_of(c->name + ".u"), r);
                return;
            } else if (cls == package_ + ".DiscreteDriveController") {
                r.controller = c;
                r.output_limit = number(*c, "uMax");
                r.delay = number(*c, "delaySamples") * number(*c, "Ts");
                r.target = find(component_of(source_of(c->name + ".q_ref")));
                const msl::Component* q = find(component_of(source_of(c->name + ".q")));
                const msl::Component* qd = find(component_of(source_of(c->name + ".qd")));
                CHECK(q == r.position_sensor);
                CHECK(qd == r.speed_sensor);
                if (r.target) r.components.insert(r.target->name);
                return;
            } else {
                FAIL("unexpected block " << c->name << " (" << cls << ") before the amplifier");
            }
        }
    }

    // The controller's output as a linear form of r, q, qd and integrals.
    Form form(const std::string& out, DriveReadback& r) {
        const msl::Component* c = find(component_of(out));
        REQUIRE(c);
        r.components.insert(c->name);
        const std::string& cls = c->class_name;
        if (c == r.position_sensor) return {{"q", 1}};
        if (c == r.speed_sensor) return {{"qd", 1}};
        if (cls == kBlocks + "Sources.CombiTimeTable" || cls == kBlocks + "Sources.Constant" ||
            cls == package_ + ".SmoothTarget") {
            CHECK((!r.target || r.target == c));
            r.target = c;
            return {{"r", 1}};
        }
        const auto in = [&](const char* port) { return form(source_of(c->name + "." + port), r); };
        if (cls == kBlocks + "Math.Feedback") return sum(in("u1"), scaled(in("u2"), -1));
        if (cls == kBlocks + "Math.Gain") return scaled(in("u"), number(*c, "k"));
        if (cls == kBlocks + "Math.Add") return sum(scaled(in("u1"), number(*c, "k1")), scaled(in("u2"), number(*c, "k2")));
        if (cls == kBlocks + "Math.Add3")
            return sum(sum(scaled(in("u1"), number(*c, "k1")), scaled(in("u2"), number(*c, "k2"))),
                       scaled(in("u3"), number(*c, "k3")));
        if (cls == kBlocks + "Continuous.Integrator") {
            CHECK_FALSE(c->modifier("y_start"));  // starts at 0
            return {{"int" + form_text(in("u")), number(*c, "k")}};
        }
        FAIL("unexpected block " << c->name << " (" << cls << ") in the controller");
        return {};
    }

    const msl::Model& model_;
    Graph graph_;
    std::string package_;
    std::string axis_;
};

// The law of ControllerSpec as a linear form (continuous time).
Form expected_law(const ControllerSpec& c) {
    const Form e{{"r", 1}, {"q", -1}};
    Form up = scaled(e, c.kp);
    if (c.ki > 0) up = sum(up, {{"int" + form_text(e), c.ki}});
    if (c.kd > 0) up = sum(up, {{"qd", -c.kd}});
    if (c.kv <= 0) return up;
    const Form ev = sum(up, {{"qd", -1}});
    Form u = scaled(ev, c.kv);
    if (c.kvi > 0) u = sum(u, {{"int" + form_text(ev), c.kvi}});
    return u;
}

void check_target(const msl::Component* target, const MotionProfile& motion, const std::string& package) {
    REQUIRE(target);
    CAPTURE(target->name);
    const std::vector<MotionPoint>& points = motion.points();
    if (points.empty()) {
        CHECK(target->class_name == kBlocks + "Sources.Constant");
        CHECK(number(*target, "k") == 0);
        return;
    }
    if (motion.interpolation() == Interpolation::Smooth) {
        CHECK(target->class_name == package + ".SmoothTarget");
    } else {
        CHECK(target->class_name == kBlocks + "Sources.CombiTimeTable");
        CHECK(target->value("smoothness") == kBlocks + (motion.interpolation() == Interpolation::Step
                                                            ? "Types.Smoothness.ConstantSegments"
                                                            : "Types.Smoothness.LinearSegments"));
        CHECK(target->value("extrapolation") == kBlocks + "Types.Extrapolation.HoldLastPoint");
    }
    const std::vector<std::vector<double>> table = matrix(target->value("table"));
    REQUIRE(table.size() == points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        REQUIRE(table[i].size() == 2);
        CHECK(table[i][0] == points[i].time);  // shortest round-trip text: exact
        CHECK(table[i][1] == points[i].value);
    }
}

// Every drive traced and compared with its Drive; the mechanics component
// connected to exactly the driven joints' axis flanges.
void check_drives(xtest::Translated& t, const Exported& e, const std::vector<Drive>& drives) {
    const Mechanism& m = *t.mechanism;
    Tracer tracer(e.mechatronic, e.package.name);
    const msl::Component* mechanics = e.mechatronic.find("mechanics");
    REQUIRE(mechanics);
    CHECK(mechanics->class_name == e.package.name + ".Mechanics");

    std::set<std::string> expected_flanges, used_flanges;
    std::set<std::string> reached;
    for (const Drive& d : drives) {
        CAPTURE(d.name);
        const std::string flange = axis_flange(m, e.package.mechanics, d.joint);
        REQUIRE_FALSE(flange.empty());
        expected_flanges.insert(flange);
        const DriveReadback r = tracer.trace("mechanics." + flange, d.linear);
        for (const std::string& c : r.components) {
            CHECK_MESSAGE(reached.insert(c).second, c << " is shared by two drives");
            // Descriptions name the drive.
            CHECK(tracer.find(c)->description.rfind("drive '" + d.name + "'", 0) == 0);
        }

        // The key consistency: inertia and effort limit at the joint.
        CHECK(close(r.reflected_inertia, d.armature));
        CHECK(close(r.ratio, d.ratio));
        CHECK(r.efficiency == d.efficiency);
        CHECK(r.k == d.motor.torque_constant);
        CHECK(r.resistance == d.armature_resistance);
        CHECK(r.voltage == (d.spec.amplifier.mode == AmplifierMode::Voltage));
        // The inductor is written in voltage mode when La > 0.
        CHECK(r.inductance == (r.voltage ? d.armature_inductance : 0.0));
        CHECK(r.output_limit == d.output_limit);
        const double max_current = r.voltage ? r.output_limit / r.resistance : r.amplifier_gain * r.output_limit;
        if (!r.voltage) CHECK(r.amplifier_gain == d.spec.amplifier.gain);
        CHECK(close(r.efficiency * r.ratio * r.k * max_current, d.effort_limit));
        CHECK(close(r.delay, d.spec.controller.delay, 1e-12));

        // Sensors on the joint side: position always, speed where the law needs it.
        const ControllerSpec& c = d.spec.controller;
        REQUIRE(r.position_sensor);
        CHECK(bool(r.speed_sensor) == (c.sample_period > 0 || c.kd > 0 || c.kv > 0));

        // The controller.
        if (c.sample_period > 0) {
            REQUIRE(r.controller);
            const msl::Component& k = *r.controller;
            CHECK(number(k, "kp") == c.kp);
            CHECK(number(k, "ki") == c.ki);
            CHECK(number(k, "kd") == c.kd);
            CHECK(number(k, "kv") == c.kv);
            CHECK(number(k, "kvi") == c.kvi);
            CHECK(number(k, "Ts") == c.sample_period);
            CHECK(k.value("delaySamples") == std::to_string(std::lround(c.delay / c.sample_period)));
            const int estimate = c.velocity_estimate == VelocityEstimate::Measured ? 0
                                 : c.velocity_estimate == VelocityEstimate::Difference ? 1 : 2;
            CHECK(k.value("velocityEstimate") == std::to_string(estimate));
        } else {
            CHECK_FALSE(r.controller);
            CHECK_MESSAGE(same_form(r.law, expected_law(c)),
                          "controller law " << form_text(r.law) << " instead of " << form_text(expected_law(c)));
        }
        check_target(r.target, d.spec.motion, e.package.name);
    }
    // Every component of Mechatronic belongs to a drive (or is mechanics).
    for (const msl::Component& c : e.mechatronic.components)
        if (c.name != "mechanics") CHECK_MESSAGE(reached.count(c.name), c.name << " belongs to no drive");
    for (const auto& [a, b] : e.mechatronic.connects)
        for (const std::string& ref : {a, b})
            if (component_of(ref) == "mechanics") used_flanges.insert(connector_of(ref));
    CHECK(used_flanges == expected_flanges);
}

double stop_time(const std::string& annotation) {
    const std::string key = "StopTime = ";
    const size_t at = annotation.find(key);
    REQUIRE(at != std::string::npos);
    const size_t end = annotation.find(',', at);
    return msl::parse_number(annotation.substr(at + key.size(), end - at - key.size()));
}

}  // namespace

TEST_CASE("modelica drives: revolute drives of every kind on the six-axis arm") {
    auto t = xtest::translate_builtin("six_axis_arm");
    const std::vector<Drive> drives = arm_drives(*t->mechanism);
    const Exported e = export_with(*t, "six_axis_arm", drives);
    const std::string& pkg = e.package.name;
    check_structure(e);
    check_drives(*t, e, drives);

    // Package files: the mechanical model is the one a passive export writes.
    ExportSettings passive;
    passive.model_name = "six_axis_arm";
    const mtest::Package without = mtest::export_package(*t, passive);
    CHECK(without.mechanics_text == e.package.mechanics_text);
    CHECK_FALSE(without.file("Mechatronic.mo"));
    CHECK(e.package.file("package.order")->contents ==
          "Mechanics\nDiscreteDriveController\nSmoothTarget\nMechatronic\nUserModel\n");
    CHECK_FALSE(e.package.file("Mechatronic.mo")->keep_existing);
    const msl::Model user = msl::parse_model(e.package.file("UserModel.mo")->contents);
    CHECK(user.errors.empty());
    CHECK(user.extends == std::vector<std::string>{pkg + ".Mechatronic"});
    CHECK(e.package.file("UserModel.mo")->keep_existing);

    // Mechatronic.mo: generated header, the experiment long enough for the
    // last motion point (12.5 s > the 10 s asked for).
    const std::string& text = e.package.file("Mechatronic.mo")->contents;
    CHECK(text.rfind("// Generated by mbx", 0) == 0);
    CHECK(e.mechatronic.within == pkg);
    CHECK(e.mechatronic.name == "Mechatronic");
    CHECK(stop_time(e.mechatronic.annotation) == 12.5);
    CHECK(stop_time(user.annotation) == 12.5);

    // Names: <drive>_<role>, the drive's name as an identifier.
    for (const char* name : {"waist_target", "waist_position", "waist_speed", "waist_error", "waist_error_integral",
                             "waist_position_law", "waist_velocity_error", "waist_velocity_error_integral",
                             "waist_velocity_law", "waist_limiter", "waist_delay", "waist_source", "waist_resistor",
                             "waist_inductor", "waist_emf", "waist_ground", "waist_rotor", "waist_motor_gear",
                             "waist_transmission_inertia", "waist_transmission", "shoulder_amplifier",
                             "wrist_pitch_target", "hand_controller"})
        CHECK_MESSAGE(e.mechatronic.find(name), "no component " << name);
    // The writer's own index of the components, for other consumers.
    {
        ExportSettings s;
        s.model_name = "six_axis_arm";
        s.drives = drives;
        ExportModel model = xtest::export_model(*t, s);
        std::vector<JointFlanges> flanges;
        write_mechanics(model, pkg, &flanges);
        const MechatronicModel written = write_mechatronic(model, pkg, flanges);
        CHECK(written.text == text);
        CHECK(written.uses_discrete_controller);
        CHECK(written.uses_smooth_target);
        CHECK(written.stop_time == 12.5);
        REQUIRE(written.drives.size() == drives.size());
        for (size_t i = 0; i < drives.size(); ++i) {
            const ModelicaDriveComponents& parts = written.drives[i];
            CHECK(parts.drive == int(i));
            CHECK(flanges[size_t(drives[i].joint)].axis == axis_flange(*t->mechanism, e.package.mechanics, drives[i].joint));
            for (const auto& [role, name] : parts.roles) {
                CHECK(name == parts.prefix + "_" + role);
                CHECK(e.mechatronic.find(name));
            }
            CHECK_FALSE(parts.component("target").empty());
            CHECK_FALSE(parts.component("emf").empty());
        }
        CHECK(written.drives[2].prefix == "wrist_pitch");
        CHECK(written.drives[3].component("controller") == "hand_controller");
        CHECK(written.drives[0].component("controller").empty());
    }
    CHECK_FALSE(e.mechatronic.find("hand_inductor"));  // La = 0
    // What MSL's continuous blocks do differently from mbx's controller is noted.
    bool noted = false;
    for (const Finding& f : e.package.notes)
        noted = noted || (f.code == MBX_FINDING_EXPORT_APPROXIMATION && f.severity == MBX_SEVERITY_INFO &&
                          f.message.find("Modelica: drive 'waist'") != std::string::npos &&
                          f.message.find("Integrator keeps integrating") != std::string::npos &&
                          f.message.find("FixedDelay") != std::string::npos);
    CHECK(noted);
    CHECK_FALSE(e.mechatronic.find("shoulder_inductor"));  // a current source imposes the current
}

TEST_CASE("modelica drives: a ball screw on a prismatic joint with the EMPS rig's sampled controller") {
    auto t = xtest::translate(linear_axis());
    const Mechanism& m = *t->mechanism;
    const std::vector<Drive> drives = axis_drives(m);
    REQUIRE(drives[0].linear);
    const Exported e = export_with(*t, "linear axis", drives, 2);
    check_structure(e);
    check_drives(*t, e, drives);
    CHECK(stop_time(e.mechatronic.annotation) == 2.5);

    // The drive train ends on the prismatic joint's translational flange.
    const msl::Component* screw = e.mechatronic.find("carriage_screw");
    REQUIRE(screw);
    CHECK(screw->class_name == "Modelica.Mechanics.Rotational.Components.IdealGearR2T");
    CHECK(msl::parse_number(screw->value("ratio")) == 2 * kPi / 0.005);
    const msl::Component* lossy = e.mechatronic.find("carriage_transmission");
    REQUIRE(lossy);
    CHECK(lossy->value("ratio") == "1");
    CHECK(lossy->value("lossTable") == "[0, 0.9, 0.9, 0, 0]");
    // Ball screw: J_rotor (2 pi / lead)^2 + J_screw (2 pi / lead)^2 at the carriage, in kg.
    const double n = 2 * kPi / 0.005;
    CHECK(close(drives[0].armature, (kMotor150.J + kScrew.J) * n * n));

    // The EMPS controller, as the sampled block's parameters.
    const msl::Component* k = e.mechatronic.find("carriage_controller");
    REQUIRE(k);
    CHECK(k->class_name == e.package.name + ".DiscreteDriveController");
    CHECK(k->value("kp") == "160.18");
    CHECK(k->value("kv") == "243.45");
    CHECK(k->value("Ts") == "0.001");
    CHECK(k->value("delaySamples") == "1");
    CHECK(k->value("uMax") == "10");
    CHECK(k->value("velocityEstimate") == "2");

    // The block implements drive.h's law: the filtered difference, the
    // whole-sample delay, the saturation and the loops, as written.
    const msl::Model& block = e.blocks.at("DiscreteDriveController");
    for (const char* line : {"when sample(0, Ts) then", "v := if started then (q - q_1) / Ts else 0;",
                             "qf := if started then 0.5 * q + 0.5 * q_1 else q;",
                             "v := if started then (qf - qf_1) / Ts else 0;", "dt := if started then Ts else 0;",
                             "e := q_ref - q;", "ie := integral_e + e * dt;", "up := kp * e + ki * ie - kd * v;",
                             "iv := integral_ev + ev * dt;", "u := if kv > 0 then kv * ev + kvi * iv else up;",
                             "if uMax > 0 and abs(u) > uMax then", "u := max(-uMax, min(uMax, u));",
                             "pending[1] := u;", "y := pending[delaySamples + 1];"})
        CHECK_MESSAGE(block.algorithm.find(line) != std::string::npos, "the controller's algorithm lacks: " << line);
    for (const char* input : {"q_ref", "q", "qd"}) {
        const msl::Component* c = block.find(input);
        REQUIRE(c);
        CHECK(c->class_name == "Modelica.Blocks.Interfaces.RealInput");
    }
    CHECK(block.find("y")->class_name == "Modelica.Blocks.Interfaces.RealOutput");
    CHECK(block.find("pending")->dimensions == "delaySamples + 1");
    const msl::Model& smooth = e.blocks.at("SmoothTarget");
    CHECK(smooth.extends == std::vector<std::string>{"Modelica.Blocks.Interfaces.SO"});
    CHECK(smooth.algorithm.find("y := table[k, 2] + (table[k + 1, 2] - table[k, 2]) * u^3 * (10 - 15 * u + 6 * u^2);") !=
          std::string::npos);
}

TEST_CASE("modelica drives: re-export is byte-identical and keeps the user's model") {
    mbx_test::TempDir dir("mbx_modelica_drives");
    auto t = xtest::translate(linear_axis());
    ExportSettings s;
    s.model_name = "linear axis";
    s.drives = axis_drives(*t->mechanism);
    const OutputFiles first = xtest::export_to(*t, dir, MBX_EXPORT_MODELICA, s);
    auto again = xtest::translate(linear_axis());
    ExportSettings s2 = s;
    s2.drives = axis_drives(*again->mechanism);
    const OutputFiles second = xtest::export_to(*again, dir, MBX_EXPORT_MODELICA, s2);
    REQUIRE(first.size() == second.size());
    for (size_t i = 0; i < first.size(); ++i) {
        CHECK(first[i].path == second[i].path);
        CHECK_MESSAGE(first[i].contents == second[i].contents, first[i].path << " differs between exports");
    }
    const OutputFile* user = xtest::find_file(first, "modelica/Linear_axis/UserModel.mo");
    REQUIRE(user);
    CHECK(user->contents.find("extends Linear_axis.Mechatronic;") != std::string::npos);
    // The user's model stays as it was.
    const std::string path = (dir.path / "modelica" / "Linear_axis" / "UserModel.mo").string();
    const std::string edited = mbx_test::read_file(path) + "// mine\n";
    std::ofstream(path, std::ios::binary) << edited;
    xtest::export_to(*t, dir, MBX_EXPORT_MODELICA, s);
    CHECK(mbx_test::read_file(path) == edited);
}

TEST_CASE("modelica drives: a drive on a joint without an axis flange is left out with a note") {
    // A planar slider-crank cut at its prismatic: the crank revolute carries
    // MSL's RevolutePlanarLoopConstraint and has no flange.
    mbx_memory::Assembly a;
    a.name = "slider crank";
    Builder b(a, "sc", kSI, kSI);
    const Vec3 A(0, 0, 0), B(0.05, 0.03, 0), C(0.2, 0, 0), z(0, 0, 1);
    box_body(b, "frame", "Frame", MBX_BODY_GROUND, Vec3(0.1, -0.05, 0), Vec3(0.3, 0.02, 0.02));
    box_body(b, "crank", "Crank", 0, A, Vec3(0.06, 0.01, 0.01));
    box_body(b, "rod", "Rod", 0, B, Vec3(0.16, 0.01, 0.01));
    box_body(b, "slider", "Slider", 0, C, Vec3(0.03, 0.02, 0.02));
    const Mat3 I = Mat3::Identity();
    b.joint("rev_A", "frame", "crank", A, I, {mbx_stub::build::revolute(z)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    b.joint("rev_B", "crank", "rod", B, I, {mbx_stub::build::revolute(z)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    b.joint("rev_C", "rod", "slider", C, I, {mbx_stub::build::revolute(z)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    Prim slide;
    slide.type = MBX_PRIMITIVE_PRISMATIC;
    slide.axis = Vec3(1, 0, 0);
    b.joint("slide", "frame", "slider", C, I, {slide}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    auto t = xtest::translate(std::move(a));
    const Mechanism& m = *t->mechanism;
    REQUIRE(m.loops.size() == 1);
    REQUIRE(m.joints[size_t(m.loops[0].cut_joint)].type == MBX_PRIMITIVE_PRISMATIC);

    // Which revolute lost its flange: the one Mechanics writes as the constraint.
    ExportSettings s;
    s.model_name = "slider crank";
    const mtest::Package passive = mtest::export_package(*t, s);
    std::string constrained, free;
    for (const Joint& j : m.joints) {
        if (j.type != MBX_PRIMITIVE_REVOLUTE) continue;
        const bool flange = !axis_flange(m, passive.mechanics, joint_named(m, j.name)).empty();
        (flange ? free : constrained) = j.name;
    }
    REQUIRE_FALSE(constrained.empty());
    REQUIRE_FALSE(free.empty());

    s.drives.push_back(make_drive(m, "stuck", constrained, kKrs, nullptr, voltage_amp(), pid(10, 0, 0, 0, 0, 0), {}));
    const mtest::Package only_stuck = mtest::export_package(*t, s);
    CHECK_FALSE(only_stuck.file("Mechatronic.mo"));
    CHECK(only_stuck.file("package.order")->contents == "Mechanics\nUserModel\n");
    bool noted = false;
    for (const Finding& f : only_stuck.notes)
        noted = noted || (f.code == MBX_FINDING_EXPORT_APPROXIMATION &&
                          f.message.find("drive 'stuck' is left out of Mechatronic.mo") != std::string::npos);
    CHECK(noted);

    // With a drive on a free revolute too, that one is written.
    s.drives.push_back(make_drive(m, "crank", free, kKrs, nullptr, voltage_amp(), pid(10, 0, 0, 0, 0, 0), {}));
    const Exported e = export_with(*t, "slider crank", s.drives);
    check_structure(e);
    check_drives(*t, e, {s.drives[1]});
    CHECK_FALSE(e.mechatronic.find("stuck_target"));
}

TEST_CASE("modelica checker: signal, block and algorithm flaws are reported") {
    const msl::Model block = msl::parse_model(
        "within P;\n"
        "block B \"b\"\n"
        "  parameter Real k = 1 \"gain\";\n"
        "  Modelica.Blocks.Interfaces.RealInput u;\n"
        "  Modelica.Blocks.Interfaces.RealOutput y(start = 0, fixed = true);\n"
        "protected\n"
        "  discrete Real x[2](each start = 0);\n"
        "algorithm\n"
        "  when sample(0, 1) then\n"
        "    for i in 1:2 loop\n"
        "      x[i] := k * u + undeclared;\n"
        "    end for;\n"
        "    if k > 0 then\n"
        "      y := x[1];\n"
        "    end if;\n"
        "  end when;\n"
        "end B;\n");
    CHECK(block.errors.empty());
    CHECK(block.kind == "block");
    REQUIRE(block.find("x"));
    CHECK(block.find("x")->is_protected);
    CHECK(block.find("x")->dimensions == "2");
    CHECK(block.find("k")->binding == "1");
    msl::Index index = mtest::msl_index();
    const std::vector<std::string> block_errors = msl::check_model(index, block);
    REQUIRE(block_errors.size() == 1);
    CHECK(block_errors[0] == "B: the algorithm uses undeclared undeclared");
    index.add("P.B", msl::class_info(block));
    CHECK(index.elements("P.B") == std::set<std::string>{"k", "u", "y"});  // protected x is not an element

    const msl::Model unbalanced = msl::parse_model(
        "block C\n  Real x;\nalgorithm\n  when time > 1 then\n    x := 1;\n  end if;\nend C;\n");
    CHECK_FALSE(unbalanced.errors.empty());

    const msl::Model model = msl::parse_model(
        "within P;\n"
        "model M\n"
        "  Modelica.Blocks.Sources.Constant c1(k = 1);\n"
        "  Modelica.Blocks.Sources.Constant c2(k = 2);\n"
        "  Modelica.Blocks.Math.Feedback f;\n"
        "  Modelica.Blocks.Math.Gain g(k = 2);\n"
        "  Modelica.Blocks.Sources.CombiTimeTable table(table = [0, 0; 1, 1], smoothness = "
        "Modelica.Blocks.Types.Smoothness.LinearSegments);\n"
        "  P.B b;\n"
        "  Modelica.Mechanics.Rotational.Components.Inertia inertia(J = 1);\n"
        "equation\n"
        "  connect(c1.y, f.u1);\n"
        "  connect(c2.y, f.u1);\n"        // two sources
        "  connect(table.y[1], b.u);\n"
        "  connect(b.y, inertia.flange_a);\n"  // a signal on a flange
        "end M;\n");
    CHECK(model.errors.empty());
    const std::vector<std::string> errors = msl::check_model(index, model);
    std::string all;
    for (const std::string& err : errors) all += err + "\n";
    CAPTURE(all);
    CHECK(all.find("have 2 sources") != std::string::npos);
    CHECK(all.find("input f.u2 is not connected") != std::string::npos);
    CHECK(all.find("input g.u is not connected") != std::string::npos);
    CHECK(all.find("connect(b.y, inertia.flange_a) joins different connector kinds") != std::string::npos);
    CHECK(all.find("table") == std::string::npos);  // CombiTimeTable (mis-filed in the index) is known
}
}  // namespace MBX_UNITY_ID
