// calibration.html: one page a person reads in a browser, with everything
// inline (styles, SVG plots): no scripts, fonts or images from anywhere, so
// it opens offline and can be mailed as one file.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <string_view>

#include "calibration/outputs/calibration_files.h"
#include "calibration/outputs/calibration_files_detail.h"
#include "calibration/outputs/html_plot.h"
#include "core/report/utf8.h"

namespace mbx::calibration {

namespace {

using namespace detail;
using namespace html_plot;

// Grouped bars of the error after each step.
std::string step_chart(const CalibrationResult& r) {
    struct Bar {
        const char* name;
        const char* color;
        double StepErrors::*value;
    };
    const Bar bars[] = {{"identification fit", "#9ecae1", &StepErrors::fit_error},
                        {"identification validation", "#3182bd", &StepErrors::validation_error},
                        {"simulated fit", "#fdae6b", &StepErrors::simulated_fit},
                        {"simulated validation", "#e6550d", &StepErrors::simulated_validation}};
    double top = 0;
    for (const StepErrors& s : r.steps)
        for (const Bar& b : bars)
            if (std::isfinite(s.*b.value)) top = std::max(top, s.*b.value);
    Frame f{0, double(r.steps.size()), 0, top > 0 ? top * 1.05 : 1};
    std::string out;
    axes(out, f, "Error after each step", "step", "error [%]", false);
    const double group = f.px(1) - f.px(0), w = group * 0.8 / 4;
    for (size_t i = 0; i < r.steps.size(); ++i) {
        const StepErrors& s = r.steps[i];
        for (size_t k = 0; k < 4; ++k) {
            const double v = s.*bars[k].value;
            if (!std::isfinite(v)) continue;
            const double x = f.px(double(i)) + group * 0.1 + double(k) * w;
            out += "<rect x=\"";
            coord(out, x);
            out += "\" y=\"";
            coord(out, f.py(v));
            out += "\" width=\"";
            coord(out, w);
            out += "\" height=\"";
            coord(out, f.py(0) - f.py(v));
            out += "\" fill=\"";
            out += bars[k].color;
            out += "\"><title>" + esc(s.label) + ": " + bars[k].name + " " + num(v) + " %</title></rect>";
        }
        // The cause's name fits under its bars; the full label is in the table.
        std::string label = std::to_string(i) + " " +
                            (s.cause >= 0 ? r.identification.causes[size_t(s.cause)].candidate.cause
                                          : i == 0 ? std::string("baseline") : s.label);
        const size_t fits = size_t(std::max(4.0, group / 6.2));
        if (label.size() > fits) label = label.substr(0, fits - 1) + "…";
        text(out, f.px(double(i) + 0.5), kHeight - kBottom + 15, label, "middle");
    }
    legend(out, {{"ident. fit", bars[0].color}, {"ident. validation", bars[1].color},
                 {"simulated fit", bars[2].color}, {"simulated validation", bars[3].color}});
    out += "</svg>\n";
    return out;
}


// The record's file name and role: full paths are in the records table and
// would crowd a plot's title.
// Records are named relative to the experiment file ("dir/../data/x.csv"):
// shown normalised (the JSON keeps them as given).
std::string shown_path(const std::string& path) { return std::filesystem::path(path).lexically_normal().string(); }

std::string record_label(const CalibrationResult& r, int i) {
    const std::string& path = r.record_paths[size_t(i)];
    const size_t slash = path.find_last_of('/');
    return (slash == std::string::npos ? path : path.substr(slash + 1)) + " (" + role_name(r.record_roles[size_t(i)]) + ")";
}

// Quantity, unit: "effort [N]".
std::string axis_label(Quantity q, bool linear, const char* what = nullptr) {
    return std::string(what ? what : quantity_name(q)) + " [" + quantity_unit(q, linear) + "]";
}

void step_table(std::string& h, const CalibrationResult& r) {
    h += "<table><tr><th>step</th><th>model</th><th>identification fit %</th><th>identification validation %</th>"
         "<th>simulated fit %</th><th>simulated validation %</th></tr>\n";
    for (size_t i = 0; i < r.steps.size(); ++i) {
        const StepErrors& s = r.steps[i];
        h += "<tr><td class=n>" + std::to_string(i) + "</td><td>" + esc(s.label) + "</td><td class=n>" +
             num(s.fit_error) + "</td><td class=n>" + num(s.validation_error) + "</td><td class=n>" +
             num(s.simulated_fit) + "</td><td class=n>" + num(s.simulated_validation) + "</td></tr>\n";
    }
    h += "</table>\n";
}

void signal_table(std::string& h, const sim::Model& model, const CalibrationResult& r) {
    const StepErrors &b = r.baseline(), &f = r.final_step();
    if (b.simulated.empty()) return;
    h += "<table><tr><th>record</th><th>joint or body</th><th>quantity</th><th>weight</th><th>baseline %</th>"
         "<th>calibrated %</th><th>baseline RMS</th><th>calibrated RMS</th></tr>\n";
    for (const SignalError& e : b.simulated) {
        const SignalError* after = nullptr;
        for (const SignalError& g : f.simulated)
            if (g.record == e.record && g.joint == e.joint && g.quantity == e.quantity && g.body == e.body &&
                g.component == e.component && g.point == e.point)
                after = &g;
        const char* unit = signal_unit(model, e.joint, e.body, e.quantity);
        h += "<tr><td>" + esc(record_label(r, e.record)) + "</td><td>" +
             esc(signal_label(model, e.joint, e.body, e.quantity, e.component, e.point)) + "</td><td>" +
             quantity_name(e.quantity) + "</td><td class=n>" + num(e.weight) + "</td><td class=n>" + num(e.relative) +
             "</td><td class=n>" + (after ? num(after->relative) : "") + "</td><td class=n>" + num(e.rms) + " " + unit +
             "</td><td class=n>" + (after ? num(after->rms) + " " + unit : "") + "</td></tr>\n";
    }
    h += "</table>\n";
}

std::string pose_text(const PoseError& e) {
    return num(e.position) + " % of size, " + num(e.rotation) + " deg";
}

// The contact stage's causes, parameters and pose errors.
void contact_table(std::string& h, const sim::Model& model, const ContactStageResult& c) {
    h += "<p>Contact of body " + esc(model.bodies[size_t(c.body)].name) + " (" + std::to_string(c.fit_trials.size()) +
         " fit and " + std::to_string(c.validation_trials.size()) + " validation trials, " +
         std::to_string(c.fit.rollouts) + " rollouts): validation error before " + pose_text(c.fit.baseline_validation) +
         ".</p>\n";
    if (c.fit.steps.empty()) h += "<p>No contact cause lowered the validation error enough to be named.</p>\n";
    else {
        h += "<table><tr><th>step</th><th>cause</th><th>parameters (± standard error)</th><th>fit</th><th>validation</th>"
             "<th>evidence</th></tr>\n";
        for (size_t i = 0; i < c.fit.steps.size(); ++i) {
            const ContactStep& s = c.fit.steps[i];
            std::string p;
            for (const FittedValue& v : s.parameters)
                p += esc(v.name) + " = " + num(v.value) + " ± " + num(v.standard_error) + " " + esc(v.unit) + "<br>";
            h += "<tr><td class=n>" + std::to_string(i + 1) + "</td><td>" + esc(s.cause) + "</td><td>" + p + "</td><td>" +
                 pose_text(s.fit) + "</td><td>" + pose_text(s.validation) + "</td><td>" + esc(s.evidence) + "</td></tr>\n";
        }
        h += "</table>\n";
    }
    for (const std::string& n : c.fit.notes) h += "<p>" + esc(n) + "</p>\n";
}

void cause_table(std::string& h, const sim::Model& model, const CalibrationResult& r) {
    const Identification& id = r.identification;
    if (id.causes.empty()) {
        h += "<p>No cause passed the tests: what the model misses is within what noise explains.</p>\n";
        return;
    }
    h += "<table><tr><th>step</th><th>cause</th><th>subject</th><th>parameters (± standard error)</th>"
         "<th>evidence</th><th>identification fit / validation %</th><th>simulated fit / validation %</th></tr>\n";
    for (size_t i = 0; i < id.causes.size(); ++i) {
        const SelectedCause& c = id.causes[i];
        const CauseSubject s = cause_subject(model, c.candidate);
        h += "<tr><td class=n>" + std::to_string(i + 1) + "</td><td>" + esc(c.candidate.cause) + "</td><td>" + s.kind +
             " " + esc(s.name) + " <small>(" + esc(s.id) + ")</small></td><td>";
        for (size_t k = 0; k < c.parameters.size(); ++k)
            h += (k ? "<br>" : "") + esc(c.parameters[k].name) + " = " + num(c.parameters[k].value) + " ± " +
                 num(c.parameters[k].std_error, 2);
        h += "</td><td>" + esc(c.evidence) + "</td><td class=n>" + num(c.fit_error) + " / " + num(c.validation_error) +
             "</td><td class=n>";
        if (const StepErrors* st = step_of_cause(r, int(i)))
            h += num(st->simulated_fit) + " / " + num(st->simulated_validation);
        h += "</td></tr>\n";
    }
    h += "</table>\n";
}

// What the description file gets, in the joint's own units.
void update_table(std::string& h, const CalibrationResult& r) {
    if (r.joints.empty() && r.drives.empty() && r.unwritten.empty()) return;
    h += "<h2>Written to description.xml</h2>\n";
    if (!r.joints.empty()) {
        h += "<table><tr><th>joint</th><th>causes</th><th>joint dynamics after calibration</th></tr>\n";
        for (const JointUpdate& u : r.joints) {
            const sim::JointDynamics& d = u.after;
            const char* e = u.linear ? "N" : "N m";
            const char* v = u.linear ? "m/s" : "rad/s";
            std::string values;
            auto add = [&](const char* name, double x, const std::string& unit) {
                if (x == 0) return;
                values += (values.empty() ? "" : ", ") + std::string(name) + " " + num(x) + " " + unit;
            };
            add("damping", d.damping, std::string(e) + (u.linear ? " s/m" : " s/rad"));
            add("coulomb", d.coulomb, e);
            if (d.asymmetric) {
                add("damping (q̇ < 0)", d.damping_negative, std::string(e) + (u.linear ? " s/m" : " s/rad"));
                add("coulomb (q̇ < 0)", d.coulomb_negative, e);
            }
            add("stribeck", d.stribeck, e);
            add("stribeck velocity", d.stribeck_velocity, v);
            add("offset", d.offset, e);
            add("stiffness", d.stiffness, std::string(e) + (u.linear ? "/m" : "/rad"));
            add("rest", d.rest, u.linear ? "m" : "rad");
            add("armature", d.armature, u.linear ? "kg" : "kg m²");
            if (const auto& t = u.transmission_after) {
                add("transmission stiffness", t->stiffness, std::string(e) + (u.linear ? "/m" : "/rad"));
                add("transmission damping", t->damping, std::string(e) + (u.linear ? " s/m" : " s/rad"));
                add("motor inertia", t->motor_inertia, u.linear ? "kg" : "kg m²");
                add("backlash", t->backlash, u.linear ? "m" : "rad");
            }
            std::string causes;
            for (const std::string& c : u.causes) causes += (causes.empty() ? "" : ", ") + c;
            h += "<tr><td>" + esc(u.name) + " <small>(" + esc(u.constraint_id) + ")</small></td><td>" + esc(causes) +
                 "</td><td>" + esc(values) + "</td></tr>\n";
        }
        h += "</table>\n";
    }
    for (const DriveUpdate& d : r.drives)
        h += "<p>Drive " + esc(d.name) + " <small>(" + esc(d.constraint_id) + ")</small>: controller delay " +
             num(d.delay_before * 1e3) + " ms → " + num(d.delay_after * 1e3) + " ms.</p>\n";
    if (!r.unwritten.empty()) {
        h += "<p>Identified, applied in the replays, but not in the description file:</p><ul>\n";
        for (const UnwrittenCause& u : r.unwritten)
            h += "<li>" + esc(r.identification.causes[size_t(u.cause)].candidate.cause) + ": " + esc(u.reason) +
                 "</li>\n";
        h += "</ul>\n";
    }
}

}  // namespace

std::string calibration_html(const sim::Model& model, const Experiment& experiment, const CalibrationResult& r) {
    check_result(model, r);
    const Identification& id = r.identification;
    std::string h;
    h.reserve(256 * 1024);
    const std::string title = "mbx calibration" + (model.name.empty() ? std::string() : ": " + model.name);
    h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + esc(title) +
         "</title>\n<style>\n" + kStyle + "</style></head><body>\n<h1>" + esc(title) + "</h1>\n";
    const char* driven = r.mode == DriveMode::ClosedLoop ? "in closed loop (the controller follows the recorded reference)"
                         : r.mode == DriveMode::Effort ? "by the recorded effort"
                                                       : "free from the measured initial state";
    std::string concentration;
    for (const std::string& c : id.residual_concentration) concentration += " It concentrates on " + esc(c) + ".";
    h += "<p>Experiment " + esc(shown_path(experiment.path)) + ", the model driven " + driven + ". Calibrated in " +
         num(r.wall_time, 3) + " s." +
         (std::isfinite(id.noise_level)
              ? " The records' own effort noise after the filter (what no model explains): " + num(id.noise_level) +
                    " % of the validation effort; " +
                    (explained_to_noise(id.final_validation_error, id.noise_level)
                         ? std::string("the calibrated model explains the rest to the noise.")
                         : num(std::sqrt(std::max(0.0, id.final_validation_error * id.final_validation_error -
                                                           id.noise_level * id.noise_level))) +
                               " % of it is left above the noise." + concentration)
              : std::string()) +
         "</p>\n<table><tr><th>record</th><th>role</th></tr>\n";
    for (size_t i = 0; i < r.record_paths.size(); ++i)
        h += "<tr><td>" + esc(shown_path(r.record_paths[i])) + "</td><td>" + role_name(r.record_roles[i]) + "</td></tr>\n";
    h += "</table>\n";

    const StepErrors &b = r.baseline(), &f = r.final_step();
    h += "<h2>Errors</h2>\n<p>Simulated error: fit " + num(b.simulated_fit) + " % → " + num(f.simulated_fit) +
         " %, validation " + num(b.simulated_validation) + " % → " + num(f.simulated_validation) +
         " % (identification: " + num(b.fit_error) + " % → " + num(f.fit_error) + " %, " + num(b.validation_error) +
         " % → " + num(f.validation_error) + " %).</p>\n";
    h += step_chart(r);
    step_table(h, r);
    signal_table(h, model, r);

    h += "<h2>Causes</h2>\n";
    if (r.contact.ran) contact_table(h, model, r.contact);
    else cause_table(h, model, r);
    update_table(h, r);

    if (!r.traces.empty()) h += "<h2>Compared signals</h2>\n";
    for (const Trace& t : r.traces) {
        Plot p;
        p.title = record_label(r, t.record) + ": " + signal_label(model, t.joint, t.body, t.quantity, t.component, t.point) +
                  " " + quantity_name(t.quantity);
        p.xlabel = "time [s]";
        p.ylabel = std::string(quantity_name(t.quantity)) + " [" + signal_unit(model, t.joint, t.body, t.quantity) + "]";
        p.series = {{"measured", "#222222", &t.t, &t.measured},
                    {"baseline", "#d95f02", &t.t, &t.baseline},
                    {"calibrated", "#1f77b4", &t.t, &t.calibrated}};
        h += svg(p);
    }

    if (!r.residuals.empty())
        h += "<h2>Residual signatures</h2>\n<p>Measured minus modelled effort on the fit records (inverse dynamics), "
             "before and after calibration: friction shows against velocity, a spring or a sensor offset against "
             "position.</p>\n";
    for (const ResidualCloud& c : r.residuals) {
        const bool linear = linear_joint(model, c.joint);
        for (int against = 0; against < 2; ++against) {
            Plot p;
            const std::vector<double>* x = against == 0 ? &c.velocity : &c.position;
            p.title = "Residual of " + joint_label(model, c.joint) + " against " + (against == 0 ? "velocity" : "position");
            p.xlabel = axis_label(against == 0 ? Quantity::Velocity : Quantity::Position, linear);
            p.ylabel = axis_label(Quantity::Effort, linear, "residual effort");
            p.series = {{"before", "#d95f02", x, &c.before, true}, {"after", "#1f77b4", x, &c.after, true}};
            h += svg(p);
        }
    }

    std::vector<std::string> warnings = r.warnings;
    for (const std::string& w : id.warnings)
        if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
    h += "<h2>Warnings</h2>\n";
    if (warnings.empty()) h += "<p>None.</p>\n";
    else {
        h += "<ul class=w>\n";
        for (const std::string& w : warnings) h += "<li>" + esc(w) + "</li>\n";
        h += "</ul>\n";
    }
    if (!id.considered.empty()) {
        h += "<details><summary>Candidates considered in the first round</summary><ul>\n";
        for (const std::string& s : id.considered) h += "<li>" + esc(s) + "</li>\n";
        h += "</ul></details>\n";
    }
    h += "</body></html>\n";
    return h;
}

}  // namespace mbx::calibration
