#include "calibration/simulation/contact_stage.h"

#include <pugixml.hpp>

#include <algorithm>
#include <cmath>

#include "calibration/records/body_quantities.h"
#include "calibration/calibrate.h"
#include "calibration/simulation/replay.h"
#include "core/finding.h"
#include "core/heartbeat.h"
#include "core/mechatronics/contact_description.h"
#include "core/report/json_writer.h"

namespace mbx::calibration {

namespace sc = sim::contact;

namespace {

[[noreturn]] void fail(const std::string& file, int line, const std::string& what) {
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"), file + ":" + std::to_string(line) + ": " + what, file,
                line);
}

// The explicit Euler step of the rollouts: the cube tosses score within
// 0.1 %-point of 0.1 ms rollouts at 0.25 ms (tests/contact/cube_tosses.h).
constexpr double kContactStep = 2.5e-4;

// The body's size, for position errors in % of it: the largest extent of
// its shapes (0.1 m when it has none the estimate can use).
double body_size(const std::vector<sc::Shape>& shapes, int body) {
    double size = 0;
    for (const sc::Shape& s : shapes) {
        if (s.body != body) continue;
        switch (s.kind) {
        case sc::ShapeKind::Sphere: size = std::max(size, 2 * s.radius); break;
        case sc::ShapeKind::Box: size = std::max(size, s.size.maxCoeff()); break;
        case sc::ShapeKind::Cylinder:
        case sc::ShapeKind::Capsule: size = std::max(size, std::max(2 * s.radius, s.length + 2 * s.radius)); break;
        default: break;
        }
    }
    return size > 0 ? size : 0.1;
}

// The model after a contact step: the start with the step's parameters
// (every named cause's, refitted jointly).
ContactModel model_after(const ContactModel& start, const ContactStep& step) {
    ContactModel m = start;
    for (const FittedValue& v : step.parameters) {
        if (v.name == "stiffness") m.settings.normal.stiffness = v.value;
        else if (v.name == "damping") m.settings.normal.damping = v.value;
        else if (v.name == "mu_static") m.settings.friction.mu_static = v.value;
        else if (v.name == "mu_kinetic") m.settings.friction.mu_kinetic = v.value;
        else if (v.name == "ground_offset") m.ground_offset = v.value;
    }
    return m;
}

// Simulated compared signals of one record from its rollout.
std::vector<std::vector<double>> rolled_signals(const Record& r, const Rollout& roll,
                                                const std::vector<ComparedSignal>& compared) {
    std::vector<std::vector<double>> out(compared.size(), std::vector<double>(r.t.size(), NAN));
    for (size_t k = 0; k < r.t.size() && k < roll.positions.size(); ++k) {
        const Eigen::Quaterniond& q = roll.orientations[k];
        for (size_t c = 0; c < compared.size(); ++c) {
            const ComparedSignal& cs = compared[c];
            if (cs.quantity == Quantity::Position) {
                out[c][k] = (roll.positions[k] + q * cs.point)[cs.component];
                continue;
            }
            // The sign that agrees with the measured components, as the replays take it.
            const double comp[4] = {q.w(), q.x(), q.y(), q.z()};
            double agree = 0;
            for (const BodySignal& s : r.body_signals)
                if (s.quantity == Quantity::Orientation && s.body == cs.body) agree += s.values[k] * comp[s.component];
            out[c][k] = agree < 0 ? -comp[cs.component] : comp[cs.component];
        }
    }
    return out;
}

void score_step(const Experiment& e, const std::vector<Record>& records, const std::vector<ComparedSignal>& compared,
                const std::vector<std::vector<std::vector<double>>>& sim, StepErrors& step) {
    double err[2] = {0, 0}, ref[2] = {0, 0};
    for (size_t r = 0; r < records.size(); ++r) {
        for (size_t c = 0; c < compared.size(); ++c) {
            const ComparedSignal& cs = compared[c];
            const std::vector<double>& meas = *measured_values(records[r], cs);
            const std::vector<double> reference = error_reference(e, records[r], cs, meas);
            double ee = 0, nn = 0;
            size_t count = 0;
            for (size_t k = 0; k < meas.size(); ++k) {
                if (!std::isfinite(sim[r][c][k]) || !in_window(cs, records[r], k)) continue;
                ee += (meas[k] - sim[r][c][k]) * (meas[k] - sim[r][c][k]);
                nn += reference[k] * reference[k];
                ++count;
            }
            SignalError se;
            se.record = int(r), se.role = records[r].role, se.quantity = cs.quantity, se.weight = cs.weight;
            se.body = cs.body, se.component = cs.component, se.point = cs.point;
            se.relative = nn > 0 ? 100 * std::sqrt(ee / nn) : 0;
            se.rms = count ? std::sqrt(ee / double(count)) : 0;
            step.simulated.push_back(se);
            const int role = records[r].role == Role::Fit ? 0 : 1;
            err[role] += cs.weight * ee, ref[role] += cs.weight * nn;
        }
    }
    step.simulated_fit = ref[0] > 0 ? 100 * std::sqrt(err[0] / ref[0]) : 0;
    step.simulated_validation = ref[1] > 0 ? 100 * std::sqrt(err[1] / ref[1]) : 0;
}

std::string number(double v) {
    std::string s;
    append_json_number(s, v);
    return s;
}

void set_number(pugi::xml_node n, const char* name, double v) {
    if (!n.attribute(name)) n.append_attribute(name);
    n.attribute(name).set_value(number(v).c_str());
}

}  // namespace

