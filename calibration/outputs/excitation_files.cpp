#include "calibration/outputs/excitation_files.h"

#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "calibration/outputs/html_plot.h"
#include "core/finding.h"
#include "core/report/atomic_file.h"
#include "core/report/json_writer.h"

namespace mbx::calibration {

namespace {

// The CSV would be larger than any rig's controller takes as one file.
constexpr double kMaxCsvRows = 1e7;

const sim::JointT<double>& joint_of(const sim::Model& m, int dof) { return m.joints[size_t(m.dof_joint[size_t(dof)])]; }

bool linear(const sim::Model& m, int dof) { return joint_of(m, dof).kind == sim::JointKind::Prismatic; }

// Shortest round-trip text, locale-independent.
std::string number(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

// Every design dof's stem, made unique by its coordinate's index where two
// joint names reduce to the same stem.
std::vector<std::string> stems(const sim::Model& m, const ExcitationDesign& d) {
    std::vector<std::string> out;
    for (int dof : d.dofs) out.push_back(excitation_column_stem(m, dof));
    for (size_t i = 0; i < out.size(); ++i)
        for (size_t k = i + 1; k < out.size(); ++k)
            if (out[k] == out[i]) out[k] += "_" + std::to_string(d.dofs[k]);
    return out;
}


}  // namespace

double measured_std_error(const ExcitationReport& r, const std::string& name) {
    for (const auto& [n, v] : r.measured_std_error)
        if (n == name) return v;
    return NAN;
}

std::string excitation_column_stem(const sim::Model& m, int dof) {
    std::string s;
    for (char c : joint_of(m, dof).name)
        s += (std::isalnum(static_cast<unsigned char>(c)) || c == '_') ? c : '_';
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) s = "j" + s;
    return s;
}

std::string excitation_csv(const sim::Model& m, const ExcitationDesign& d, double rate) {
    const double rows = d.period * d.periods * rate + 1;
    if (!(rows <= kMaxCsvRows))
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name),
                    "excitation.csv would hold " + number(std::round(rows)) + " rows at " + number(rate) +
                        " Hz, more than the " + number(kMaxCsvRows) + " it is limited to (lower the sample rate or the periods)");
    const SampledMotion mo = sample_design(d, rate);
    const std::vector<std::string> names = stems(m, d);
    std::string out = "t";
    for (const std::string& n : names) out += "," + n + "_ref," + n + "_ref_velocity," + n + "_ref_acceleration";
    out += '\n';
    char buf[32];
    auto put = [&](double v) {
        const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 12);
        out.append(buf, r.ptr);
    };
    for (size_t k = 0; k < mo.t.size(); ++k) {
        put(mo.t[k]);
        for (Eigen::Index i = 0; i < Eigen::Index(d.dofs.size()); ++i) {
            out += ',', put(mo.q(Eigen::Index(k), i));
            out += ',', put(mo.qd(Eigen::Index(k), i));
            out += ',', put(mo.qdd(Eigen::Index(k), i));
        }
        out += '\n';
    }
    return out;
}

