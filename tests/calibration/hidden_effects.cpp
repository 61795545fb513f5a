// The hidden-effect generator (hidden_effects.h). Causes and how each is made:
//
// | cause                     | where     | how                                                         | main magnitude     |
// |---------------------------|-----------|-------------------------------------------------------------|--------------------|
// | viscous_friction          | MuJoCo    | dof_damping = damping                                       | damping            |
// | coulomb_friction          | MuJoCo    | dof_frictionloss = coulomb (stiff friction constraint)      | coulomb            |
// | armature                  | MuJoCo    | dof_armature = armature                                     | armature           |
// | mass_error                | MuJoCo    | body_mass and body_inertia times (1 + relative change)      | relative change    |
// | mass_error (com_shift)    | MuJoCo    | body_ipos moved along a direction (mbx body frame)          | shift (m)          |
// | mass_error (inertia_error)| MuJoCo    | moments across a direction + value * largest moment         | relative change    |
// | effort_offset             | generator | applied = commanded + offset; recorded = commanded          | offset             |
// | actuator_gain             | generator | applied = gain * commanded                                  | gain               |
// | delay                     | generator | applied = commanded from `delay` s earlier (whole steps)    | delay              |
// | sensor_offset             | generator | recorded and controlled q = true q + offset                 | offset             |
// | asymmetric_friction       | generator | -(c tanh(v/vs) + dc |tanh(v/vs)|): c+ = c + dc, c- = c - dc | c; dc/c in [.4,.8] |
// | stribeck_friction         | generator | -fs tanh(v/vs) exp(-(v/vst)^2), vst 20 % of the RMS speed   | fs                 |
// | position_dependent_effort | generator | -k q (q from the CAD pose)                                  | k                  |
// | compliance                | MJCF edit | motor body (armature Jm) + hinge/slide with stiffness, damping | link resonance (Hz) |
// | backlash                  | MJCF edit | motor body (armature Jm) + hinge/slide limited to +-b/2     | width b            |
//
// Compliance and backlash are generated alone: the joint's MJCF body gets a
// motor-side body in front of it that holds the driven (and measured) joint;
// the link hangs from it by the elastic or dead-band joint. Jm is 0.2-0.5 of
// the link's inertia at the CAD pose, the compliance's damping ratio 0.05-0.15.
//
// The smooth sign's vs is 1 % of the reference's RMS speed, raised where
// needed so the explicit force stays stable at the step (h c / (vs J) < 0.25).
#include "hidden_effects.h"

#include <mujoco/mujoco.h>
#include <pugixml.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>

#include "apps/stub_host/assemblies/builder.h"
#include "export/common/export_model.h"
#include "export/common/names.h"
#include "export/export_files.h"
#include "export/mjcf/mjcf_layout.h"
#include "calibration/records/experiment.h"
#include "calibration/records/records.h"
#include "host_adapters/urdf/urdf_adapter.h"
#include "sim/build_model.h"
#include "sim/simulation.h"
#include "apps/stub_host/assemblies/stub_assembly.h"

