#include "core/mechatronics/drive_file.h"

#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <unordered_map>
#include <stdexcept>

#include "core/input_file.h"
#include "core/mechatronics/xml_text.h"
#include "core/text_format.h"

namespace mbx {

namespace {

// Attributes each element may carry: anything else is a typo a user wants to
// hear about (a misspelt "kd" silently meaning 0 is a bad afternoon).
const std::map<std::string, std::set<std::string>>& allowed_attributes() {
    static const std::map<std::string, std::set<std::string>> table = {
        {"mechatronics", {"version"}},
        {"library", {"file"}},
        {"drive", {"name", "constraint", "primitive", "joint_name", "motor", "transmission"}},
        {"override", {"name", "value"}},
        {"amplifier", {"mode", "gain"}},
        {"controller", {"kp", "ki", "kd", "kv", "kvi", "sample_period", "delay", "output_limit", "velocity_estimate"}},
        {"motion", {"interpolation", "unit"}},
        {"point", {"t", "q"}},
        {"joint", {"constraint", "primitive", "damping", "coulomb", "coulomb_velocity", "stiffness", "rest", "armature",
                   "lower", "upper", "unit", "offset", "coulomb_negative", "damping_negative", "stribeck",
                   "stribeck_velocity"}},
        {"transmission", {"stiffness", "damping", "motor_inertia", "backlash"}},
        {"body", {"id", "mass_scale", "com_shift", "inertia_change"}},
        {"mounting", {"tilt_x", "tilt_y", "unit"}},
    };
    return table;
}

double motion_unit_factor(const std::string& unit, bool& known) {
    known = true;
    if (unit.empty() || unit == "rad" || unit == "m") return 1;
    if (unit == "deg") return M_PI / 180;
    if (unit == "mm") return 1e-3;
    known = false;
    return 1;
}

class Reader {
public:
    Reader(const std::string& text, const std::string& file, const std::string& base_dir, MechatronicSpec& spec,
           std::vector<DriveError>& errors)
        : text_(text), file_(file), base_dir_(base_dir), lines_(text), spec_(spec), errors_(errors) {}

    void read() {
        pugi::xml_document doc;
        const pugi::xml_parse_result parsed = doc.load_buffer(text_.data(), text_.size(), pugi::parse_default);
        if (!parsed) {
            errors_.push_back({file_, lines_.line_at(parsed.offset), "",
                               std::string("not well-formed XML: ") + parsed.description()});
            return;
        }
        const pugi::xml_node root = doc.document_element();
        if (std::string(root.name()) != "mechatronics") {
            errors_.push_back({file_, lines_.line(root), "", "the root element must be <mechatronics>"});
            return;
        }
        check_attributes(root, "");
        const std::string version = root.attribute("version").as_string("1");
        if (version != "1") error(root, "", "unsupported version '" + version + "' (this mbx reads version 1)");
        spec_.drives.reserve(spec_.drives.size() +
                             size_t(std::distance(root.children("drive").begin(), root.children("drive").end())));
        for (pugi::xml_node n : root.children()) {
            if (n.type() != pugi::node_element) continue;
            const std::string name = n.name();
            if (name == "library") library(n);
            else if (name == "drive") drive(n);
            else if (name == "joint") joint(n);
            else if (name == "body") body(n);
            else if (name == "mounting") mounting(n);
            else if (name == "collision" || name == "contact") read_contact_element(n, lines_, file_, spec_.contact, errors_);
            else error(n, "", "unknown element <" + name + "> (library, drive, joint, body, mounting, collision, contact)");
        }
    }

private:
    void error(const pugi::xml_node& at, const std::string& who, std::string message) {
        errors_.push_back({file_, lines_.line(at), who, std::move(message)});
        bad_ = true;
    }

    void check_attributes(const pugi::xml_node& n, const std::string& who) {
        const auto it = allowed_attributes().find(n.name());
        for (pugi::xml_attribute a : n.attributes())
            if (it == allowed_attributes().end() || !it->second.count(a.name()))
                error(n, who, "unknown attribute '" + std::string(a.name()) + "' on <" + n.name() + ">");
    }