std::string excitation_experiment(const sim::Model& m, const ExcitationDesign& d, const ExcitationReport& r) {
    pugi::xml_document doc;
    pugi::xml_node root = doc.append_child("experiment");
    root.append_attribute("version") = "1";
    root.append_child(pugi::node_comment)
        .set_value((" Designed by mbx excite: run excitation.csv's references (" + number(d.period * d.periods) +
                    " s, at rest at both ends) on the machine under its controller and record at " +
                    number(r.options.sample_rate) +
                    " Hz, with these column names, into measured.csv; validation.csv is a record of another motion "
                    "(an earlier record, or a design with another seed). ")
                       .c_str());
    auto record = [&](const char* file, const char* role) {
        pugi::xml_node n = root.append_child("record");
        n.append_attribute("file") = file;
        n.append_attribute("role") = role;
    };
    record("measured.csv", "fit");
    record("validation.csv", "validation");
    pugi::xml_node time = root.append_child("time");
    time.append_attribute("column") = "t";
    time.append_attribute("unit") = "s";
    const std::vector<std::string> names = stems(m, d);
    for (size_t i = 0; i < d.dofs.size(); ++i) {
        const sim::JointT<double>& j = joint_of(m, d.dofs[i]);
        const bool lin = linear(m, d.dofs[i]);
        const std::string id = j.constraint_id.empty() ? j.name : j.constraint_id;
        auto column = [&](const std::string& name, const char* quantity, const char* unit) {
            pugi::xml_node n = root.append_child("column");
            n.append_attribute("name") = name.c_str();
            n.append_attribute("joint") = id.c_str();
            n.append_attribute("quantity") = quantity;
            n.append_attribute("unit") = unit;
        };
        column(names[i] + "_ref", "reference", lin ? "m" : "rad");
        column(names[i] + "_q", "position", lin ? "m" : "rad");
        column(names[i] + "_effort", "effort", lin ? "N" : "N*m");
    }
    root.append_child("drive").append_attribute("mode") = "closed_loop";
    if (r.options.cutoff > 0) root.append_child("filter").append_attribute("cutoff") = number(r.options.cutoff).c_str();
    for (size_t i = 0; i < d.dofs.size(); ++i) {
        const sim::JointT<double>& j = joint_of(m, d.dofs[i]);
        const std::string id = j.constraint_id.empty() ? j.name : j.constraint_id;
        for (const char* q : {"effort", "position"}) {
            pugi::xml_node n = root.append_child("compare");
            n.append_attribute("joint") = id.c_str();
            n.append_attribute("quantity") = q;
        }
    }
    std::ostringstream os;
    doc.save(os, "  ", pugi::format_indent | pugi::format_no_declaration, pugi::encoding_utf8);
    return os.str();
}

std::string excitation_json(const sim::Model& m, const ExcitationDesign& d, const ExcitationReport& r) {
    JsonWriter w;
    w.begin_object();
    w.member("model", m.name).member("input", r.input);
    w.key("design").begin_object();
    w.member("period", d.period).member("periods", d.periods).member("harmonics", r.options.harmonics);
    w.member("margin", r.options.margin).member("sample_rate", r.options.sample_rate);
    w.member("cutoff", r.options.cutoff > 0 ? r.options.cutoff : r.options.sample_rate / 40);
    w.member("evaluations", d.evaluations).member("seed", r.options.seed);
    w.member("criterion", d.predicted.criterion);
    w.end_object();
    w.key("joints").begin_array();
    const std::vector<std::string> names = stems(m, d);
    for (size_t i = 0; i < d.dofs.size(); ++i) {
        const sim::JointT<double>& j = joint_of(m, d.dofs[i]);
        const ExcitationLimits& L = r.limits[i];
        w.begin_object();
        w.member("id", j.constraint_id).member("name", j.name).member("column", names[i] + "_ref");
        w.member("unit", linear(m, d.dofs[i]) ? "m" : "rad");
        w.member("start", d.references[i].q0).member("effort_noise", d.effort_noise[i]);
        w.key("limits").begin_object(JsonWriter::Layout::Inline);
        w.member("lower", L.lower).member("upper", L.upper).member("velocity", L.velocity);
        w.member("acceleration", L.acceleration).member("effort", L.effort);
        if (i < r.limit_sources.size()) w.member("source", r.limit_sources[i]);
        w.end_object();
        // The servo the design assumed follows the reference ("reached" is its motion).
        if (i < r.options.servo.size() && r.options.servo[i].stiffness > 0 && i < d.servo_inertia.size()) {
            const ExcitationServo& sv = r.options.servo[i];
            w.key("servo").begin_object(JsonWriter::Layout::Inline);
            w.member("stiffness", sv.stiffness).member("damping", sv.damping);
            w.member("damping_on", sv.damping_on_error ? "error" : "speed").member("inertia", d.servo_inertia[i]);
            w.end_object();
        }
        w.key("reached").begin_object(JsonWriter::Layout::Inline);
        w.member("lowest", d.lowest[i]).member("highest", d.highest[i]).member("velocity", d.peak_velocity[i]);
        w.member("acceleration", d.peak_acceleration[i]).member("effort", d.peak_effort[i]);
        w.end_object();
        // q(t) = start + sum_l a_l sin(l w t) + b_l (cos(l w t) - 1), w = 2 pi / period
        w.key("a").begin_array(JsonWriter::Layout::Inline);
        for (double v : d.references[i].a) w.value(v);
        w.end_array();
        w.key("b").begin_array(JsonWriter::Layout::Inline);
        for (double v : d.references[i].b) w.value(v);
        w.end_array();
        w.end_object();
    }
    w.end_array();
    w.key("parameters").begin_array();
    for (size_t k = 0; k < d.predicted.names.size(); ++k) {
        w.begin_object(JsonWriter::Layout::Inline);
        w.member("name", d.predicted.names[k]).member("std_error", d.predicted.std_error[Eigen::Index(k)]);
        if (k < size_t(d.reference.std_error.size()))
            w.member("random_multisine_std_error", d.reference.std_error[Eigen::Index(k)]);
        const double measured = measured_std_error(r, d.predicted.names[k]);
        if (!std::isnan(measured)) w.member("measured_std_error", measured);
        w.end_object();
    }
    w.end_array();
    w.key("dropped").begin_array(JsonWriter::Layout::Inline);
    for (const std::string& c : d.dropped) w.value(c);
    w.end_array();
    w.end_object();
    return w.take() + "\n";
}