namespace mbx_test {

namespace fs = std::filesystem;

double HiddenEffect::parameter(const std::string& name) const {
    for (const auto& p : parameters)
        if (p.first == name) return p.second;
    throw std::runtime_error("hidden effect " + cause + " has no parameter " + name);
}

std::vector<std::string> generated_causes() {
    return {"viscous_friction", "coulomb_friction", "armature",          "mass_error",
            "effort_offset",    "actuator_gain",    "delay",             "sensor_offset",
            "asymmetric_friction", "stribeck_friction", "position_dependent_effort", "compliance", "backlash",
            "com_shift", "inertia_error"};
}

mbx_memory::Assembly two_link_arm_assembly() {
    using namespace mbx_stub::build;
    mbx_memory::Assembly a;
    a.name = "two_link_arm";
    a.source = "mbx hidden-effect generator: two-link arm (m, kg)";
    const mbx_units si{1, 1, 1};
    Builder b(a, "two_link_arm", si, si);
    const Mat3 I = Mat3::Identity();
    const Vec3 shoulder(0, 0, 1.0), elbow(0, 0, 0.70), tip(0, 0, 0.45);
    b.body("ground", "Ground", MBX_BODY_GROUND, 5.0, I, Vec3::Zero(), Vec3(0, 0, 0.5), box_inertia(5.0, 0.1, 0.1, 1.0));
    b.body("upper", "Upper arm", 0, 2.0, I, shoulder, (shoulder + elbow) / 2, box_inertia(2.0, 0.04, 0.04, 0.30));
    b.body("forearm", "Forearm", 0, 1.0, I, elbow, (elbow + tip) / 2, box_inertia(1.0, 0.03, 0.03, 0.25));
    b.joint("shoulder", "ground", "upper", shoulder, I, {revolute(Vec3::UnitY())}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    b.joint("elbow", "upper", "forearm", elbow, I, {revolute(Vec3::UnitY())}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    b.mesh("upper", box_mesh("bar", Vec3(0.04, 0.04, 0.30), I, Vec3(0, 0, -0.15)));
    b.mesh("forearm", box_mesh("bar", Vec3(0.03, 0.03, 0.25), I, Vec3(0, 0, -0.125)));
    return a;
}

mbx_memory::Assembly yaw_arm_assembly() {
    using namespace mbx_stub::build;
    mbx_memory::Assembly a;
    a.name = "yaw_arm";
    a.source = "mbx hidden-effect generator: yaw-pitch-pitch arm (m, kg)";
    const mbx_units si{1, 1, 1};
    Builder b(a, "yaw_arm", si, si);
    const Mat3 I = Mat3::Identity();
    const Vec3 yaw(0, 0, 1.1), shoulder(0.1, 0, 1.0), elbow(0.1, 0, 0.70), tip(0.1, 0, 0.45);
    b.body("ground", "Ground", MBX_BODY_GROUND, 5.0, I, Vec3::Zero(), Vec3(0, 0, 0.5), box_inertia(5.0, 0.1, 0.1, 1.0));
    b.body("turntable", "Turntable", 0, 1.0, I, yaw, Vec3(0.05, 0, 1.05), box_inertia(1.0, 0.2, 0.05, 0.1));
    b.body("upper", "Upper arm", 0, 2.0, I, shoulder, (shoulder + elbow) / 2, box_inertia(2.0, 0.04, 0.04, 0.30));
    b.body("forearm", "Forearm", 0, 1.0, I, elbow, (elbow + tip) / 2, box_inertia(1.0, 0.03, 0.03, 0.25));
    b.joint("yaw", "ground", "turntable", yaw, I, {revolute(Vec3::UnitZ())}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    b.joint("shoulder", "turntable", "upper", shoulder, I, {revolute(Vec3::UnitY())}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    b.joint("elbow", "upper", "forearm", elbow, I, {revolute(Vec3::UnitY())}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    b.mesh("turntable", box_mesh("plate", Vec3(0.2, 0.05, 0.1), I, Vec3(0.05, 0, -0.05)));
    b.mesh("upper", box_mesh("bar", Vec3(0.04, 0.04, 0.30), I, Vec3(0, 0, -0.15)));
    b.mesh("forearm", box_mesh("bar", Vec3(0.03, 0.03, 0.25), I, Vec3(0, 0, -0.125)));
    return a;
}

namespace {

constexpr double kStep = 0.5e-3;      // MuJoCo's step (s)
constexpr int kStepsPerSample = 2;    // records at 1 kHz
constexpr double kTwoPi = 6.283185307179586;

struct MechanismInfo {
    std::string input_kind, input, shapes;
    std::vector<std::string> actuated;  // constraint ids
    std::vector<double> amplitude;      // reference peak per actuated joint (rad, m)
};

MechanismInfo mechanism_info(const std::string& name) {
    const std::string samples = MBX_SAMPLES_DIR;
    if (name == "emps_axis")
        return {"file", samples + "/emps_axis/emps_axis.xml", samples + "/emps_axis/emps_axis_a.wrl", {"40:-:41"}, {0.04}};
    if (name == "two_link_arm")
        return {"test_assembly", "two_link_arm", "", {"two_link_arm/shoulder", "two_link_arm/elbow"}, {0.8, 1.0}};
    if (name == "yaw_arm")
        return {"test_assembly", "yaw_arm", "", {"yaw_arm/yaw", "yaw_arm/shoulder", "yaw_arm/elbow"}, {1.2, 0.8, 1.0}};
    if (name == "fourbar") return {"builtin", "fourbar", "", {"fourbar/rev_A"}, {0.3}};
    if (name == "dfki_acrobot")
        return {"urdf", std::string(MBX_SHARED_DATA) + "/measured/dfki_double_pendulum_c0/identified_model_3.1_acrobot.urdf",
                "", {"Joint1", "Joint2"}, {0.8, 1.0}};
    throw std::runtime_error("hidden effects: unknown mechanism '" + name +
                             "' (emps_axis, two_link_arm, yaw_arm, fourbar, dfki_acrobot)");
}

struct MjDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
    void operator()(mjData* d) const { mj_deleteData(d); }
};

// Gaussian draws from mt19937_64's bits (its sequence is fixed by the
// standard; std::normal_distribution's is not), so files repeat across libraries.
struct Rng {
    std::mt19937_64 engine;
    explicit Rng(uint64_t seed) : engine(seed) {}
    double uniform() { return double(engine() >> 11) * (1.0 / 9007199254740992.0); }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    double normal() {
        double u = uniform();
        while (u <= 0) u = uniform();
        return std::sqrt(-2 * std::log(u)) * std::cos(kTwoPi * uniform());
    }
};

// A multi-sine with 1/f amplitudes (flat speed spectrum, acceleration
// growing with frequency) scaled to a peak, faded in over the first 0.5 s so
// that it starts at rest. With holds, every kPeriod it fades out and rests
// at 0 for kHold: standstill data tells a constant offset from friction that
// differs with the direction of motion (asymmetric Coulomb), which sliding
// data alone cannot.
struct MultiSine {
    std::vector<double> f, c, phase;
    double scale = 1;
    double start = 0;  // the measured position at t = 0
    bool holds = false;
    static constexpr double kFade = 0.5, kPeriod = 2.7, kHold = 0.4, kHoldFade = 0.3;

    // A cosine step from 0 (x <= 0) to 1 (x >= 1) and its slope.
    static void step(double x, double& w, double& wd) {
        if (x <= 0 || x >= 1) {
            w = x <= 0 ? 0 : 1, wd = 0;
            return;
        }
        w = 0.5 * (1 - std::cos(M_PI * x));
        wd = 0.5 * M_PI * std::sin(M_PI * x);
    }
    void envelope(double t, double& e, double& ed) const {
        double w, wd;
        step(t / kFade, w, wd);
        e = w, ed = wd / kFade;
        if (!holds) return;
        const double tau = std::fmod(t, kPeriod);
        const double out_start = kPeriod - kHold - 2 * kHoldFade, in_start = kPeriod - kHoldFade;
        double h = 1, hd = 0;
        if (tau >= out_start && tau < in_start - kHold) {
            step((tau - out_start) / kHoldFade, w, wd);
            h = 1 - w, hd = -wd / kHoldFade;
        } else if (tau >= in_start - kHold && tau < in_start) {
            h = 0;
        } else if (tau >= in_start) {
            step((tau - in_start) / kHoldFade, w, wd);
            h = w, hd = wd / kHoldFade;
        }
        ed = ed * h + e * hd;
        e *= h;
    }
    void value(double t, double& r, double& rd) const {
        double s = 0, sd = 0;
        for (size_t k = 0; k < f.size(); ++k) {
            const double w = kTwoPi * f[k];
            s += c[k] * std::sin(w * t + phase[k]);
            sd += c[k] * w * std::cos(w * t + phase[k]);
        }
        double e, ed;
        envelope(t, e, ed);
        r = scale * e * s;
        rd = scale * (ed * s + e * sd);
        // From the measured start (a sensor offset): no step in the first command.
        double w, wd;
        step(t / kFade, w, wd);
        r += (1 - w) * start;
        rd -= wd / kFade * start;
    }
};

MultiSine make_multisine(Rng& rng, double f_lo, double f_hi, int n, double peak, double duration, bool holds) {
    MultiSine m;
    m.holds = holds;
    for (int k = 0; k < n; ++k) {
        const double f = f_lo * std::pow(f_hi / f_lo, double(k) / (n - 1)) * rng.uniform(0.92, 1.08);
        m.f.push_back(f);
        m.c.push_back(1 / f);
        m.phase.push_back(rng.uniform(0, kTwoPi));
    }
    double top = 0;
    for (double t = 0; t <= duration; t += 1e-3) {
        double r, rd;
        m.value(t, r, rd);
        top = std::max(top, std::fabs(r));
    }
    m.scale = peak / top;
    return m;
}

double rms_speed(const MultiSine& m, double duration) {
    double s = 0;
    int n = 0;
    for (double t = 0; t <= duration; t += 1e-3, ++n) {
        double r, rd;
        m.value(t, r, rd);
        s += rd * rd;
    }
    return std::sqrt(s / std::max(n, 1));
}

// The effect on one actuated joint applied by the generator.
struct JointEffects {
    double offset = 0, gain = 1, sensor_offset = 0, stiffness = 0;
    int delay_steps = 0;
    double coulomb = 0, asymmetry = 0;   // asymmetric friction
    double stribeck = 0, stribeck_v = 1; // Stribeck
    double vs = 1;                       // smooth sign's velocity
    double spot = 0, spot_from = 0;      // Coulomb friction beyond a position (a tight spot)
    double force(double q, double v) const {
        double f = -stiffness * q;
        const double s = std::tanh(v / vs);
        f -= coulomb * s + asymmetry * std::fabs(s);
        // (smoothed over a hundredth of a radian or metre at its edge)
        if (spot != 0) f -= spot * s * 0.5 * (1 + std::tanh((q - spot_from) / 0.01));
        if (stribeck != 0) f -= stribeck * s * std::exp(-(v / stribeck_v) * (v / stribeck_v));
        return f;
    }
};

std::string fmt(const char* f, double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, x);
    return buf;
}

std::string json_escape(const std::string& s) {
    std::string r;
    for (char ch : s) {
        if (ch == '"' || ch == '\\') r += '\\';
        r += ch;
    }
    return r;
}

std::string xml_escape(const std::string& s) {
    std::string r;
    for (char ch : s) {
        switch (ch) {
        case '&': r += "&amp;"; break;
        case '<': r += "&lt;"; break;
        case '>': r += "&gt;"; break;
        case '"': r += "&quot;"; break;
        default: r += ch;
        }
    }
    return r;
}

// A CSV column stem from a report name: no separators, quotes or blanks.
std::string column_stem(const std::string& name) {
    std::string r;
    for (char ch : name) r += ch == ',' || ch == '"' || static_cast<unsigned char>(ch) <= ' ' ? '_' : ch;
    return r.empty() ? "joint" : r;
}

std::string effect_json(const HiddenEffect& e) {
    std::ostringstream o;
    o << "{\"cause\": \"" << json_escape(e.cause) << "\"";
    if (!e.joint_id.empty())
        o << ", \"joint_id\": \"" << json_escape(e.joint_id) << "\", \"joint_name\": \"" << json_escape(e.joint_name) << "\"";
    if (!e.body_id.empty())
        o << ", \"body_id\": \"" << json_escape(e.body_id) << "\", \"body_name\": \"" << json_escape(e.body_name) << "\"";
    o << ", \"parameters\": {";
    for (size_t k = 0; k < e.parameters.size(); ++k)
        o << (k ? ", " : "") << "\"" << json_escape(e.parameters[k].first) << "\": " << fmt("%.10g", e.parameters[k].second);
    o << "}}";
    return o.str();
}

std::string case_json(const GeneratedCase& c, const CaseSpec& spec) {
    std::ostringstream o;
    o << "{\"name\": \"" << json_escape(c.name) << "\", \"mechanism\": \"" << c.mechanism << "\", \"input_kind\": \""
      << c.input_kind << "\", \"input\": \"" << json_escape(c.input) << "\", \"shapes\": \"" << json_escape(c.shapes)
      << "\", \"seed\": " << spec.seed << ", \"noise_fraction\": " << spec.noise_fraction << ", \"rests\": " << (spec.holds ? "true" : "false") << ", \"hidden\": [";
    for (size_t k = 0; k < c.hidden.size(); ++k) o << (k ? ", " : "") << effect_json(c.hidden[k]);
    o << "]}";
    return o.str();
}

void write_text(const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
    if (!f) throw std::runtime_error("hidden effects: cannot write " + p.string());
}

// A transmission between an actuated joint and its link, put into the MJCF.
struct Transmission {
    size_t actuated = 0;
    std::string joint;  // the MJCF joint (keeps its name on the motor side)
    bool linear = false;
    double motor_inertia = 0;
    double stiffness = 0, damping = 0;  // compliance
    double width = 0;                   // backlash: the dead band's full width
};

std::string number_text(double x) { return fmt("%.12g", x); }

// The MJCF with each transmission's joint moved onto a new motor-side body
// (the body's pose, a negligible mass, the motor's inertia as the joint's
// armature) and the link hung from it by a joint on the same axis: a spring
// and damper (compliance) or a free dead band between stiff limits (backlash).
void write_transmissions(const std::string& in, const std::string& out, const std::vector<Transmission>& trs) {
    pugi::xml_document doc;
    if (!doc.load_file(in.c_str())) throw std::runtime_error("hidden effects: cannot read " + in);
    for (const Transmission& tr : trs) {
        pugi::xml_node joint = doc.find_node([&](pugi::xml_node n) {
            return std::string(n.name()) == "joint" && tr.joint == n.attribute("name").value();
        });
        if (!joint) throw std::runtime_error("hidden effects: no MJCF joint " + tr.joint);
        pugi::xml_node link = joint.parent();
        pugi::xml_node motor = link.parent().insert_child_before("body", link);
        motor.append_attribute("name") = (std::string(link.attribute("name").value()) + "_motor").c_str();
        for (const char* a : {"pos", "quat"})
            if (pugi::xml_attribute x = link.attribute(a)) {
                motor.append_attribute(a) = x.value();
                link.remove_attribute(x);
            }
        pugi::xml_node drive = motor.append_copy(joint);
        drive.append_attribute("armature") = number_text(tr.motor_inertia).c_str();
        pugi::xml_node inertial = motor.append_child("inertial");
        inertial.append_attribute("pos") = "0 0 0";
        inertial.append_attribute("mass") = "1e-9";
        inertial.append_attribute("diaginertia") = "1e-12 1e-12 1e-12";
        motor.append_move(link);
        joint.attribute("name") = (tr.joint + "_transmission").c_str();
        if (tr.width > 0) {
            joint.append_attribute("limited") = "true";
            joint.append_attribute("range") = (number_text(-tr.width / 2) + " " + number_text(tr.width / 2)).c_str();
            // Stiff stops: MuJoCo's clamp (two steps) is the stiffest it allows.
            joint.append_attribute("solreflimit") = number_text(2 * kStep).append(" 1").c_str();
            joint.append_attribute("solimplimit") = "0.99 0.99 0.001";
        } else {
            joint.append_attribute("stiffness") = number_text(tr.stiffness).c_str();
            joint.append_attribute("damping") = number_text(tr.damping).c_str();
        }
    }
    if (!doc.save_file(out.c_str(), "  ")) throw std::runtime_error("hidden effects: cannot write " + out);
}

}  // namespace

std::unique_ptr<xtest::Translated> open_mechanism(const std::string& mechanism) {
    const MechanismInfo info = mechanism_info(mechanism);
    if (info.input_kind == "file") {
        mbx_files::FileAdapterOptions o;
        o.shapes_path = info.shapes;
        return xtest::translate_file(info.input, o);
    }
    if (info.input_kind == "test_assembly")
        return xtest::translate(info.input == "yaw_arm" ? yaw_arm_assembly() : two_link_arm_assembly());
    if (info.input_kind == "urdf") {
        std::shared_ptr<mbx_files::UrdfAdapter> adapter = mbx_files::UrdfAdapter::open(info.input);
        return xtest::translate_table(adapter->table(), adapter);
    }
    mbx_memory::Assembly a;
    if (!mbx_stub::builtin_assembly(info.input, a)) throw std::runtime_error("no built-in " + info.input);
    return xtest::translate(std::move(a));
}

GeneratedCase generate_case(const CaseSpec& spec, const std::string& out_dir, std::vector<TrueMotion>* motion) {
    const MechanismInfo info = mechanism_info(spec.mechanism);
    if (spec.name.empty()) throw std::runtime_error("hidden effects: a case needs a name");
    if (spec.fit_seconds < 1 || spec.validation_seconds < 1)
        throw std::runtime_error("hidden effects: records shorter than 1 s");
    const fs::path dir(out_dir);
    fs::create_directories(dir);

    // mbx's translation and MJCF export, loaded by MuJoCo.
    std::unique_ptr<xtest::Translated> t = open_mechanism(spec.mechanism);
    const mbx::sim::Model model = mbx::sim::build_model(*t->mechanism);
    mbx::ExportSettings settings;
    settings.model_name = spec.mechanism;
    mbx::MjcfLayout layout;
    {
        mbx::ExportModel em = xtest::export_model(*t, settings);
        layout = mbx::build_mjcf_layout(em);
        mbx::write_output_files(dir.string(), mbx::export_files(em, MBX_EXPORT_MJCF));
    }
    const std::string mjcf = (dir / "mjcf" / (mbx::sanitize_identifier(settings.model_name, "model") + ".xml")).string();
    std::unique_ptr<mjModel, MjDeleter> mm;
    std::unique_ptr<mjData, MjDeleter> md;
    mjModel* m = nullptr;
    mjData* d = nullptr;
    // `limits`: a dead band (backlash) is a joint limit; the export's CAD limits stay off.
    auto load = [&](const std::string& path, bool limits) {
        char error[1024] = "";
        mm.reset(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
        if (!mm) throw std::runtime_error("hidden effects: MuJoCo refused " + path + ": " + error);
        md.reset(mj_makeData(mm.get()));
        m = mm.get();
        d = md.get();
        m->opt.timestep = kStep;
        m->opt.integrator = mjINT_RK4;
        m->opt.disableflags |= mjDSBL_CONTACT;
        if (!limits) m->opt.disableflags |= mjDSBL_LIMIT;
        for (int k = 0; k < 3; ++k) m->opt.gravity[k] = model.gravity[k];
        // Loops: the stiffest equalities MuJoCo's clamp allows (2-step time
        // constant, impedance near 1), so the closure drift stays far below the noise.
        for (int e = 0; e < m->neq; ++e) {
            m->eq_solref[mjNREF * e] = 2 * kStep;
            m->eq_solref[mjNREF * e + 1] = 1;
            m->eq_solimp[mjNIMP * e] = 0.9999;
            m->eq_solimp[mjNIMP * e + 1] = 0.9999;
        }
    };
    load(mjcf, false);

    // Coordinate maps: every 1-dof sim joint to its MuJoCo joint.
    std::vector<int> qpos_of_v(size_t(model.nv), -1), dof_of_v(size_t(model.nv), -1);
    std::map<int, std::string> mj_joint_of;  // sim joint -> MJCF joint name
    auto map_coordinates = [&] {
    for (const auto& j : model.joints) {
        if (j.kind == mbx::sim::JointKind::Fixed) continue;
        if (j.nv() != 1) throw std::runtime_error("hidden effects: only hinge and slide joints are supported");
        for (const mbx::MjcfBody& b : layout.bodies)
            for (const mbx::MjcfJoint& mjj : b.joints)
                if (mjj.joint == j.source) {
                    const int id = mj_name2id(m, mjOBJ_JOINT, mjj.name.c_str());
                    if (id < 0) throw std::runtime_error("hidden effects: no MuJoCo joint " + mjj.name);
                    qpos_of_v[size_t(j.v_index)] = m->jnt_qposadr[id];
                    dof_of_v[size_t(j.v_index)] = m->jnt_dofadr[id];
                    mj_joint_of[int(&j - &model.joints[0])] = mjj.name;
                }
    }
    for (int k = 0; k < model.nv; ++k)
        if (dof_of_v[size_t(k)] < 0) throw std::runtime_error("hidden effects: a coordinate has no MuJoCo joint");
    };
    map_coordinates();

    GeneratedCase out;
    out.name = spec.name;
    out.mechanism = spec.mechanism;
    out.input_kind = info.input_kind;
    out.input = info.input;
    out.shapes = info.shapes;
    const size_t na = info.actuated.size();
    std::vector<int> act_joint(na), act_v(na), act_dof(na);
    std::vector<bool> linear(na);
    for (size_t i = 0; i < na; ++i) {
        const int j = mbx::sim::find_joint(model, info.actuated[i]);
        if (j < 0) throw std::runtime_error("hidden effects: no joint " + info.actuated[i]);
        act_joint[i] = j;
        act_v[i] = model.joints[size_t(j)].v_index;
        act_dof[i] = dof_of_v[size_t(act_v[i])];
        linear[i] = model.joints[size_t(j)].kind == mbx::sim::JointKind::Prismatic;
        out.joint_ids.push_back(model.joints[size_t(j)].constraint_id);
        out.joint_names.push_back(model.joints[size_t(j)].name);
    }

    // Controller gains from the clean model's inertia at the assembly pose:
    // a 6 Hz critically-ish damped PD (the reference reaches 3 Hz).
    mj_setConst(m, d);
    std::vector<double> kp(na), kd(na);
    for (size_t i = 0; i < na; ++i) {
        const double J = m->dof_M0[act_dof[i]];
        const double w = kTwoPi * 6;
        kp[i] = J * w * w;
        kd[i] = 2 * 0.8 * J * w;
    }
    out.controller_kp = kp, out.controller_kd = kd;

    Rng rng(0x9e3779b97f4a7c15ULL ^ (uint64_t(spec.seed) * 0x100000001b3ULL));
    // Excitation (drawn first so a case's motion does not depend on its effects' draws).
    std::vector<MultiSine> fit_ref(na), val_ref(na);
    std::vector<double> speed(na);
    for (size_t i = 0; i < na; ++i) {
        fit_ref[i] = make_multisine(rng, 0.2, 3.0, 7, info.amplitude[i], spec.fit_seconds, spec.holds);
        val_ref[i] = make_multisine(rng, 0.3, 2.5, 6, 0.85 * info.amplitude[i], spec.validation_seconds, spec.holds);
        speed[i] = rms_speed(fit_ref[i], spec.fit_seconds);
    }

    // Effects.
    std::vector<JointEffects> je(na);
    std::vector<Transmission> transmissions;  // compliance, backlash: edits of the MJCF
    for (size_t i = 0; i < na; ++i) je[i].vs = 0.01 * speed[i];
    for (const EffectSpec& e : spec.effects) {
        if (!(e.high >= e.low)) throw std::runtime_error("hidden effects: empty range for " + e.cause);
        const double value = rng.uniform(e.low, e.high);
        HiddenEffect h;
        h.cause = e.cause;
        if (e.cause == "mounting_tilt") {
            // The floor out of level: MuJoCo's gravity turned by `value` rad
            // about the world axis the subject names ("x" or "y").
            if (e.subject != "x" && e.subject != "y")
                throw std::runtime_error("hidden effects: mounting_tilt's subject is the axis, x or y");
            const Eigen::Vector3d axis = e.subject == "x" ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
            const Eigen::Vector3d g = Eigen::AngleAxisd(value, axis) * Eigen::Vector3d(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
            for (int k = 0; k < 3; ++k) m->opt.gravity[k] = g[k];
            h.parameters = {{"tilt_" + e.subject, value}};
            out.hidden.push_back(h);
            continue;
        }
        if (e.cause == "mass_error" || e.cause == "com_shift" || e.cause == "inertia_error") {
            int sb = -1;
            for (size_t b = 1; b < model.bodies.size(); ++b)
                if (model.bodies[b].id == e.subject || model.bodies[b].name == e.subject) sb = int(b);
            if (sb < 0) throw std::runtime_error("hidden effects: no body '" + e.subject + "' in " + spec.mechanism);
            const int src = model.bodies[size_t(sb)].source;
            const int k = layout.of_body[size_t(src)];
            const int mb = k < 0 ? -1 : mj_name2id(m, mjOBJ_BODY, layout.bodies[size_t(k)].name.c_str());
            if (mb < 0) throw std::runtime_error("hidden effects: body '" + e.subject + "' has no MuJoCo body");
            h.cause = "mass_error";
            h.body_id = model.bodies[size_t(sb)].id;
            h.body_name = model.bodies[size_t(sb)].name;
            if (e.cause == "mass_error") {
                if (value <= -1) throw std::runtime_error("hidden effects: a mass cannot vanish");
                const double nominal = m->body_mass[mb];
                m->body_mass[mb] *= 1 + value;
                for (int r = 0; r < 3; ++r) m->body_inertia[3 * mb + r] *= 1 + value;
                h.parameters = {{"relative_mass_change", value}, {"mass", m->body_mass[mb]}, {"nominal_mass", nominal}};
                out.hidden.push_back(h);
                continue;
            }
            // Vectors in mbx's body frame (the truth's) to MuJoCo's body
            // frame: the two frames' world rotations at the assembly pose.
            const Eigen::Vector3d direction = e.direction.normalized();
            if (!direction.allFinite()) throw std::runtime_error("hidden effects: " + e.cause + " needs a direction");
            mbx::sim::Data sd(model);
            sd.q = model.q_reference;
            mbx::sim::update_kinematics(model, sd);
            mj_resetData(m, d);
            for (int v = 0; v < model.nv; ++v)
                d->qpos[qpos_of_v[size_t(v)]] = model.q_reference[model.joints[size_t(model.dof_joint[size_t(v)])].q_index];
            mj_kinematics(m, d);
            Eigen::Matrix3d mj_world;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) mj_world(r, c) = d->xmat[9 * mb + 3 * r + c];
            const Eigen::Matrix3d to_mj = mj_world.transpose() * sd.x_world[size_t(sb)].R;
            if (e.cause == "com_shift") {
                // The centre of mass moves `value` m along `direction`; the inertia about it stays.
                const Eigen::Vector3d shift = value * direction, in_mj = to_mj * shift;
                for (int r = 0; r < 3; ++r) m->body_ipos[3 * mb + r] += in_mj[r];
                h.parameters = {{"com_shift", value}, {"com_shift_x", shift[0]}, {"com_shift_y", shift[1]},
                                {"com_shift_z", shift[2]}};
            } else {
                // Material spread along `direction` (heavier ends, same mass
                // and centre): the moments about the axes across it grow by
                // `value` times the body's largest moment about its centre.
                Eigen::Matrix3d principal;
                const Eigen::Quaterniond iq(m->body_iquat[4 * mb], m->body_iquat[4 * mb + 1], m->body_iquat[4 * mb + 2],
                                            m->body_iquat[4 * mb + 3]);
                const Eigen::Matrix3d Ri = iq.toRotationMatrix();
                const Eigen::Vector3d moments(m->body_inertia[3 * mb], m->body_inertia[3 * mb + 1], m->body_inertia[3 * mb + 2]);
                principal = Ri * moments.asDiagonal() * Ri.transpose();
                const double delta = value * moments.maxCoeff();
                const Eigen::Matrix3d change = delta * (Eigen::Matrix3d::Identity() - direction * direction.transpose());
                const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(principal + to_mj * change * to_mj.transpose());
                Eigen::Matrix3d axes = eig.eigenvectors();
                if (axes.determinant() < 0) axes.col(2) *= -1;
                const Eigen::Quaterniond q(axes);
                m->body_iquat[4 * mb] = q.w(), m->body_iquat[4 * mb + 1] = q.x();
                m->body_iquat[4 * mb + 2] = q.y(), m->body_iquat[4 * mb + 3] = q.z();
                for (int r = 0; r < 3; ++r) m->body_inertia[3 * mb + r] = eig.eigenvalues()[r];
                h.parameters = {{"relative_inertia_change", value},
                                {"inertia_change_xx", change(0, 0)}, {"inertia_change_yy", change(1, 1)},
                                {"inertia_change_zz", change(2, 2)}, {"inertia_change_xy", change(0, 1)},
                                {"inertia_change_xz", change(0, 2)}, {"inertia_change_yz", change(1, 2)}};
            }
            out.hidden.push_back(h);
            continue;
        }
        const int j = mbx::sim::find_joint(model, e.subject);
        size_t i = na;
        for (size_t a = 0; a < na; ++a)
            if (act_joint[a] == j) i = a;
        if (j < 0 || i == na)
            throw std::runtime_error("hidden effects: '" + e.subject + "' is no actuated joint of " + spec.mechanism);
        h.joint_id = model.joints[size_t(j)].constraint_id;
        h.joint_name = model.joints[size_t(j)].name;
        const int dof = act_dof[i];
        JointEffects& x = je[i];
        const double J = m->dof_M0[dof];
        auto smooth_velocity = [&](double c) { x.vs = std::max(x.vs, 4 * kStep * c / J); };
        if (e.cause == "viscous_friction") {
            m->dof_damping[dof] = value;
            h.parameters = {{"damping", value}};
        } else if (e.cause == "coulomb_friction") {
            m->dof_frictionloss[dof] = value;
            // A stiff friction constraint: sliding friction within a few steps of a reversal.
            m->dof_solref[mjNREF * dof] = 2 * kStep;
            m->dof_solref[mjNREF * dof + 1] = 1;
            m->dof_solimp[mjNIMP * dof] = 0.99;
            m->dof_solimp[mjNIMP * dof + 1] = 0.99;
            h.parameters = {{"coulomb", value}};
        } else if (e.cause == "armature") {
            m->dof_armature[dof] = value;
            h.parameters = {{"armature", value}};
        } else if (e.cause == "effort_offset") {
            x.offset = value;
            h.parameters = {{"offset", value}};
        } else if (e.cause == "actuator_gain") {
            x.gain = value;
            h.parameters = {{"gain", value}};
        } else if (e.cause == "delay") {
            x.delay_steps = std::max(1, int(std::lround(value / kStep)));
            h.parameters = {{"delay", x.delay_steps * kStep}};
        } else if (e.cause == "sensor_offset") {
            x.sensor_offset = value;
            h.parameters = {{"offset", value}};
        } else if (e.cause == "asymmetric_friction") {
            const double ratio = rng.uniform(0.4, 0.8);
            x.coulomb = value;
            x.asymmetry = ratio * value;
            smooth_velocity(value + x.asymmetry);
            h.parameters = {{"coulomb", value},
                            {"coulomb_asymmetry", x.asymmetry},
                            {"coulomb_positive", value + x.asymmetry},
                            {"coulomb_negative", value - x.asymmetry},
                            {"smoothing_velocity", x.vs}};
        } else if (e.cause == "tight_spot") {
            // Outside the catalogue: Coulomb friction only beyond 40 % of
            // the reference's reach on the positive side.
            x.spot = value, x.spot_from = 0.4 * info.amplitude[i];
            smooth_velocity(value);
            h.parameters = {{"coulomb", value}, {"from", x.spot_from}};
        } else if (e.cause == "stribeck_friction") {
            x.stribeck = value;
            x.stribeck_v = 0.2 * speed[i];
            smooth_velocity(value);
            h.parameters = {{"stribeck", value}, {"stribeck_velocity", x.stribeck_v}, {"smoothing_velocity", x.vs}};
        } else if (e.cause == "position_dependent_effort") {
            x.stiffness = value;
            h.parameters = {{"stiffness", value}};
        } else if (e.cause == "compliance") {
            // `value` is the link's resonance on the spring (Hz) with the motor held.
            Transmission tr;
            tr.actuated = i, tr.joint = mj_joint_of.at(j), tr.linear = linear[i];
            tr.motor_inertia = rng.uniform(0.2, 0.5) * J;
            tr.stiffness = J * std::pow(kTwoPi * value, 2);
            const double reduced = J * tr.motor_inertia / (J + tr.motor_inertia);
            tr.damping = 2 * rng.uniform(0.05, 0.15) * std::sqrt(tr.stiffness * reduced);
            transmissions.push_back(tr);
            h.parameters = {{"stiffness", tr.stiffness}, {"damping", tr.damping}, {"motor_inertia", tr.motor_inertia},
                            {"link_frequency", value}};
        } else if (e.cause == "backlash") {
            Transmission tr;
            tr.actuated = i, tr.joint = mj_joint_of.at(j), tr.linear = linear[i];
            tr.motor_inertia = rng.uniform(0.2, 0.5) * J;
            tr.width = value;
            transmissions.push_back(tr);
            h.parameters = {{"width", value}, {"motor_inertia", tr.motor_inertia}};
        } else {
            throw std::runtime_error("hidden effects: unknown cause '" + e.cause + "'");
        }
        out.hidden.push_back(h);
    }
    if (!transmissions.empty()) {
        // A new body between the joint and its link: the motor side, driven
        // and read by the encoder, then the spring or the dead band to the link.
        if (spec.effects.size() != 1)
            throw std::runtime_error("hidden effects: compliance and backlash are generated alone");
        const std::string edited = (dir / "mjcf" / "with_transmission.xml").string();
        write_transmissions(mjcf, edited, transmissions);
        bool dead_band = false;
        for (const Transmission& tr : transmissions) dead_band = dead_band || tr.width > 0;
        load(edited, dead_band);
        map_coordinates();
        for (size_t i = 0; i < na; ++i) act_dof[i] = dof_of_v[size_t(act_v[i])];
    }
    mj_setConst(m, d);
    for (size_t i = 0; i < na; ++i) fit_ref[i].start = val_ref[i].start = je[i].sensor_offset;

    // The two records.
    const double q_step[2] = {kTwoPi / 40000, 1e-6};  // encoder counts: revolute, prismatic
    std::vector<std::string> stems;
    for (size_t i = 0; i < na; ++i) stems.push_back(column_stem(out.joint_names[i]));
    out.column_stems = stems;
    if (motion) motion->clear();
    for (int rec = 0; rec < 2; ++rec) {
        const std::vector<MultiSine>& ref = rec == 0 ? fit_ref : val_ref;
        const double duration = rec == 0 ? spec.fit_seconds : spec.validation_seconds;
        mj_resetData(m, d);
        mj_forward(m, d);
        const int steps = int(std::lround(duration / kStep));
        const int samples = steps / kStepsPerSample + 1;
        TrueMotion tm;
        tm.q.resize(samples, model.nv), tm.v.resize(samples, model.nv), tm.a.resize(samples, model.nv);
        tm.commanded.resize(samples, Eigen::Index(na)), tm.applied.resize(samples, Eigen::Index(na));
        tm.generator_force.resize(samples, Eigen::Index(na));
        tm.actuated_dof = act_v;
        std::vector<std::vector<double>> history(na);
        std::vector<double> u(na), applied(na), extra(na);
        int sample = 0;
        for (int s = 0; s <= steps; ++s) {
            const double time = s * kStep;
            for (size_t i = 0; i < na; ++i) {
                const double q = d->qpos[m->jnt_qposadr[m->dof_jntid[act_dof[i]]]], v = d->qvel[act_dof[i]];
                double r, rd;
                if (rec == 0 && spec.fit_reference) spec.fit_reference(i, time, r, rd);
                else if (rec == 1 && spec.validation_reference) spec.validation_reference(i, time, r, rd);
                else ref[i].value(time, r, rd);
                u[i] = kp[i] * (r - (q + je[i].sensor_offset)) + kd[i] * (rd - v);
                history[i].push_back(u[i]);
                const int back = int(history[i].size()) - 1 - je[i].delay_steps;
                const double delayed = back >= 0 ? history[i][size_t(back)] : 0;
                const double before = back >= 1 ? history[i][size_t(back - 1)] : 0;
                // The effort is held over the step; its value at mid-step
                // (extrapolated) keeps the hold from delaying it by h/2,
                // which the calibration would rightly name as a delay.
                applied[i] = je[i].gain * (1.5 * delayed - 0.5 * before) + je[i].offset;
                extra[i] = je[i].force(q, v);
            }
            mju_zero(d->qfrc_applied, m->nv);
            for (size_t i = 0; i < na; ++i) d->qfrc_applied[act_dof[i]] = applied[i] + extra[i];
            if (s % kStepsPerSample == 0 && sample < samples) {
                mj_forward(m, d);
                tm.t.push_back(time);
                for (int k = 0; k < model.nv; ++k) {
                    tm.q(sample, k) = d->qpos[qpos_of_v[size_t(k)]];
                    tm.v(sample, k) = d->qvel[dof_of_v[size_t(k)]];
                    tm.a(sample, k) = d->qacc[dof_of_v[size_t(k)]];
                }
                for (size_t i = 0; i < na; ++i) {
                    tm.commanded(sample, Eigen::Index(i)) = u[i];
                    tm.applied(sample, Eigen::Index(i)) = applied[i];
                    tm.generator_force(sample, Eigen::Index(i)) = extra[i];
                }
                ++sample;
            }
            if (s < steps) mj_step(m, d);
            for (int k = 0; k < m->nq; ++k)
                if (!std::isfinite(d->qpos[k]))
                    throw std::runtime_error("hidden effects: MuJoCo diverged in case " + spec.name);
        }
        for (int w = 0; w < mjNWARNING; ++w)
            if (d->warning[w].number > 0)
                throw std::runtime_error("hidden effects: MuJoCo warned (" + std::to_string(w) + ") in case " + spec.name);

        // Noise (white, a fraction of each joint's effort RMS) and quantisation.
        std::vector<double> sigma(na);
        for (size_t i = 0; i < na; ++i)
            sigma[i] = i < spec.noise_sigma.size()
                           ? spec.noise_sigma[i]
                           : spec.noise_fraction * std::sqrt(tm.commanded.col(Eigen::Index(i)).squaredNorm() / samples);
        tm.effort_noise_sigma_first = sigma[0];
        std::string csv = "t";
        for (size_t i = 0; i < na; ++i) csv += "," + stems[i] + ".q," + stems[i] + ".effort";
        csv += "\n";
        for (int k = 0; k < samples; ++k) {
            csv += fmt("%.4f", tm.t[size_t(k)]);
            for (size_t i = 0; i < na; ++i) {
                const double dq = q_step[linear[i] ? 1 : 0];
                const double q = tm.q(k, act_v[i]) + je[i].sensor_offset;
                csv += "," + fmt("%.10g", std::round(q / dq) * dq);
                csv += "," + fmt("%.9g", tm.commanded(k, Eigen::Index(i)) + sigma[i] * rng.normal());
            }
            csv += "\n";
        }
        const std::string file = rec == 0 ? "fit.csv" : "validation.csv";
        write_text(dir / file, csv);
        (rec == 0 ? out.fit_csv : out.validation_csv) = (dir / file).string();
        if (motion) motion->push_back(std::move(tm));
    }

    // The experiment file (docs/calibration.md).
    std::ostringstream x;
    x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<!-- Generated by tests/calibration/hidden_effects.cpp: case " << xml_escape(spec.name) << ", mechanism "
      << spec.mechanism << ", seed " << spec.seed << ". MuJoCo on mbx's MJCF export; truth in truth.json. -->\n"
      << "<experiment version=\"1\">\n"
      << "  <record file=\"fit.csv\" role=\"fit\"/>\n"
      << "  <record file=\"validation.csv\" role=\"validation\"/>\n"
      << "  <time column=\"t\" unit=\"s\"/>\n";
    for (size_t i = 0; i < na; ++i) {
        const std::string id = xml_escape(out.joint_ids[i]);
        x << "  <column name=\"" << stems[i] << ".q\" joint=\"" << id << "\" quantity=\"position\" unit=\""
          << (linear[i] ? "m" : "rad") << "\"/>\n"
          << "  <column name=\"" << stems[i] << ".effort\" joint=\"" << id << "\" quantity=\"effort\" unit=\""
          << (linear[i] ? "N" : "N*m") << "\"/>\n";
    }
    x << "  <drive mode=\"effort\"/>\n";
    for (size_t i = 0; i < na; ++i)
        x << "  <compare joint=\"" << xml_escape(out.joint_ids[i]) << "\" quantity=\"effort\"/>\n";
    x << "</experiment>\n";
    out.experiment_path = (dir / "experiment.xml").string();
    write_text(out.experiment_path, x.str());
    write_text(dir / "truth.json", case_json(out, spec) + "\n");
    return out;
}

std::vector<CaseSpec> hidden_effect_suite(unsigned seed) {
    // Magnitude ranges per mechanism, sized against the clean fit records
    // (effort RMS: emps_axis 4.8 N; arm shoulder 2.9 N m, elbow 0.65 N m;
    // fourbar crank 2.2e-4 N m; speed RMS 0.053 m/s, 1.0 rad/s, 0.38 rad/s)
    // so that each effect is roughly 5-60 % of the effort RMS, several times
    // the 1.5 % noise.
    struct Row {
        const char* mechanism;
        std::vector<EffectSpec> effects;
        bool holds = false;
    };
    const std::string S = "two_link_arm/shoulder", E = "two_link_arm/elbow", P = "40:-:41", A = "fourbar/rev_A";
    // No armature, actuator gain or mass error on emps_axis: its effort is
    // the carriage's mass times acceleration alone, so the three are one
    // and the same scaling of it (no data can tell them apart).
    const std::vector<Row> rows = {
        // emps_axis: the 9.42 kg carriage on a horizontal slide (no drive).
        {"emps_axis", {{"viscous_friction", P, 20, 60}}},
        {"emps_axis", {{"coulomb_friction", P, 1, 3}}},
        {"emps_axis", {{"effort_offset", P, 0.8, 2}}, true},
        {"emps_axis", {{"asymmetric_friction", P, 1, 3}}, true},
        {"emps_axis", {{"stribeck_friction", P, 1.5, 3}}},
        {"emps_axis", {{"delay", P, 0.004, 0.012}}},
        {"emps_axis", {{"position_dependent_effort", P, 60, 200}}},
        // two-link arm hanging under gravity.
        {"two_link_arm", {{"viscous_friction", S, 0.3, 1.0}}},
        {"two_link_arm", {{"viscous_friction", E, 0.1, 0.4}}},
        {"two_link_arm", {{"coulomb_friction", S, 0.3, 1.0}}},
        {"two_link_arm", {{"coulomb_friction", E, 0.08, 0.25}}},
        {"two_link_arm", {{"armature", S, 0.03, 0.1}}},
        {"two_link_arm", {{"armature", E, 0.01, 0.04}}},
        {"two_link_arm", {{"mass_error", "two_link_arm/upper", 0.2, 0.5}}},
        {"two_link_arm", {{"mass_error", "two_link_arm/forearm", -0.4, -0.15}}},
        {"two_link_arm", {{"effort_offset", S, 0.3, 1.0}}},
        {"two_link_arm", {{"effort_offset", E, -0.25, -0.08}}, true},
        {"two_link_arm", {{"actuator_gain", S, 0.7, 0.9}}},
        {"two_link_arm", {{"actuator_gain", E, 0.7, 0.9}}},
        {"two_link_arm", {{"sensor_offset", S, 0.03, 0.08}}},
        {"two_link_arm", {{"sensor_offset", E, -0.1, -0.05}}},
        {"two_link_arm", {{"asymmetric_friction", S, 0.3, 0.8}}, true},
        {"two_link_arm", {{"stribeck_friction", E, 0.1, 0.3}}},
        {"two_link_arm", {{"delay", S, 0.004, 0.012}}},
        {"two_link_arm", {{"delay", E, 0.004, 0.012}}},
        {"two_link_arm", {{"position_dependent_effort", E, 0.5, 1.5}}},
        // fourbar: crank driven, loop closed by MuJoCo's equality; efforts ~2e-4 N m.
        {"fourbar", {{"viscous_friction", A, 1.2e-4, 3.5e-4}}},
        {"fourbar", {{"coulomb_friction", A, 3e-5, 1e-4}}},
        {"fourbar", {{"armature", A, 1e-5, 3e-5}}},
        {"fourbar", {{"effort_offset", A, 3e-5, 1e-4}}},
        {"fourbar", {{"actuator_gain", A, 0.7, 0.9}}},
        {"fourbar", {{"asymmetric_friction", A, 3e-5, 8e-5}}, true},
        {"fourbar", {{"mass_error", "fourbar/coupler", 0.3, 0.6}}},
        // clean, with and without rests
        {"emps_axis", {}},
        {"emps_axis", {}, true},
        {"two_link_arm", {}},
        {"two_link_arm", {}, true},
        {"fourbar", {}},
        {"fourbar", {}, true},
        // two at once
        {"emps_axis", {{"viscous_friction", P, 20, 60}, {"coulomb_friction", P, 1, 3}}},
        {"two_link_arm", {{"coulomb_friction", S, 0.3, 1.0}, {"mass_error", "two_link_arm/forearm", 0.2, 0.5}}},
        {"fourbar", {{"viscous_friction", A, 1.2e-4, 3.5e-4}, {"effort_offset", A, 3e-5, 1e-4}}},
        // Transmissions (MJCF edits), appended so the cases above keep their seeds;
        // magnitudes are the link's resonance in Hz: within the 25 Hz the
        // records resolve, above the 3 Hz the reference reaches.
        {"emps_axis", {{"compliance", P, 8, 20}}},
        {"two_link_arm", {{"compliance", S, 6, 14}}},
        {"two_link_arm", {{"compliance", E, 8, 16}}},
        // Dead bands (widths in rad), appended likewise.
        {"two_link_arm", {{"backlash", S, 0.01, 0.03}}},
        {"two_link_arm", {{"backlash", E, 0.01, 0.03}}},
        // A body's centre of mass and inertia (named mass_error), appended
        // likewise: across and along the forearm (x, z in its frame; the
        // joints turn about y), across the upper arm; the forearm's
        // material spread along it. (The upper arm's moment about the
        // shoulder axis is the shoulder's armature to any record.)
        {"two_link_arm", {{"com_shift", "two_link_arm/forearm", 0.02, 0.05, Eigen::Vector3d::UnitX()}}},
        {"two_link_arm", {{"com_shift", "two_link_arm/forearm", 0.03, 0.06, Eigen::Vector3d::UnitZ()}}},
        {"two_link_arm", {{"com_shift", "two_link_arm/upper", -0.05, -0.02, Eigen::Vector3d::UnitX()}}},
        {"two_link_arm", {{"inertia_error", "two_link_arm/forearm", 0.4, 0.9, Eigen::Vector3d::UnitZ()}}},
    };
    std::vector<CaseSpec> specs;
    std::map<std::string, int> used;
    for (size_t k = 0; k < rows.size(); ++k) {
        CaseSpec c;
        c.mechanism = rows[k].mechanism;
        c.effects = rows[k].effects;
        c.holds = rows[k].holds;
        std::string name = c.mechanism;
        if (c.effects.empty()) name += "_clean";
        if (c.holds) name += "_rests";
        for (const EffectSpec& e : c.effects) {
            std::string subject = e.subject;
            const size_t slash = subject.rfind('/');
            if (slash != std::string::npos) subject = subject.substr(slash + 1);
            name += "_" + e.cause + "_" + mbx::sanitize_identifier(subject, "joint");
        }
        const int n = used[name]++;
        if (n) name += "_" + std::to_string(n + 1);
        c.name = name;
        c.seed = seed * 1009u + unsigned(k) * 7919u + 1u;
        specs.push_back(c);
    }
    return specs;
}

std::vector<GeneratedCase> generate_suite(const std::vector<CaseSpec>& specs, const std::string& out_dir) {
    std::vector<GeneratedCase> cases;
    std::string json = "[\n";
    for (size_t k = 0; k < specs.size(); ++k) {
        cases.push_back(generate_case(specs[k], (fs::path(out_dir) / specs[k].name).string()));
        json += "  " + case_json(cases.back(), specs[k]) + (k + 1 < specs.size() ? ",\n" : "\n");
    }
    json += "]\n";
    write_text(fs::path(out_dir) / "truth.json", json);
    return cases;
}

mbx::calibration::Identification identify_case(const mbx::sim::Model& m, const std::string& experiment_path,
                                               mbx::calibration::IdentifyOptions options) {
    using namespace mbx::calibration;
    const std::vector<Record> records = load_records(load_experiment(experiment_path), m);
    std::vector<const Record*> fit_records, validation_records;
    for (const Record& r : records) (r.role == Role::Fit ? fit_records : validation_records).push_back(&r);
    const RegressionRows fit = regression_rows(m, fit_records, options);
    const RegressionRows validation = regression_rows(m, validation_records, options, &fit.weight);
    options.noise_level = noise_floor(m, validation, validation_records);
    return identify(m, fit, validation, options);
}

}  // namespace mbx_test