    // A number attribute; `fallback` when absent.
    double number(const pugi::xml_node& n, const char* name, double fallback, const std::string& who) {
        const pugi::xml_attribute a = n.attribute(name);
        if (!a) return fallback;
        double v = 0;
        if (!parse_xml_number(a.as_string(), v)) {
            error(n, who, std::string(name) + " = '" + a.as_string() + "' is not a number");
            return fallback;
        }
        return v;
    }

    // `count` numbers in one attribute ("dx dy dz"); left as they are when absent.
    void numbers(const pugi::xml_node& n, const char* name, size_t count, double* out, const std::string& who) {
        const pugi::xml_attribute a = n.attribute(name);
        if (!a) return;
        std::vector<double> v(count);
        if (!parse_xml_numbers(a.as_string(), count, v.data())) {
            error(n, who, std::string(name) + " = '" + a.as_string() + "' is not " + std::to_string(count) +
                              " numbers");
            return;
        }
        std::copy(v.begin(), v.end(), out);
    }

    void library(const pugi::xml_node& n) {
        check_attributes(n, "");
        const std::string path = n.attribute("file").as_string();
        if (path.empty()) {
            error(n, "", "<library> needs a file attribute");
            return;
        }
        const std::string full = path[0] == '/' || base_dir_.empty() ? path : base_dir_ + "/" + path;
        if (const std::string why = input_file_problem(full); !why.empty()) {
            error(n, "", "cannot read the object library '" + full + "': " + why);
            return;
        }
        spec_.library.load_file(full);
    }

    void drive(const pugi::xml_node& n) {
        bad_ = false;
        DriveSpec d;
        d.file = file_;
        d.line = lines_.line(n);
        d.name = n.attribute("name").as_string();
        d.joint.constraint_id = n.attribute("constraint").as_string();
        const std::string who = !d.name.empty() ? d.name : !d.joint.constraint_id.empty() ? d.joint.constraint_id
                                                                                            : "<drive>";
        check_attributes(n, who);
        if (d.joint.constraint_id.empty()) error(n, who, "drive has no constraint (the CAD joint's stable id)");
        d.joint.primitive = primitive(n, who);
        d.motor_id = n.attribute("motor").as_string();
        if (d.motor_id.empty()) error(n, who, "drive has no motor (a library object ID)");
        d.transmission_id = n.attribute("transmission").as_string();

        int amplifiers = 0, controllers = 0, motions = 0;
        for (pugi::xml_node c : n.children()) {
            if (c.type() != pugi::node_element) continue;
            const std::string name = c.name();
            check_attributes(c, who);
            if (name == "override") {
                const std::string param = c.attribute("name").as_string();
                if (param.empty()) error(c, who, "<override> needs a name");
                else if (!c.attribute("value")) error(c, who, "override of '" + param + "' has no value");
                else if (d.overrides.count(param)) error(c, who, "parameter '" + param + "' overridden twice");
                else d.overrides[param] = number(c, "value", 0, who);
            } else if (name == "amplifier") {
                if (++amplifiers > 1) error(c, who, "more than one <amplifier>");
                const std::string mode = c.attribute("mode").as_string("voltage");
                if (mode == "voltage") d.amplifier.mode = AmplifierMode::Voltage;
                else if (mode == "current") d.amplifier.mode = AmplifierMode::Current;
                else error(c, who, "amplifier mode '" + mode + "' is neither voltage nor current");
                d.amplifier.gain = number(c, "gain", 1, who);
                if (d.amplifier.mode == AmplifierMode::Voltage && c.attribute("gain"))
                    error(c, who, "a voltage amplifier has no gain (the output is the armature voltage)");
            } else if (name == "controller") {
                if (++controllers > 1) error(c, who, "more than one <controller>");
                controller(c, who, d.controller);
            } else if (name == "motion") {
                if (++motions > 1) error(c, who, "more than one <motion>");
                motion(c, who, d);
            } else {
                error(c, who, "unknown element <" + name + "> in a drive (override, amplifier, controller, motion)");
            }
        }
        if (controllers == 0) error(n, who, "drive has no <controller>");
        const std::string key = d.joint.constraint_id + "#" + std::to_string(d.joint.primitive);
        if (const auto it = seen_.find(key); it != seen_.end() && !d.joint.constraint_id.empty())
            error(n, who, "a second drive for the same joint (the first is at line " + std::to_string(it->second) + ")");
        else seen_.emplace(key, d.line);
        if (!bad_) spec_.drives.push_back(std::move(d));
    }

