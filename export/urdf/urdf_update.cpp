#include "export/urdf/urdf_update.h"

#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>

#include "core/mechatronics/body_mass.h"
#include "core/mechatronics/xml_text.h"
#include "core/translator/mechanism.h"
#include "export/urdf/xml_source_edits.h"

namespace mbx {

namespace {

// Shortest text that reads back as exactly `v`; `scale` is the size of the
// quantity it belongs to, below 1e-14 of which a value is rounding noise
// of the axes' turn and is written as 0.
std::string exact_text(double v, double scale) {
    if (std::fabs(v) <= 1e-14 * scale) v = 0;
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string vector_text(const Vec3& v, double scale) {
    return exact_text(v.x(), scale) + " " + exact_text(v.y(), scale) + " " + exact_text(v.z(), scale);
}

// URDF's rpy: fixed-axis roll about x, pitch about y, yaw about z.
Mat3 rpy_rotation(const Vec3& rpy) {
    return (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
            Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
        .toRotationMatrix();
}

bool differs(double a, double b, double scale) { return std::fabs(a - b) > 1e-12 * scale; }

struct MassProperties {
    double mass = 0;
    Vec3 com = Vec3::Zero();
    Mat3 inertia = Mat3::Zero();  // about com
};

// The inertia entries in URDF's attribute order and their matrix places.
struct Entry {
    const char* name;
    int r, c;
};
constexpr Entry kInertiaEntries[] = {{"ixx", 0, 0}, {"ixy", 0, 1}, {"ixz", 0, 2},
                                     {"iyy", 1, 1}, {"iyz", 1, 2}, {"izz", 2, 2}};

class Updater {
public:
    Updater(ExportModel& model, std::string_view text, const std::string& file)
        : model_(model), m_(model.mechanism()), text_(text), file_(file), edits_(text) {}

    UrdfUpdate run() {
        const pugi::xml_parse_result parsed =
            doc_.load_buffer(text_.data(), text_.size(), pugi::parse_default, pugi::encoding_utf8);
        if (!parsed) fail(Subject::model(""), line_at(size_t(parsed.offset)), std::string("not well-formed XML: ") + parsed.description());
        robot_ = doc_.document_element();
        if (std::string(robot_.name()) != "robot") fail(Subject::model(""), edits_.line_of(robot_), "the root element is <" + std::string(robot_.name()) + ">, not <robot>: not a URDF");
        for (pugi::xml_node n : robot_.children("link")) links_.emplace(n.attribute("name").as_string(), n);
        for (pugi::xml_node n : robot_.children("joint")) joints_.emplace(n.attribute("name").as_string(), n);
        UrdfUpdate out;
        for (size_t j = 0; j < m_.joints.size(); ++j) out.joints_changed += update_joint(int(j)) ? 1 : 0;
        for (size_t b = 0; b < m_.bodies.size(); ++b) out.links_changed += update_body(int(b));
        out.text = edits_.apply();
        return out;
    }

private:
    [[noreturn]] void fail(const Subject& subject, int line, const std::string& message) const {
        throw Error(MBX_ERROR_INVALID_INPUT, subject, message, file_, line);
    }
    int line_at(size_t offset) const {
        offset = std::min(offset, text_.size());
        return 1 + int(std::count(text_.begin(), text_.begin() + ptrdiff_t(offset), '\n'));
    }
    double number(const pugi::xml_node& e, const char* name, double fallback, const Subject& who) const {
        const pugi::xml_attribute a = e.attribute(name);
        if (!a) return fallback;
        double v = 0;
        if (!parse_xml_number(a.value(), v))
            fail(who, edits_.line_of(e), "<" + std::string(e.name()) + "> " + name + " is not a number");
        return v;
    }
    Vec3 vector(const pugi::xml_node& e, const char* name, const Subject& who) const {
        Vec3 v = Vec3::Zero();
        const pugi::xml_attribute a = e.attribute(name);
        if (a && !parse_xml_numbers(a.value(), 3, v.data()))
            fail(who, edits_.line_of(e), "<" + std::string(e.name()) + "> " + name + " is not three numbers");
        return v;
    }

    // <dynamics> of a revolute or prismatic tree joint that has joint dynamics.
    bool update_joint(int j) {
        const Joint& joint = m_.joints[size_t(j)];
        if (joint.cut || (joint.type != MBX_PRIMITIVE_REVOLUTE && joint.type != MBX_PRIMITIVE_PRISMATIC)) return false;
        const ResolvedJointDynamics* jd = model_.joint_dynamics_of(j);
        if (!jd) return false;
        const Constraint& constraint = m_.assembly.constraints[size_t(joint.constraint)];
        if (constraint.chain.size() != 1) return false;  // planar, floating: one <dynamics> for several freedoms
        const Subject who = model_.joint_subject(j);
        const auto found = joints_.find(constraint.id);
        if (found == joints_.end())
            fail(who, 0, "joint '" + constraint.id + "' of the mechanism is not in this file: not the URDF it was read from");
        const pugi::xml_node xj = found->second;
        note_unheld(j, *jd, who);
        const double damping = jd->symmetric_damping(), friction = jd->symmetric_coulomb();
        const pugi::xml_node dyn = xj.child("dynamics");
        const double scale = std::max({std::fabs(damping), std::fabs(friction), 1e-300});
        const double was_damping = dyn ? number(dyn, "damping", 0, who) : 0;
        const double was_friction = dyn ? number(dyn, "friction", 0, who) : 0;
        const bool new_damping = differs(damping, was_damping, std::max(scale, std::fabs(was_damping)));
        const bool new_friction = differs(friction, was_friction, std::max(scale, std::fabs(was_friction)));
        if (!new_damping && !new_friction) return false;
        if (!dyn) {
            edits_.insert_first_child(xj, "<dynamics damping=\"" + exact_text(damping, 0) + "\" friction=\"" +
                                              exact_text(friction, 0) + "\"/>");
            return true;
        }
        if (new_damping) edits_.set_attribute(dyn, "damping", exact_text(damping, 0));
        if (new_friction) edits_.set_attribute(dyn, "friction", exact_text(friction, 0));
        return true;
    }

    void note_unheld(int j, const ResolvedJointDynamics& jd, const Subject& who) {
        std::string lost;
        const auto add = [&lost](const std::string& what) { lost += (lost.empty() ? "" : ", ") + what; };
        if (jd.armature > 0) add("armature " + exact_text(jd.armature, 0));
        if (jd.stiffness > 0) add("spring stiffness " + exact_text(jd.stiffness, 0));
        if (const std::string beyond = joint_dynamics_beyond_symmetric(jd); !beyond.empty()) add(beyond);
        if (lost.empty()) return;
        model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, who,
                    "URDF <dynamics> holds one damping and one friction level: joint '" + m_.joints[size_t(j)].name +
                        "' keeps its " + lost + " only in the description file");
    }

    // The parts of body b that carry mass, with their pose in the body frame.
    struct Share {
        int part = -1;
        Pose in_body;
    };

    int update_body(int b) {
        const RigidBody& body = m_.bodies[size_t(b)];
        if (body.kind != MBX_RIGID_BODY_DYNAMIC || !(body.mass > 0)) return 0;
        std::vector<Share> shares;
        MassProperties sum;
        for (int p : body.parts) {
            const Part& part = m_.assembly.parts[size_t(p)];
            if (!(part.mass > 0) || part.is_ground()) continue;
            shares.push_back({p, body.pose.inverse() * part.pose});
            sum.mass += part.mass;
            sum.com += part.mass * shares.back().in_body.apply(part.com);
        }
        if (shares.empty()) return 0;
        sum.com /= sum.mass;
        for (const Share& s : shares) {
            const Part& part = m_.assembly.parts[size_t(s.part)];
            const Mat3& R = s.in_body.rotation;
            const Vec3 r = s.in_body.apply(part.com) - sum.com;
            sum.inertia += R * part.inertia * R.transpose() + part.mass * (r.dot(r) * Mat3::Identity() - r * r.transpose());
        }
        const double size = std::sqrt(std::max(sum.inertia.trace(), 0.0) / sum.mass) + sum.com.norm();
        const double inertia_scale = std::max(sum.inertia.cwiseAbs().maxCoeff(), 1e-300);
        const bool same = std::fabs(body.mass - sum.mass) <= 1e-9 * sum.mass &&
                          (body.com - sum.com).norm() <= 1e-9 * size &&
                          (body.inertia - sum.inertia).cwiseAbs().maxCoeff() <= 1e-9 * inertia_scale;
        for (const Share& s : shares) check_link(s.part);
        if (same) return 0;

        // The body's correction relative to its links, shared out so that the
        // links add up to the body again: every mass scaled alike and moved
        // alike keeps their spread, so the inertia about the centre of mass
        // scales with them; the rest of the change goes to one link.
        const double scale = body.mass / sum.mass;
        const Vec3 shift = body.com - sum.com;
        const Mat3 change = body.inertia - scale * sum.inertia;
        size_t receiver = 0;
        for (size_t k = 1; k < shares.size(); ++k)
            if (m_.assembly.parts[size_t(shares[k].part)].mass > m_.assembly.parts[size_t(shares[receiver].part)].mass)
                receiver = k;
        for (size_t k = 0; k < shares.size(); ++k) {
            const Part& part = m_.assembly.parts[size_t(shares[k].part)];
            const Mat3& R = shares[k].in_body.rotation;
            MassProperties now;
            now.mass = scale * part.mass;
            now.com = part.com + R.transpose() * shift;
            now.inertia = scale * part.inertia;
            if (k == receiver) now.inertia += R.transpose() * change * R;
            write_inertial(shares[k].part, now, b);
        }
        return int(shares.size());
    }

    // The file's link has the mass the mechanism's part was read with.
    void check_link(int p) const {
        const Part& part = m_.assembly.parts[size_t(p)];
        const Subject who = Subject::body(part.id, part.name);
        const auto found = links_.find(part.id);
        if (found == links_.end())
            fail(who, 0, "link '" + part.id + "' of the mechanism is not in this file: not the URDF it was read from");
        const pugi::xml_node inertial = found->second.child("inertial");
        const double mass = inertial ? number(inertial.child("mass"), "value", 0, who) : 0;
        if (std::fabs(mass - part.mass) > 1e-9 * part.mass)
            fail(who, edits_.line_of(found->second),
                 "link '" + part.id + "' has mass " + exact_text(mass, 0) + " kg here but " +
                     exact_text(part.mass, 0) + " kg in the mechanism: not the URDF it was read from");
    }

    void write_inertial(int p, const MassProperties& now, int b) {
        const Part& part = m_.assembly.parts[size_t(p)];
        const Subject who = Subject::body(part.id, part.name);
        const pugi::xml_node link = links_.at(part.id);
        const pugi::xml_node inertial = link.child("inertial");
        if (const std::string why = implausible_inertia(now.inertia); !why.empty())
            fail(Subject::rigid_body(m_.bodies[size_t(b)].id, m_.bodies[size_t(b)].name), edits_.line_of(inertial),
                 "link '" + part.id + "' would take the inertia change of body '" + m_.bodies[size_t(b)].name +
                     "', but then " + why);

        const pugi::xml_node mass = inertial.child("mass");
        const double was_mass = number(mass, "value", 0, who);
        if (differs(now.mass, was_mass, now.mass)) edits_.set_attribute(mass, "value", exact_text(now.mass, 0));

        const pugi::xml_node origin = inertial.child("origin");
        const Mat3 axes = origin ? rpy_rotation(vector(origin, "rpy", who)) : Mat3::Identity();
        const Vec3 was_com = origin ? vector(origin, "xyz", who) : Vec3::Zero();
        const double size = std::sqrt(std::max(now.inertia.trace(), 0.0) / now.mass) + now.com.norm();
        if ((now.com - was_com).cwiseAbs().maxCoeff() > 1e-12 * size) {
            if (origin) edits_.set_attribute(origin, "xyz", vector_text(now.com, size));
            else edits_.insert_first_child(inertial, "<origin xyz=\"" + vector_text(now.com, size) + "\" rpy=\"0 0 0\"/>");
        }

        // The file's numbers are about the inertial's own axes.
        const Mat3 in_axes = axes.transpose() * now.inertia * axes;
        const pugi::xml_node inertia = inertial.child("inertia");
        const double scale = std::max(in_axes.cwiseAbs().maxCoeff(), 1e-300);
        if (!inertia) {
            std::string element = "<inertia";
            for (const Entry& e : kInertiaEntries)
                element += std::string(" ") + e.name + "=\"" + exact_text(in_axes(e.r, e.c), scale) + "\"";
            edits_.insert_first_child(inertial, element + "/>");
            return;
        }
        for (const Entry& e : kInertiaEntries) {
            const double v = in_axes(e.r, e.c);
            if (differs(v, number(inertia, e.name, 0, who), scale))
                edits_.set_attribute(inertia, e.name, exact_text(v, scale));
        }
    }

    ExportModel& model_;
    const Mechanism& m_;
    std::string_view text_;
    std::string file_;
    XmlSourceEdits edits_;
    pugi::xml_document doc_;
    pugi::xml_node robot_;
    std::map<std::string, pugi::xml_node> links_, joints_;
};

}  // namespace

UrdfUpdate update_urdf(ExportModel& model, std::string_view urdf, const std::string& file) {
    return Updater(model, urdf, file).run();
}

}  // namespace mbx
