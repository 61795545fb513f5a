#include "calibration/records/experiment.h"

#include <pugixml.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "core/finding.h"
#include "core/mechatronics/xml_text.h"

namespace mbx::calibration {

const char* quantity_name(Quantity q) {
    switch (q) {
    case Quantity::Position: return "position";
    case Quantity::Velocity: return "velocity";
    case Quantity::Acceleration: return "acceleration";
    case Quantity::Effort: return "effort";
    case Quantity::Voltage: return "voltage";
    case Quantity::Current: return "current";
    case Quantity::Reference: return "reference";
    case Quantity::ControllerInput: return "controller_input";
    case Quantity::Orientation: return "orientation";
    case Quantity::AngularVelocity: return "angular_velocity";
    }
    return "?";
}

const char* drive_mode_name(DriveMode m) {
    switch (m) {
    case DriveMode::ClosedLoop: return "closed_loop";
    case DriveMode::Effort: return "effort";
    case DriveMode::Free: return "free";
    }
    return "?";
}

namespace {

bool parse_quantity(const std::string& word, Quantity& out) {
    for (Quantity q : {Quantity::Position, Quantity::Velocity, Quantity::Acceleration, Quantity::Effort,
                       Quantity::Voltage, Quantity::Current, Quantity::Reference, Quantity::ControllerInput,
                       Quantity::Orientation, Quantity::AngularVelocity})
        if (word == quantity_name(q)) {
            out = q;
            return true;
        }
    return false;
}

// Angle and length units and their SI factors; rates and accelerations add
// "/s" and "/s^2" to them.
const std::map<std::string, double>& angle_units() {
    static const std::map<std::string, double> u{{"rad", 1.0}, {"deg", M_PI / 180}};
    return u;
}
const std::map<std::string, double>& length_units() {
    static const std::map<std::string, double> u{{"m", 1.0}, {"mm", 1e-3}};
    return u;
}

bool lookup(const std::map<std::string, double>& units, const std::string& unit, const std::string& suffix,
            double& factor) {
    for (const auto& [name, f] : units)
        if (unit == name + suffix) {
            factor = f;
            return true;
        }
    return false;
}

}  // namespace

bool unit_factor(Quantity q, const std::string& unit, bool linear, double& factor) {
    const auto& pos = linear ? length_units() : angle_units();
    switch (q) {
    case Quantity::Position:
    case Quantity::Reference: return lookup(pos, unit, "", factor);
    case Quantity::Velocity: return lookup(pos, unit, "/s", factor);
    case Quantity::Acceleration: return lookup(pos, unit, "/s^2", factor);
    case Quantity::Effort:
        factor = 1;
        return linear ? unit == "N" : (unit == "N*m" || unit == "N m" || unit == "Nm");
    case Quantity::Voltage:
    case Quantity::ControllerInput: factor = 1; return unit == "V";
    case Quantity::Current: factor = 1; return unit == "A";
    case Quantity::Orientation: factor = 1; return unit == "1";
    case Quantity::AngularVelocity: return lookup(angle_units(), unit, "/s", factor);
    }
    return false;
}

namespace {

class Parser {
public:
    Parser(const std::string& text, const std::string& path) : text_(text), lines_(text) { exp_.path = path; }