    // A primitive attribute: a whole number >= 0, or -1 when absent.
    int primitive(const pugi::xml_node& n, const std::string& who) {
        if (!n.attribute("primitive")) return -1;
        const double p = number(n, "primitive", -1, who);
        if (p < 0 || p != std::floor(p) || p > 1e6) {
            error(n, who, "primitive must be a whole number >= 0");
            return -1;
        }
        return int(p);
    }

    void mounting(const pugi::xml_node& n) {
        bad_ = false;
        check_attributes(n, "<mounting>");
        for (pugi::xml_node c : n.children())
            if (c.type() == pugi::node_element)
                error(c, "<mounting>", "unknown element <" + std::string(c.name()) + "> in <mounting> (it takes attributes only)");
        const std::string unit = n.attribute("unit").as_string("rad");
        const double factor = unit == "rad" ? 1.0 : unit == "deg" ? M_PI / 180 : 0.0;
        if (factor == 0) error(n, "<mounting>", "unit = '" + unit + "' is not rad or deg");
        MountingSpec m;
        m.given = true, m.file = file_, m.line = lines_.line(n);
        m.tilt_x = number(n, "tilt_x", 0, "<mounting>") * factor;
        m.tilt_y = number(n, "tilt_y", 0, "<mounting>") * factor;
        // A few degrees is a floor out of level; beyond a right angle is no mounting tilt at all.
        for (double v : {m.tilt_x, m.tilt_y})
            if (!(std::abs(v) <= M_PI / 2)) error(n, "<mounting>", "a tilt must be finite and at most 90 degrees");
        if (spec_.mounting.given && spec_.mounting.file == file_)
            error(n, "<mounting>", "a second <mounting> (the first is at line " + std::to_string(spec_.mounting.line) + ")");
        if (!bad_) spec_.mounting = m;
    }

    void body(const pugi::xml_node& n) {
        bad_ = false;
        BodyMassSpec b;
        b.file = file_;
        b.line = lines_.line(n);
        b.body = n.attribute("id").as_string();
        const std::string who = !b.body.empty() ? b.body : "<body>";
        check_attributes(n, who);
        if (b.body.empty()) error(n, who, "body has no id (the CAD part id of the body)");
        for (pugi::xml_node c : n.children())
            if (c.type() == pugi::node_element)
                error(c, who, "unknown element <" + std::string(c.name()) + "> in a body (it takes attributes only)");
        b.mass_scale = number(n, "mass_scale", 1, who);
        if (!(b.mass_scale > 0)) error(n, who, "mass_scale must be positive");
        numbers(n, "com_shift", 3, b.com_shift.data(), who);
        numbers(n, "inertia_change", 6, b.inertia_change.data(), who);
        if (const auto it = seen_bodies_.find(b.body); it != seen_bodies_.end() && !b.body.empty())
            error(n, who, "a second <body> for the same body (the first is at line " + std::to_string(it->second) + ")");
        else seen_bodies_.emplace(b.body, b.line);
        if (!bad_) spec_.body_masses.push_back(std::move(b));
    }

