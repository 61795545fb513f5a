// description.xml: the input description file with what calibration
// identified written into it, edited in place with pugixml so that
// everything it does not change (comments, drives, motions, other joints,
// the layout) comes through as the user wrote it.
#include <pugixml.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <vector>

#include "calibration/outputs/calibration_files.h"
#include "calibration/outputs/calibration_files_detail.h"
#include "core/finding.h"
#include "core/mechatronics/drive.h"
#include "core/mechatronics/xml_text.h"
#include "core/report/json_writer.h"
#include "core/translator/mechanism.h"

namespace mbx::calibration {

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& file, int line, const std::string& message) {
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(""), message, file, line);
}

// Shortest text that reads back as exactly `v` (locale-independent), so the
// calibrated model is the one whose errors the report gives.
std::string number_text(double v) {
    std::string s;
    append_json_number(s, v);
    return s;
}

// Numbers separated by blanks, each as number_text writes it.
template <class V> std::string numbers_text(const V& v) {
    std::string s;
    for (Eigen::Index k = 0; k < v.size(); ++k) s += (k ? " " : "") + number_text(v[k]);
    return s;
}

// The SI factor of a description file's position unit; false if unknown.
bool unit_factor(const std::string& unit, double& factor) {
    factor = 1;
    if (unit.empty() || unit == "rad" || unit == "m") return true;
    if (unit == "deg") factor = M_PI / 180;
    else if (unit == "mm") factor = 1e-3;
    else return false;
    return true;
}

// An XML comment may not hold "--" nor end in "-".
std::string comment_text(std::string s) {
    for (size_t i; (i = s.find("--")) != std::string::npos;) s.replace(i, 2, "- -");
    if (!s.empty() && s.back() == '-') s += ' ';
    return s;
}

// The element's primitive attribute as JointRef has it (-1: absent).
int primitive_of(const pugi::xml_node& n) {
    const pugi::xml_attribute a = n.attribute("primitive");
    return a ? a.as_int(-1) : -1;
}

// The <joint> or <drive> element of the root for a constraint and primitive:
// one naming this primitive, else one naming none (the constraint's only
// prismatic or revolute primitive).
pugi::xml_node find_element(const pugi::xml_node& root, const char* element, const std::string& constraint,
                            int primitive) {
    pugi::xml_node loose;
    for (pugi::xml_node n : root.children(element)) {
        if (constraint != n.attribute("constraint").as_string()) continue;
        const int p = primitive_of(n);
        if (p == primitive && p >= 0) return n;
        if (p < 0 && !loose) loose = n;
    }
    return loose;
}

// Sets a coefficient, or removes it when 0 (its meaning when absent).
void set_or_remove(pugi::xml_node n, const char* name, double v) {
    if (v == 0) {
        n.remove_attribute(name);
        return;
    }
    pugi::xml_attribute a = n.attribute(name);
    if (!a) a = n.append_attribute(name);
    a.set_value(number_text(v).c_str());
}

void set_always(pugi::xml_node n, const char* name, double v) {
    pugi::xml_attribute a = n.attribute(name);
    if (!a) a = n.append_attribute(name);
    a.set_value(number_text(v).c_str());
}

// Writes `d` into a <joint> element. Coefficients are per rad or per m
// whatever the element's unit; positions and speeds are in its unit.
// Limits stay as they were: calibration does not identify them.
void write_joint(pugi::xml_node n, const sim::JointDynamics& d, const std::string& file, int line) {
    const std::string unit = n.attribute("unit").as_string();
    double f = 1;
    if (!unit_factor(unit, f)) fail(file, line, "unit '" + unit + "' is not rad, deg, m or mm");
    const double values[] = {d.damping, d.coulomb, d.coulomb_velocity, d.damping_negative, d.coulomb_negative,
                             d.stribeck, d.stribeck_velocity, d.offset, d.stiffness, d.rest, d.armature};
    for (double v : values)
        if (!std::isfinite(v)) fail(file, line, "a calibrated joint dynamics value is not finite");
    set_or_remove(n, "damping", d.damping);
    set_or_remove(n, "coulomb", d.coulomb);
    set_or_remove(n, "coulomb_velocity", d.coulomb_velocity / f);
    if (d.asymmetric) {
        // 0 is meaningful here (no friction that way), so it is written.
        set_always(n, "coulomb_negative", d.coulomb_negative);
        set_always(n, "damping_negative", d.damping_negative);
    } else {
        n.remove_attribute("coulomb_negative");
        n.remove_attribute("damping_negative");
    }
    set_or_remove(n, "stribeck", d.stribeck);
    set_or_remove(n, "stribeck_velocity", d.stribeck_velocity / f);
    set_or_remove(n, "offset", d.offset);
    set_or_remove(n, "stiffness", d.stiffness);
    set_or_remove(n, "rest", d.rest / f);
    set_or_remove(n, "armature", d.armature);
}