    Experiment run() {
        pugi::xml_document doc;
        const pugi::xml_parse_result parsed = doc.load_buffer(text_.data(), text_.size(), pugi::parse_default);
        if (!parsed) {
            fail(lines_.line_at(parsed.offset), std::string("not well-formed XML: ") + parsed.description());
            finish();
        }
        const pugi::xml_node root = doc.document_element();
        if (std::string(root.name()) != "experiment") {
            fail(lines_.line(root), "the root element must be <experiment>");
            finish();
        }
        attributes(root, {"version"});
        if (root.attribute("version") && std::string(root.attribute("version").value()) != "1")
            fail(lines_.line(root), "unknown experiment version '" + std::string(root.attribute("version").value()) + "' (1 is known)");
        bool have_time = false, have_drive = false, have_filter = false;
        std::set<std::string> column_names;
        const std::filesystem::path base = std::filesystem::path(exp_.path).parent_path();
        for (pugi::xml_node n : root.children()) {
            if (n.type() != pugi::node_element) continue;
            const std::string name = n.name();
            const int line = lines_.line(n);
            if (name == "record") {
                attributes(n, {"file", "role", "start", "stop", "trials"});
                RecordSpec r;
                r.line = line;
                const std::string file = n.attribute("file").value();
                if (file.empty()) fail(line, "<record> needs a file");
                r.path = file.empty() ? file : (std::filesystem::path(file).is_absolute() ? file : (base / file).lexically_normal().string());
                const std::string role = n.attribute("role").value();
                if (role == "fit")
                    r.role = Role::Fit;
                else if (role == "validation")
                    r.role = Role::Validation;
                else
                    fail(line, "<record> role must be 'fit' or 'validation' (got '" + role + "')");
                r.start = optional_number(n, "start", -1);
                r.stop = optional_number(n, "stop", -1);
                if (r.start >= 0 && r.stop >= 0 && !(r.stop > r.start)) fail(line, "<record> stop must be after start");
                if (n.attribute("trials")) {
                    r.trials = trial_list(n);
                    trials_used_line = line;
                }
                exp_.records.push_back(r);
            } else if (name == "trials") {
                attributes(n, {"column"});
                if (!exp_.trial_column.empty()) fail(line, "a second <trials>");
                exp_.trial_column = n.attribute("column").value();
                if (exp_.trial_column.empty()) fail(line, "<trials> needs a column (the trial id of each row)");
            } else if (name == "time") {
                attributes(n, {"column", "unit", "scale"});
                if (have_time) fail(line, "a second <time>");
                have_time = true;
                exp_.time_column = n.attribute("column").value();
                if (exp_.time_column.empty()) fail(line, "<time> needs a column");
                const std::string unit = n.attribute("unit").value();
                if (unit == "s" || unit.empty())
                    exp_.time_factor = 1;
                else if (unit == "ms")
                    exp_.time_factor = 1e-3;
                else
                    fail(line, "<time> unit must be 's' or 'ms' (got '" + unit + "')");
                exp_.time_factor *= positive(n, "scale", 1);
            } else if (name == "column") {
                attributes(n, {"name", "joint", "body", "quantity", "unit", "scale", "optional", "axis", "component", "point"});
                ColumnSpec c;
                c.line = line;
                c.name = n.attribute("name").value();
                if (c.name.empty()) fail(line, "<column> needs a name (the CSV header)");
                if (!column_names.insert(c.name).second) fail(line, "column '" + c.name + "' is described twice");
                subject(n, c.joint, c.body);
                c.quantity = quantity(n);
                body_component(n, !c.body.empty(), c.quantity, c.component, c.point);
                c.unit = n.attribute("unit").value();
                // A quaternion has no unit to forget.
                if (c.unit.empty() && c.quantity == Quantity::Orientation) c.unit = "1";
                if (c.unit.empty()) fail(line, "<column> '" + c.name + "' needs a unit");
                double f = 0;
                const bool unit_ok = !c.body.empty()
                                         ? unit_factor(c.quantity, c.unit, true, f)
                                         : unit_factor(c.quantity, c.unit, false, f) || unit_factor(c.quantity, c.unit, true, f);
                if (!c.unit.empty() && !unit_ok)
                    fail(line, "unit '" + c.unit + "' is not one of " + (c.body.empty() ? "" : "a body's ") +
                                   quantity_name(c.quantity) + "'s units");
                c.scale = number(n, "scale", 1);
                if (c.scale == 0) fail(line, "<column> scale must not be 0");
                const std::string opt = n.attribute("optional").value();
                if (!opt.empty() && opt != "true" && opt != "false") fail(line, "optional must be 'true' or 'false'");
                c.optional = opt == "true";
                exp_.columns.push_back(c);
            } else if (name == "drive") {
                attributes(n, {"mode", "horizon"});
                if (have_drive) fail(line, "a second <drive>");
                have_drive = true;
                const std::string mode = n.attribute("mode").value();
                if (mode == "closed_loop")
                    exp_.mode = DriveMode::ClosedLoop;
                else if (mode == "effort")
                    exp_.mode = DriveMode::Effort;
                else if (mode == "free")
                    exp_.mode = DriveMode::Free;
                else
                    fail(line, "<drive> mode must be closed_loop, effort or free (got '" + mode + "')");
                exp_.horizon = positive(n, "horizon", 0.5);
            } else if (name == "filter") {
                attributes(n, {"cutoff"});
                if (have_filter) fail(line, "a second <filter>");
                have_filter = true;
                if (!n.attribute("cutoff")) fail(line, "<filter> needs cutoff (Hz)");
                exp_.cutoff = positive(n, "cutoff", 0);
            } else if (name == "compare") {
                attributes(n, {"joint", "body", "quantity", "weight", "start", "stop", "axis", "component", "point"});
                CompareSpec c;
                c.line = line;
                subject(n, c.joint, c.body);
                c.quantity = quantity(n);
                body_component(n, !c.body.empty(), c.quantity, c.component, c.point);
                c.weight = positive(n, "weight", 1);
                c.start = optional_number(n, "start", -1);
                c.stop = optional_number(n, "stop", -1);
                if (c.start >= 0 && c.stop >= 0 && !(c.stop > c.start)) fail(line, "<compare> stop must be after start");
                exp_.compare.push_back(c);
            } else {
                fail(line, "unknown element <" + name + ">");
            }
        }
        if (trials_used_line && exp_.trial_column.empty())
            fail(trials_used_line, "<record trials=...> needs <trials column=...> (which column tells the trials apart)");
        const int root_line = lines_.line(root);
        if (!have_time) fail(root_line, "no <time column=...>");
        bool fit = false, validation = false;
        for (const RecordSpec& r : exp_.records) (r.role == Role::Fit ? fit : validation) = true;
        if (!fit) fail(root_line, "no <record role=\"fit\">");
        if (!validation) fail(root_line, "no <record role=\"validation\"> (give a held-out file or time window)");
        if (exp_.compare.empty()) fail(root_line, "no <compare>: which signals should the model reproduce?");
        finish();
        return exp_;
    }

private:
    void fail(int line, const std::string& message) {
        errors_ += (errors_.empty() ? "" : "\n") + exp_.path + ":" + std::to_string(line) + ": " + message;
        if (!first_line_) first_line_ = line;
    }
    void finish() {
        if (!errors_.empty()) throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"), errors_, exp_.path, first_line_);
    }
    void attributes(const pugi::xml_node& n, std::initializer_list<const char*> known) {
        for (pugi::xml_attribute a : n.attributes()) {
            bool ok = false;
            for (const char* k : known) ok = ok || std::string(a.name()) == k;
            if (!ok) fail(lines_.line(n), "unknown attribute '" + std::string(a.name()) + "' on <" + n.name() + ">");
        }
    }
    double number(const pugi::xml_node& n, const char* attr, double fallback) {
        const pugi::xml_attribute a = n.attribute(attr);
        if (!a) return fallback;
        double v = 0;
        if (!parse_xml_number(a.value(), v)) {
            fail(lines_.line(n), std::string(attr) + " '" + a.value() + "' is not a finite number");
            return fallback;
        }
        return v;
    }
    double positive(const pugi::xml_node& n, const char* attr, double fallback) {
        const double v = number(n, attr, fallback);
        if (!(v > 0)) {
            fail(lines_.line(n), std::string(attr) + " must be positive");
            return fallback;
        }
        return v;
    }
    double optional_number(const pugi::xml_node& n, const char* attr, double fallback) {
        if (!n.attribute(attr)) return fallback;
        const double v = number(n, attr, fallback);
        if (v < 0) fail(lines_.line(n), std::string(attr) + " must not be negative");
        return v;
    }
    // "0-569/50 3 7": ids, ranges a-b and ranges with a step a-b/s.
    std::vector<long long> trial_list(const pugi::xml_node& n) {
        std::vector<long long> out;
        std::istringstream in(n.attribute("trials").value());
        std::string word;
        auto bad = [&](const std::string& w) {
            fail(lines_.line(n), "trials: '" + w + "' is not a trial id, a range a-b or a range with a step a-b/s");
        };
        while (in >> word) {
            long long a = 0, b = 0, step = 1;
            char dash = 0, slash = 0;
            std::istringstream w(word);
            if (!(w >> a)) { bad(word); continue; }
            b = a;
            if (w >> dash) {
                if (dash != '-' || !(w >> b)) { bad(word); continue; }
                if (w >> slash) {
                    if (slash != '/' || !(w >> step) || step <= 0) { bad(word); continue; }
                }
                std::string rest;
                if (w >> rest || b < a) { bad(word); continue; }
            }
            if ((b - a) / step > 1000000) { bad(word); continue; }
            for (long long k = a; k <= b; k += step) out.push_back(k);
        }
        if (out.empty()) fail(lines_.line(n), "trials lists no trial");
        return out;
    }
    void subject(const pugi::xml_node& n, std::string& joint, std::string& body) {
        joint = n.attribute("joint").value();
        body = n.attribute("body").value();
        if (joint.empty() == body.empty())
            fail(lines_.line(n), std::string("<") + n.name() + "> needs exactly one of joint and body");
    }
    Quantity quantity(const pugi::xml_node& n) {
        Quantity q = Quantity::Position;
        const std::string word = n.attribute("quantity").value();
        if (!parse_quantity(word, q))
            fail(lines_.line(n), "unknown quantity '" + word +
                                     "' (position, velocity, acceleration, effort, voltage, current, reference, controller_input; "
                                     "a body's position, velocity, orientation, angular_velocity)");
        return q;
    }
    // The axis, quaternion component and point of a body quantity; refused
    // on a joint, and a joint's quantities refused on a body.
    void body_component(const pugi::xml_node& n, bool body, Quantity q, int& component, std::array<double, 3>& point) {
        const int line = lines_.line(n);
        const std::string axis = n.attribute("axis").value(), comp = n.attribute("component").value();
        const bool has_point = bool(n.attribute("point"));
        const std::string element = std::string("<") + n.name() + ">";
        if (!body) {
            if (!axis.empty() || !comp.empty() || has_point)
                fail(line, element + ": axis, component and point describe a body quantity, not a joint's");
            if (q == Quantity::Orientation || q == Quantity::AngularVelocity)
                fail(line, element + ": a joint has no " + quantity_name(q) + " (give a body)");
            return;
        }
        if (q != Quantity::Position && q != Quantity::Velocity && q != Quantity::Orientation && q != Quantity::AngularVelocity) {
            fail(line, element + ": a body's " + quantity_name(q) +
                           " is not measured (position, velocity, orientation or angular_velocity)");
            return;
        }
        if (q == Quantity::Orientation) {
            if (!axis.empty()) fail(line, element + ": an orientation has a component (w, x, y or z), not an axis");
            if (has_point) fail(line, element + ": an orientation is the body's, not a point's");
            static const char* names[] = {"w", "x", "y", "z"};
            for (int k = 0; k < 4; ++k)
                if (comp == names[k]) component = k;
            if (component < 0) fail(line, element + ": orientation component must be w, x, y or z (got '" + comp + "')");
            return;
        }
        if (!comp.empty()) fail(line, element + ": a body's " + quantity_name(q) + " has an axis (x, y or z), not a component");
        static const char* names[] = {"x", "y", "z"};
        for (int k = 0; k < 3; ++k)
            if (axis == names[k]) component = k;
        if (component < 0) fail(line, element + ": axis must be x, y or z (got '" + axis + "')");
        if (!has_point) return;
        if (q == Quantity::AngularVelocity) {
            fail(line, element + ": an angular velocity is the body's, not a point's");
            return;
        }
        std::istringstream in(n.attribute("point").value());
        std::string word;
        int count = 0;
        bool ok = true;
        while (in >> word) {
            double v = 0;
            if (count < 3 && parse_xml_number(word.c_str(), v)) point[size_t(count)] = v;
            else ok = false;
            ++count;
        }
        if (!ok || count != 3)
            fail(line, element + ": point must be three finite numbers in metres, body frame (got '" +
                           std::string(n.attribute("point").value()) + "')");
    }

    const std::string& text_;
    XmlLines lines_;
    Experiment exp_;
    std::string errors_;
    int first_line_ = 0;
    int trials_used_line = 0;
};

}  // namespace

Experiment parse_experiment(const std::string& text, const std::string& path) { return Parser(text, path).run(); }

Experiment load_experiment(const std::string& path) {
    std::string text;
    std::string why;
    if (!read_text_file(path, text, &why))
        throw Error(MBX_ERROR_IO, Subject::model("experiment"), "cannot read the experiment file '" + path + "': " + why, path);
    return parse_experiment(text, path);
}

}  // namespace mbx::calibration