    void joint(const pugi::xml_node& n) {
        bad_ = false;
        JointDynamicsSpec j;
        j.file = file_;
        j.line = lines_.line(n);
        j.joint.constraint_id = n.attribute("constraint").as_string();
        const std::string who = !j.joint.constraint_id.empty() ? j.joint.constraint_id : "<joint>";
        check_attributes(n, who);
        if (j.joint.constraint_id.empty()) error(n, who, "joint has no constraint (the CAD joint's stable id)");
        j.joint.primitive = primitive(n, who);
        j.unit = n.attribute("unit").as_string();
        bool known = true;
        const double factor = motion_unit_factor(j.unit, known);
        for (pugi::xml_node c : n.children()) {
            if (c.type() != pugi::node_element) continue;
            if (std::string(c.name()) != "transmission") {
                error(c, who, "unknown element <" + std::string(c.name()) + "> in a joint (transmission)");
                continue;
            }
            if (j.transmission) {
                error(c, who, "a second <transmission> in the joint (the first is at line " +
                                  std::to_string(j.transmission->line) + ")");
                continue;
            }
            check_attributes(c, who);
            TransmissionSpec t;
            t.line = lines_.line(c);
            // Coefficients per rad or m, as the joint's; the dead band's width in the joint's unit.
            t.stiffness = number(c, "stiffness", 0, who);
            t.damping = number(c, "damping", 0, who);
            t.motor_inertia = number(c, "motor_inertia", 0, who);
            t.backlash = number(c, "backlash", 0, who) * factor;
            if (!c.attribute("motor_inertia")) error(c, who, "transmission needs motor_inertia");
            j.transmission = t;
        }
        if (!known) error(n, who, "unit '" + j.unit + "' is not rad, deg, m or mm");
        // Positions and the regularisation speed follow `unit`; the
        // coefficients are per rad or m always, so a file never holds a
        // damping "per degree".
        j.damping = number(n, "damping", 0, who);
        j.coulomb = number(n, "coulomb", 0, who);
        j.coulomb_velocity = number(n, "coulomb_velocity", 0, who) * factor;
        if (n.attribute("coulomb_negative")) j.coulomb_negative = number(n, "coulomb_negative", 0, who);
        if (n.attribute("damping_negative")) j.damping_negative = number(n, "damping_negative", 0, who);
        j.stribeck = number(n, "stribeck", 0, who);
        j.stribeck_velocity = number(n, "stribeck_velocity", 0, who) * factor;
        j.offset = number(n, "offset", 0, who);
        j.stiffness = number(n, "stiffness", 0, who);
        j.armature = number(n, "armature", 0, who);
        j.rest = number(n, "rest", 0, who) * factor;
        for (const auto& [name, value] : joint_dynamics_coefficients(j))
            if (value < 0) error(n, who, std::string(name) + " must not be negative");
        for (const std::string& problem : joint_dynamics_problems(j)) {
            const bool of_transmission = problem.rfind("transmission", 0) == 0;
            // The transmission's problems at its own line.
            if (of_transmission && j.transmission) {
                errors_.push_back({file_, j.transmission->line, who, problem});
                bad_ = true;
            } else {
                error(n, who, problem);
            }
        }
        const bool lower = bool(n.attribute("lower")), upper = bool(n.attribute("upper"));
        if (lower != upper) {
            error(n, who, std::string("a limit needs both lower and upper (") + (lower ? "upper" : "lower") + " is missing)");
        } else if (lower) {
            j.limited = true;
            j.lower = number(n, "lower", 0, who) * factor;
            j.upper = number(n, "upper", 0, who) * factor;
            if (j.lower > j.upper)
                error(n, who, "lower = " + std::string(n.attribute("lower").as_string()) + " is above upper = " +
                                  n.attribute("upper").as_string());
        }
        const std::string key = j.joint.constraint_id + "#" + std::to_string(j.joint.primitive);
        if (const auto it = seen_joints_.find(key); it != seen_joints_.end() && !j.joint.constraint_id.empty())
            error(n, who, "a second <joint> for the same joint (the first is at line " + std::to_string(it->second) + ")");
        else seen_joints_.emplace(key, j.line);
        if (bad_) return;
        // A later description refines an earlier one (the user's file over a
        // URDF's own): its <joint> replaces what another file gave that joint.
        for (JointDynamicsSpec& earlier : spec_.joint_dynamics)
            if (earlier.file != j.file && earlier.joint.constraint_id == j.joint.constraint_id &&
                earlier.joint.primitive == j.joint.primitive) {
                earlier = std::move(j);
                return;
            }
        spec_.joint_dynamics.push_back(std::move(j));
    }