bool contact_experiment(const Experiment& e, const sim::Model& m, const std::vector<Record>& records,
                        const ContactInput& contact) {
    if (e.mode != DriveMode::Free || records.empty()) return false;
    std::vector<int> common = measured_free_bodies(m, records[0]);
    for (const Record& r : records) {
        const std::vector<int> here = measured_free_bodies(m, r);
        common.erase(std::remove_if(common.begin(), common.end(),
                                    [&](int b) { return std::find(here.begin(), here.end(), b) == here.end(); }),
                     common.end());
    }
    if (common.empty()) return false;
    if (contact.empty())
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"),
                    e.path + ": the records measure free body '" + m.bodies[size_t(common[0])].name +
                        "' driven freely, which calibrates its contact, but the model has no collision shapes "
                        "(describe <collision> and <contact> in the description file)");
    return true;
}

void run_contact_stage(const sim::Model& m, const Experiment& e, const std::vector<Record>& records,
                       const ContactInput& contact, const CalibrateOptions& options, CalibrationResult& out) {
    ContactStageResult& cs = out.contact;
    cs.ran = true;
    std::vector<int> free_bodies = measured_free_bodies(m, records[0]);
    cs.body = free_bodies.front();
    for (int b : free_bodies)
        if (std::all_of(records.begin(), records.end(), [&](const Record& r) {
                const std::vector<int> here = measured_free_bodies(m, r);
                return std::find(here.begin(), here.end(), b) != here.end();
            })) {
            cs.body = b;
            break;
        }
    const std::vector<ComparedSignal> compared = compared_signals(e, m);
    for (const ComparedSignal& c : compared) {
        if (c.body != cs.body)
            fail(e.path, c.line, "a contact experiment compares the pose of the measured free body '" +
                                     m.bodies[size_t(cs.body)].name + "'");
        if (c.quantity != Quantity::Position && c.quantity != Quantity::Orientation)
            fail(e.path, c.line, std::string("a contact experiment compares positions and orientations (its rollouts "
                                             "give no ") + quantity_name(c.quantity) + ")");
    }

    // The material pair the body touches the world with: its first shape's and the world's first shape's.
    int body_material = -1, world_material = -1;
    for (const sc::Shape& s : contact.shapes) {
        if (s.body == cs.body && body_material < 0) body_material = s.material;
        if (s.body == 0 && world_material < 0) world_material = s.material;
    }
    ContactModel start;
    start.settings = contact.default_settings;
    for (const sc::MaterialPair& p : contact.pairs)
        if ((p.a == body_material && p.b == world_material) || (p.b == body_material && p.a == world_material)) {
            start.settings = p.settings;
            auto name = [&](int id) { return id >= 0 && size_t(id) < contact.materials.size() ? contact.materials[size_t(id)] : std::string(); };
            cs.material_a = name(p.a), cs.material_b = name(p.b);
        }
    cs.start = start;

    ContactScene scene;
    scene.model = &m, scene.body = cs.body, scene.shapes = contact.shapes;
    scene.length_scale = body_size(contact.shapes, cs.body);
    scene.integrator = ContactScene::euler(kContactStep);
    cs.integrator_step = kContactStep;
    std::vector<PoseRecord> fit, validation;
    for (size_t r = 0; r < records.size(); ++r) {
        PoseRecord p = pose_record(records[r], cs.body, int(r));
        if (records[r].role == Role::Fit) fit.push_back(std::move(p)), cs.fit_trials.push_back(int(r));
        else validation.push_back(std::move(p)), cs.validation_trials.push_back(int(r));
    }
    heartbeat("contact", 0);
    ContactFitOptions fo;
    cs.fit = fit_contact(scene, start, fit, validation, fo);

    // Replays: the compared poses rolled out before any cause and after each.
    std::vector<ContactModel> models{start};
    for (const ContactStep& s : cs.fit.steps) models.push_back(model_after(start, s));
    std::vector<std::vector<std::vector<double>>> first, last;
    for (size_t i = 0; i < models.size(); ++i) {
        heartbeat("replay", double(i) / double(models.size()));
        std::vector<std::vector<std::vector<double>>> sim;
        for (size_t r = 0; r < records.size(); ++r) {
            const PoseRecord p = records[r].role == Role::Fit ? fit[size_t(std::find(cs.fit_trials.begin(), cs.fit_trials.end(), int(r)) - cs.fit_trials.begin())]
                                                                : validation[size_t(std::find(cs.validation_trials.begin(), cs.validation_trials.end(), int(r)) - cs.validation_trials.begin())];
            sim.push_back(rolled_signals(records[r], roll_out(scene, models[i], p), compared));
        }
        StepErrors step;
        step.label = i == 0 ? "baseline" : cs.fit.steps[i - 1].cause + " on body '" + m.bodies[size_t(cs.body)].name + "'";
        step.fit_error = step.validation_error = NAN;  // no inverse dynamics in a contact fit
        score_step(e, records, compared, sim, step);
        out.steps.push_back(std::move(step));
        if (i == 0) first = sim;
        if (i + 1 == models.size()) last = std::move(sim);
    }
    const size_t points = options.plot_points;
    for (size_t r = 0; r < records.size(); ++r) {
        const Record& rec = records[r];
        const size_t stride = points > 0 && rec.t.size() > points ? (rec.t.size() + points - 1) / points : 1;
        for (size_t c = 0; c < compared.size(); ++c) {
            Trace t;
            t.record = int(r), t.role = rec.role, t.quantity = compared[c].quantity;
            t.body = compared[c].body, t.component = compared[c].component, t.point = compared[c].point;
            const std::vector<double>& meas = *measured_values(rec, compared[c]);
            for (size_t k = 0; k < rec.t.size(); k += stride) {
                if (!in_window(compared[c], rec, k)) continue;
                t.t.push_back(rec.t[k]);
                t.measured.push_back(meas[k]);
                t.baseline.push_back(first[r][c][k]);
                t.calibrated.push_back(last[r][c][k]);
            }
            out.traces.push_back(std::move(t));
        }
    }
    // The named causes as the loop's causes, on the body, so that the C API,
    // `mbx calibrate` and calibration.json list them like the joint causes;
    // there is no inverse dynamics in a contact fit.
    Identification& id = out.identification;
    id.baseline_fit_error = id.baseline_validation_error = id.final_fit_error = id.final_validation_error = NAN;
    for (size_t i = 0; i < cs.fit.steps.size(); ++i) {
        const ContactStep& step = cs.fit.steps[i];
        SelectedCause c;
        c.candidate.cause = step.cause;
        c.candidate.body = cs.body;
        for (const FittedValue& v : step.parameters) c.parameters.push_back({v.name, v.value, v.standard_error});
        c.evidence = step.evidence;
        c.fit_error = c.validation_error = NAN;
        const PoseError& before = i == 0 ? cs.fit.baseline_validation : cs.fit.steps[i - 1].validation;
        c.validation_gain = before.score() - step.validation.score();
        id.causes.push_back(std::move(c));
        out.steps[i + 1].cause = int(i);
    }
    for (const std::string& n : cs.fit.notes) id.considered.push_back(n);
    for (StepErrors& s : out.steps) s.fit_error = s.validation_error = NAN;
    if (cs.fit.steps.empty()) out.warnings.push_back("no contact cause lowered the validation error enough to be named");
}