std::string excitation_html(const sim::Model& m, const ExcitationDesign& d, const ExcitationReport& r) {
    using namespace html_plot;
    const std::string title = "Excitation design: " + (r.input.empty() ? m.name : r.input);
    std::string h = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + esc(title) +
                    "</title>\n<style>\n" + kStyle + "</style></head><body>\n<h1>" + esc(title) + "</h1>\n";
    h += "<p>" + num(double(d.dofs.size())) + " joints, a Fourier series of " + num(r.options.harmonics) +
         " harmonics each (highest " + num(r.options.harmonics / d.period) + " Hz), period " + num(d.period) + " s, " +
         num(d.periods) + " periods: " + num(d.period * d.periods) +
         " s at rest at both ends. Every limit is kept with " + num(100 * r.options.margin) +
         " % of it (of the position range) left free for the controller's tracking. The references are in "
         "excitation.csv; experiment.xml reads the record made along them.</p>\n";

    h += "<h2>Predicted standard errors</h2>\n<p>In the joint inverse-dynamics fit of these causes, with each joint's "
         "effort noise as below. A random multi-sine is scaled to the same limits";
    h += r.measured_std_error.empty() ? ".</p>\n" : "; the records it replaces are those of calibration.json.</p>\n";
    h += "<table><tr><th>parameter</th><th>along the design</th><th>along a random multi-sine</th><th>gain</th>";
    if (!r.measured_std_error.empty()) h += "<th>in the records it replaces</th><th>gain</th>";
    h += "</tr>\n";
    for (size_t k = 0; k < d.predicted.names.size(); ++k) {
        const double e = d.predicted.std_error[Eigen::Index(k)];
        const double ref = k < size_t(d.reference.std_error.size()) ? d.reference.std_error[Eigen::Index(k)] : NAN;
        h += "<tr><td>" + esc(d.predicted.names[k]) + "</td><td class=\"n\">" + num(e, 3) + "</td><td class=\"n\">" +
             num(ref, 3) + "</td><td class=\"n\">" + num(ref / e, 3) + "×</td>";
        if (!r.measured_std_error.empty()) {
            const double measured = measured_std_error(r, d.predicted.names[k]);
            h += "<td class=\"n\">" + num(measured, 3) + "</td><td class=\"n\">" + num(measured / e, 3) + "×</td>";
        }
        h += "</tr>\n";
    }
    h += "</table>\n";
    if (!d.dropped.empty()) {
        h += "<p>Left out of the default causes (this machine's efforts show them not at all, or only as the others):";
        for (const std::string& c : d.dropped) h += (c == d.dropped.front() ? " " : ", ") + esc(c);
        h += ".</p>\n";
    }

    h += "<h2>Joints</h2>\n<table><tr><th>joint</th><th>limits from</th><th>range</th><th>reached</th><th>speed "
         "limit</th><th>reached</th><th>acceleration limit</th><th>reached</th><th>effort limit</th><th>reached</th>"
         "<th>effort noise</th></tr>\n";
    for (size_t i = 0; i < d.dofs.size(); ++i) {
        const ExcitationLimits& L = r.limits[i];
        h += "<tr><td>" + esc(joint_of(m, d.dofs[i]).name) + "</td><td>" +
             esc(i < r.limit_sources.size() ? r.limit_sources[i] : "") + "</td><td class=\"n\">" + num(L.lower) + " … " +
             num(L.upper) + "</td><td class=\"n\">" + num(d.lowest[i]) + " … " + num(d.highest[i]) +
             "</td><td class=\"n\">" + num(L.velocity) + "</td><td class=\"n\">" + num(d.peak_velocity[i]) +
             "</td><td class=\"n\">" + num(L.acceleration) + "</td><td class=\"n\">" + num(d.peak_acceleration[i]) +
             "</td><td class=\"n\">" + num(L.effort) + "</td><td class=\"n\">" + num(d.peak_effort[i]) +
             "</td><td class=\"n\">" + num(d.effort_noise[i], 3) + "</td></tr>\n";
    }
    h += "</table>\n<p>Units: rad, rad/s, rad/s², N·m (m, m/s, m/s², N for sliding joints); “n/a”: no limit.</p>\n";

    h += "<h2>References</h2>\n";
    const SampledMotion mo = sample_design(d, std::max(50.0, 400 / d.period));
    static const char* const kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"};
    std::vector<std::vector<double>> q(d.dofs.size()), qd(d.dofs.size());
    for (size_t i = 0; i < d.dofs.size(); ++i) {
        q[i].assign(mo.q.col(Eigen::Index(i)).data(), mo.q.col(Eigen::Index(i)).data() + mo.q.rows());
        qd[i].assign(mo.qd.col(Eigen::Index(i)).data(), mo.qd.col(Eigen::Index(i)).data() + mo.qd.rows());
    }
    Plot positions{"Positions", "time [s]", "position [rad or m]", {}}, speeds{"Speeds", "time [s]", "speed [rad/s or m/s]", {}};
    for (size_t i = 0; i < d.dofs.size(); ++i) {
        const std::string& name = joint_of(m, d.dofs[i]).name;
        positions.series.push_back({name, kColors[i % 7], &mo.t, &q[i]});
        speeds.series.push_back({name, kColors[i % 7], &mo.t, &qd[i]});
    }
    h += svg(positions) + svg(speeds);
    h += "</body></html>\n";
    return h;
}

void write_excitation_files(const std::string& dir, const sim::Model& m, const ExcitationDesign& d,
                            const ExcitationReport& r) {
    if (dir.empty()) throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::model(m.name), "excitation output folder is empty");
    std::vector<std::pair<std::string, std::string>> files;
    files.emplace_back(dir + "/excitation.csv", excitation_csv(m, d, r.options.sample_rate));
    files.emplace_back(dir + "/experiment.xml", excitation_experiment(m, d, r));
    files.emplace_back(dir + "/excitation.json", excitation_json(m, d, r));
    files.emplace_back(dir + "/excitation.html", excitation_html(m, d, r));
    write_files_atomically(files);
}

}  // namespace mbx::calibration