// Writes an elastic transmission as the <joint>'s <transmission> child
// (replacing one it had): coefficients per rad or m, the backlash in the
// joint's unit.
void write_transmission(pugi::xml_node joint, const sim::Transmission& t, const std::string& file, int line) {
    const std::string unit = joint.attribute("unit").as_string();
    double f = 1;
    if (!unit_factor(unit, f)) fail(file, line, "unit '" + unit + "' is not rad, deg, m or mm");
    for (double v : {t.stiffness, t.damping, t.motor_inertia, t.backlash})
        if (!std::isfinite(v) || v < 0) fail(file, line, "a calibrated transmission value is not finite and positive");
    pugi::xml_node n = joint.child("transmission");
    if (!n) {
        // A self-closed joint opens: its transmission on a line of its own.
        joint.append_child(pugi::node_pcdata).set_value("\n    ");
        n = joint.append_child("transmission");
        joint.append_child(pugi::node_pcdata).set_value("\n  ");
    }
    set_or_remove(n, "stiffness", t.stiffness);
    set_or_remove(n, "damping", t.damping);
    set_always(n, "motor_inertia", t.motor_inertia);
    set_or_remove(n, "backlash", t.backlash / f);
}

// What the file's comment says mbx calibrate changed.
std::string summary(const sim::Model& model, const CalibrationResult& r, bool described,
                    const std::vector<std::string>& notes) {
    std::ostringstream s;
    s << " Calibrated by mbx calibrate (docs/calibration.md)";
    if (!r.record_paths.empty()) {
        s << " from";
        for (size_t i = 0; i < r.record_paths.size(); ++i)
            s << (i ? ", " : " ") << fs::path(r.record_paths[i]).lexically_normal().string() << " (" << detail::role_name(r.record_roles[i]) << ")";
    }
    s << ".";
    if (!described)
        s << " There was no input description, so this file holds joint dynamics only: drives were not described"
             " (add them, docs/mechatronics.md, for closed-loop runs).";
    for (const JointUpdate& u : r.joints) {
        s << "\n     joint " << u.name << " (" << u.constraint_id << "): ";
        for (size_t i = 0; i < u.causes.size(); ++i) s << (i ? ", " : "") << u.causes[i];
        if (u.causes.empty()) s << "unchanged causes";
    }
    for (const DriveUpdate& d : r.drives)
        s << "\n     drive " << d.name << " (" << d.constraint_id << "): controller delay " << number_text(d.delay_before)
          << " s -> " << number_text(d.delay_after) << " s";
    for (const BodyUpdate& b : r.bodies) {
        const BodyCorrection& c = b.correction;
        s << "\n     body " << b.name << " (" << b.id << "):";
        if (c.mass_scale != 1) s << " mass and inertia times " << number_text(c.mass_scale);
        if (!c.com_shift.isZero(0))
            s << " centre of mass moved by (" << number_text(c.com_shift[0]) << ", " << number_text(c.com_shift[1])
              << ", " << number_text(c.com_shift[2]) << ") m";
        if (!c.inertia_change.isZero(0)) s << " inertia about it changed by " << numbers_text(c.inertia_change) << " kg m^2";
    }
    if (r.mounting_tilted)
        s << "\n     mounting tilted by " << number_text(r.mounting_tilt[0] * 180 / M_PI) << " deg about x and "
          << number_text(r.mounting_tilt[1] * 180 / M_PI) << " deg about y (gravity turned in the base frame)";
    for (const std::string& n : notes) s << "\n     " << n;
    for (const UnwrittenCause& u : r.unwritten) {
        const SelectedCause& c = r.identification.causes[size_t(u.cause)];
        const detail::CauseSubject subject = detail::cause_subject(model, c.candidate);
        s << "\n     not in this file: " << c.candidate.cause << " on " << subject.kind << " " << subject.name << " ("
          << subject.id << "): " << u.reason;
    }
    s << "\n";
    return comment_text(s.str());
}