    void controller(const pugi::xml_node& c, const std::string& who, ControllerSpec& out) {
        if (!c.attribute("kp")) error(c, who, "controller needs kp");
        out.kp = number(c, "kp", 0, who);
        out.ki = number(c, "ki", 0, who);
        out.kd = number(c, "kd", 0, who);
        out.kv = number(c, "kv", 0, who);
        out.kvi = number(c, "kvi", 0, who);
        out.sample_period = number(c, "sample_period", 0, who);
        out.delay = number(c, "delay", 0, who);
        out.output_limit = number(c, "output_limit", 0, who);
        for (const auto& [name, value] : controller_values(out))
            if (value < 0) error(c, who, std::string(name) + " must not be negative");
        const std::string ve = c.attribute("velocity_estimate").as_string("measured");
        if (!parse_velocity_estimate(ve, out.velocity_estimate))
            error(c, who, "velocity_estimate '" + ve + "' is not measured, difference or filtered_difference");
        else if (out.velocity_estimate != VelocityEstimate::Measured && !(out.sample_period > 0))
            error(c, who, "velocity_estimate '" + ve + "' needs a sample_period");
        if (!delay_in_whole_samples(out))
            error(c, who, "delay must be a whole number of sample periods for a discrete controller");
    }

    void motion(const pugi::xml_node& m, const std::string& who, DriveSpec& d) {
        Interpolation interpolation = Interpolation::Linear;
        const std::string word = m.attribute("interpolation").as_string("linear");
        if (!parse_interpolation(word, interpolation))
            error(m, who, "interpolation '" + word + "' is not linear, smooth or step");
        d.motion_unit = m.attribute("unit").as_string();
        bool known = true;
        const double factor = motion_unit_factor(d.motion_unit, known);
        if (!known) error(m, who, "motion unit '" + d.motion_unit + "' is not rad, deg, m or mm");
        std::vector<MotionPoint> points;
        points.reserve(size_t(std::distance(m.children("point").begin(), m.children("point").end())));
        int elements = 0;
        for (pugi::xml_node p : m.children()) {
            if (p.type() != pugi::node_element) continue;
            ++elements;
            if (std::string(p.name()) != "point") {
                error(p, who, "unknown element <" + std::string(p.name()) + "> in a motion (point)");
                continue;
            }
            check_attributes(p, who);
            if (!p.attribute("t") || !p.attribute("q")) {
                error(p, who, "a motion point needs t and q");
                continue;
            }
            MotionPoint mp{number(p, "t", 0, who), number(p, "q", 0, who) * factor};
            if (!points.empty() && !(mp.time > points.back().time)) {
                error(p, who, "motion times must increase strictly (t = " + std::string(p.attribute("t").as_string()) +
                                  " after " + readable(points.back().time) + ")");
                continue;
            }
            points.push_back(mp);
        }
        if (elements == 0) error(m, who, "<motion> has no points");
        try {
            d.motion = MotionProfile(std::move(points), interpolation);
        } catch (const std::invalid_argument& e) {
            error(m, who, e.what());
        }
    }

    const std::string& text_;
    std::string file_, base_dir_;
    XmlLines lines_;
    MechatronicSpec& spec_;
    std::vector<DriveError>& errors_;
    std::unordered_map<std::string, int> seen_;         // joint key -> line of its drive
    std::unordered_map<std::string, int> seen_joints_;  // joint key -> line of its <joint>
    std::unordered_map<std::string, int> seen_bodies_;  // body id -> line of its <body>
    bool bad_ = false;
};

}  // namespace

bool parse_velocity_estimate(const std::string& word, VelocityEstimate& out) {
    if (word == "measured") out = VelocityEstimate::Measured;
    else if (word == "difference") out = VelocityEstimate::Difference;
    else if (word == "filtered_difference") out = VelocityEstimate::FilteredDifference;
    else return false;
    return true;
}

const char* velocity_estimate_name(VelocityEstimate v) {
    switch (v) {
    case VelocityEstimate::Difference: return "difference";
    case VelocityEstimate::FilteredDifference: return "filtered_difference";
    case VelocityEstimate::Measured: break;
    }
    return "measured";
}

void load_drive_text(const std::string& text, const std::string& file, const std::string& base_dir,
                     MechatronicSpec& spec, std::vector<DriveError>& errors) {
    Reader(text, file, base_dir, spec, errors).read();
}

void load_drive_file(const std::string& path, MechatronicSpec& spec, std::vector<DriveError>& errors) {
    std::string text;
    std::string why;
    if (!read_text_file(path, text, &why)) {
        errors.push_back({path, 0, "", "cannot read the drive description: " + why});
        return;
    }
    const size_t slash = path.find_last_of('/');
    load_drive_text(text, path, slash == std::string::npos ? "" : path.substr(0, slash), spec, errors);
}

}  // namespace mbx