std::vector<std::string> write_contact_update(pugi::xml_node root, const ContactStageResult& c, const std::string& file) {
    std::vector<std::string> notes;
    if (!c.ran || c.fit.steps.empty()) return notes;
    const ContactModel& fitted = c.fit.model;
    std::vector<std::string> named;
    for (const ContactStep& s : c.fit.steps) named.push_back(s.cause);
    auto is_named = [&](const char* cause) { return std::find(named.begin(), named.end(), cause) != named.end(); };
    if (is_named("contact_stiffness") || is_named("contact_damping") || is_named("contact_friction")) {
        pugi::xml_node entry;
        for (pugi::xml_node n : root.children("contact")) {
            const std::string a = n.attribute("a").as_string(), b = n.attribute("b").as_string();
            if ((a == c.material_a && b == c.material_b) || (a == c.material_b && b == c.material_a)) entry = n;
        }
        if (!entry) {
            // The model ran on a default the file does not spell out: write it whole.
            pugi::xml_node last;
            for (pugi::xml_node n : root.children()) if (n.type() == pugi::node_element) last = n;
            entry = last ? root.insert_child_after("contact", last) : root.append_child("contact");
            root.insert_child_before(pugi::node_pcdata, entry).set_value("\n  ");
            if (!c.material_a.empty()) entry.append_attribute("a") = c.material_a.c_str();
            if (!c.material_b.empty()) entry.append_attribute("b") = c.material_b.c_str();
            const sc::NormalModel law = fitted.settings.normal.model;
            entry.append_attribute("normal") = law == sc::NormalModel::HuntCrossley   ? "hunt_crossley"
                                               : law == sc::NormalModel::SpringDamper ? "spring_damper"
                                                                                      : "spring";
            set_number(entry, "stiffness", fitted.settings.normal.stiffness);
            set_number(entry, "exponent", fitted.settings.normal.exponent);
            set_number(entry, "damping", fitted.settings.normal.damping);
            set_number(entry, "mu_static", fitted.settings.friction.mu_static);
            set_number(entry, "mu_kinetic", fitted.settings.friction.mu_kinetic);
            entry.append_attribute("friction") = fitted.settings.friction_spring ? "spring" : "regularised";
            if (fitted.settings.friction_spring) {
                set_number(entry, "friction_stiffness", fitted.settings.friction.stiffness);
                set_number(entry, "friction_damping", fitted.settings.friction.damping);
            }
        } else {
            if (is_named("contact_stiffness")) set_number(entry, "stiffness", fitted.settings.normal.stiffness);
            if (is_named("contact_damping")) {
                // The fitted damping replaces a restitution it was solved from.
                entry.remove_attribute("restitution");
                entry.remove_attribute("impact_speed");
                set_number(entry, "damping", fitted.settings.normal.damping);
            }
            if (is_named("contact_friction")) {
                entry.remove_attribute("mu");
                set_number(entry, "mu_static", fitted.settings.friction.mu_static);
                set_number(entry, "mu_kinetic", fitted.settings.friction.mu_kinetic);
            }
        }
    }
    if (is_named("ground_offset") && fitted.ground_offset != 0) {
        int planes = 0;
        for (pugi::xml_node n : root.children("collision")) {
            if (std::string(n.attribute("body").as_string()) != "world" || std::string(n.attribute("shape").as_string()) != "plane")
                continue;
            ++planes;
            const std::string unit = n.attribute("unit").as_string();
            const double length = unit.find("mm") != std::string::npos ? 1e-3 : 1;
            const double angle = unit.find("deg") != std::string::npos ? M_PI / 180 : 1;
            Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
            std::istringstream px(n.attribute("xyz").as_string()), pr(n.attribute("rpy").as_string());
            for (int k = 0; k < 3; ++k) px >> xyz[k];
            for (int k = 0; k < 3; ++k) pr >> rpy[k];
            const Eigen::Vector3d normal = rotation_from_rpy(rpy * angle).col(2);
            xyz += fitted.ground_offset / length * normal;
            if (!n.attribute("xyz")) n.append_attribute("xyz");
            n.attribute("xyz").set_value((number(xyz[0]) + " " + number(xyz[1]) + " " + number(xyz[2])).c_str());
        }
        if (planes == 0)
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(""),
                        "calibration named a ground offset, but the description has no <collision body=\"world\" "
                        "shape=\"plane\"> to move",
                        file, 0);
    }
    const ContactModel& s = c.start;
    std::string pair = c.material_a.empty() && c.material_b.empty() ? "the default pair" : c.material_a + "/" + c.material_b;
    std::string note = "contact of " + pair + ":";
    if (is_named("contact_stiffness")) note += " stiffness " + number(s.settings.normal.stiffness) + " -> " + number(fitted.settings.normal.stiffness) + ";";
    if (is_named("contact_damping")) note += " damping " + number(s.settings.normal.damping) + " -> " + number(fitted.settings.normal.damping) + ";";
    if (is_named("contact_friction")) note += " mu " + number(s.settings.friction.mu_kinetic) + " -> " + number(fitted.settings.friction.mu_kinetic) + ";";
    if (is_named("ground_offset")) note += " world planes moved " + number(fitted.ground_offset) + " m along their normals;";
    note.pop_back();
    notes.push_back(note);
    return notes;
}

}  // namespace mbx::calibration