// Inserts a new element after `anchor`, on a line of its own with the
// file's indentation.
pugi::xml_node insert_element(pugi::xml_node root, pugi::xml_node anchor, const char* name) {
    pugi::xml_node n = root.insert_child_after(name, anchor);
    root.insert_child_before(pugi::node_pcdata, n).set_value("\n  ");
    return n;
}

// The last child of `root` that is not text (an element or a comment).
pugi::xml_node last_non_text(const pugi::xml_node& root) {
    for (pugi::xml_node n = root.last_child(); n; n = n.previous_sibling())
        if (n.type() != pugi::node_pcdata && n.type() != pugi::node_cdata) return n;
    return {};
}

}  // namespace

std::string calibrated_description(const Mechanism& mechanism, const sim::Model& model,
                                   const CalibrationResult& r, const std::string& input) {
    detail::check_result(model, r);
    pugi::xml_document doc;
    const bool described = !input.empty();
    const std::string file = described ? input : std::string("description.xml");
    pugi::xml_node root;
    if (described) {
        std::string text;
        std::string why;
        if (!read_text_file(input, text, &why))
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(""), "cannot read the description file '" + input + "': " + why,
                        input);
        const XmlLines lines(text);
        const pugi::xml_parse_result parsed =
            doc.load_buffer(text.data(), text.size(), pugi::parse_full | pugi::parse_ws_pcdata);
        if (!parsed) fail(input, lines.line_at(parsed.offset), std::string("not well-formed XML: ") + parsed.description());
        root = doc.document_element();
        if (std::string(root.name()) != "mechatronics")
            fail(input, lines.line(root), "the root element must be <mechatronics>");
        // Libraries are named relative to the input file; the output lives
        // elsewhere, so they become absolute.
        const fs::path base = fs::absolute(fs::path(input)).parent_path();
        for (pugi::xml_node lib : root.children("library")) {
            pugi::xml_attribute a = lib.attribute("file");
            const std::string path = a.as_string();
            if (!a || path.empty() || fs::path(path).is_absolute()) continue;
            a.set_value((base / path).lexically_normal().string().c_str());
        }
    } else {
        root = doc.append_child("mechatronics");
        root.append_attribute("version") = "1";
        root.append_child(pugi::node_pcdata).set_value("\n");
    }

    // The comment leads the root's content so a reader sees it first.
    pugi::xml_node comment = root.prepend_child(pugi::node_comment);
    std::vector<std::string> notes;
    root.insert_child_before(pugi::node_pcdata, comment).set_value("\n  ");

    pugi::xml_node last_joint;
    for (pugi::xml_node n : root.children("joint")) last_joint = n;
    for (const JointUpdate& u : r.joints) {
        int primitive = u.primitive;
        if (u.mechanism_joint >= 0 && size_t(u.mechanism_joint) < mechanism.joints.size())
            primitive = mechanism.joints[size_t(u.mechanism_joint)].primitive_index;
        pugi::xml_node n = find_element(root, "joint", u.constraint_id, primitive);
        if (!n) {
            n = insert_element(root, last_joint ? last_joint : last_non_text(root), "joint");
            n.append_attribute("constraint") = u.constraint_id.c_str();
            n.append_attribute("primitive") = primitive;
            last_joint = n;
        }
        write_joint(n, u.after, file, 0);
        if (u.transmission_after) write_transmission(n, *u.transmission_after, file, 0);
    }
    for (const DriveUpdate& d : r.drives) {
        const Drive& drive = model.drives[size_t(d.drive)];
        ControllerSpec c = drive.spec.controller;
        c.delay = d.delay_after;
        if (!std::isfinite(d.delay_after) || d.delay_after < 0 || !delay_in_whole_samples(c))
            fail(file, 0, "the calibrated delay " + number_text(d.delay_after) + " s of drive " + d.name +
                              " is not a whole number of its controller's sample periods");
        pugi::xml_node n = described ? find_element(root, "drive", d.constraint_id, drive.spec.joint.primitive)
                                     : pugi::xml_node();
        pugi::xml_node controller = n.child("controller");
        if (!controller) {
            // The drive came from elsewhere (the C API): the delay is in the
            // comment rather than lost with the other files.
            if (described)
                notes.push_back("drive " + d.name + " (" + d.constraint_id +
                                ") is not in this file: set its controller delay by hand");
            continue;
        }
        set_or_remove(controller, "delay", d.delay_after);
    }

    // Body mass corrections compound with the input's (the model calibrated already carried them).
    pugi::xml_node last_body;
    for (pugi::xml_node n : root.children("body")) last_body = n;
    for (const BodyUpdate& b : r.bodies) {
        const BodyCorrection& c = b.correction;
        if (!(std::isfinite(c.mass_scale) && c.mass_scale > 0))
            fail(file, 0, "the calibrated mass factor " + number_text(c.mass_scale) + " of body " + b.name + " is not positive");
        if (!c.com_shift.allFinite() || !c.inertia_change.allFinite())
            fail(file, 0, "the calibrated centre of mass or inertia of body " + b.name + " is not finite");
        pugi::xml_node n;
        for (pugi::xml_node e : root.children("body"))
            if (b.id == e.attribute("id").as_string()) n = e;
        BodyCorrection total = c;
        if (n) {
            // (the description was read already: its values are well formed)
            BodyCorrection given;
            given.mass_scale = n.attribute("mass_scale").as_double(1.0);
            parse_xml_numbers(n.attribute("com_shift").as_string("0 0 0"), 3, given.com_shift.data());
            parse_xml_numbers(n.attribute("inertia_change").as_string("0 0 0 0 0 0"), 6, given.inertia_change.data());
            total = c.after(given);
        } else {
            pugi::xml_node anchor = last_body ? last_body : last_joint ? last_joint : last_non_text(root);
            n = insert_element(root, anchor, "body");
            n.append_attribute("id") = b.id.c_str();
            last_body = n;
        }
        set_always(n, "mass_scale", total.mass_scale);
        if (!total.com_shift.isZero(0)) n.remove_attribute("com_shift"), n.append_attribute("com_shift") = numbers_text(total.com_shift).c_str();
        if (!total.inertia_change.isZero(0))
            n.remove_attribute("inertia_change"), n.append_attribute("inertia_change") = numbers_text(total.inertia_change).c_str();
    }

    // A mounting tilt adds to the input's <mounting> (small angles), in its unit.
    if (r.mounting_tilted) {
        if (!r.mounting_tilt.allFinite()) fail(file, 0, "the calibrated mounting tilt is not finite");
        pugi::xml_node n = root.child("mounting");
        if (!n) {
            n = insert_element(root, last_non_text(root), "mounting");
            n.append_attribute("unit") = "deg";
        }
        const double to_unit = std::string(n.attribute("unit").as_string("rad")) == "deg" ? 180 / M_PI : 1.0;
        set_always(n, "tilt_x", n.attribute("tilt_x").as_double(0) + r.mounting_tilt[0] * to_unit);
        set_always(n, "tilt_y", n.attribute("tilt_y").as_double(0) + r.mounting_tilt[1] * to_unit);
    }

    for (const std::string& n : write_contact_update(root, r.contact, file)) notes.push_back(n);

    comment.set_value(summary(model, r, described, notes).c_str());

    std::ostringstream out;
    if (!described) out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    // Raw, so the root's content keeps the input's own layout; pugixml drops
    // the line breaks between top-level nodes (declaration, comments, root),
    // so those go back one per line.
    for (pugi::xml_node n : doc.children()) {
        if (n.type() == pugi::node_pcdata) continue;
        n.print(out, "  ", pugi::format_raw, pugi::encoding_utf8);
        out << '\n';
    }
    return out.str();
}

}  // namespace mbx::calibration
