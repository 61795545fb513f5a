#include "urdf_reader.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <set>

#include <Eigen/Eigenvalues>
#include <pugixml.hpp>

#include "core/report/json_value.h"
#include "host_adapters/common/file_bytes.h"
#include "host_adapters/common/line_index.h"
#include "host_adapters/common/numbers.h"

namespace mbx_files {

Eigen::Isometry3d UrdfOrigin::pose() const {
    Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
    x.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    x.translation() = xyz;
    return x;
}

namespace {

const std::set<std::string> kJointTypes = {"revolute", "continuous", "prismatic", "fixed", "floating", "planar"};

std::string q(std::string_view s) { return "'" + std::string(s) + "'"; }

bool xml_space(char c) { return c == ' ' || c == '\n' || c == '\t' || c == '\r'; }

class Reader {
public:
    Reader(const LineIndex& lines, std::string file) : lines_(lines) { model_.file = std::move(file); }

    UrdfModel run(const pugi::xml_document& doc) {
        const pugi::xml_node robot = doc.document_element();
        if (!robot || std::string_view(robot.name()) != kUrdfRootElement)
            fail(robot, "not a URDF file: the root element is " + (robot ? q(robot.name()) : std::string("missing")) +
                            ", not <robot>");
        model_.name = robot.attribute("name").value();
        model_.robot_line = line(robot);
        for (const pugi::xml_node& m : robot.children("material")) {
            const std::string name = m.attribute("name").value();
            if (name.empty()) fail(m, "a top-level <material> without a name");
            model_.materials[name] = colour_of(m);
        }
        std::set<std::string> links, joints;
        for (const pugi::xml_node& n : robot.children()) {
            if (n.type() != pugi::node_element) continue;
            const std::string_view tag = n.name();
            if (tag == "link") {
                UrdfLink link = read_link(n);
                if (!links.insert(link.name).second) fail(n, "a second link named " + q(link.name));
                model_.links.push_back(std::move(link));
            } else if (tag == "joint") {
                UrdfJoint joint = read_joint(n);
                if (!joints.insert(joint.name).second) fail(n, "a second joint named " + q(joint.name));
                model_.joints.push_back(std::move(joint));
            }
            // material: read above; gazebo, transmission, ros2_control and
            // other extensions are for other tools.
        }
        if (model_.links.empty()) fail(robot, "the robot has no <link>");
        // Gazebo's convention: a joint may hang the robot on "world" without declaring it.
        if (!links.count("world"))
            for (const UrdfJoint& j : model_.joints)
                if (j.parent == "world") {
                    UrdfLink world;
                    world.name = "world";
                    world.line = j.line;
                    model_.links.insert(model_.links.begin(), std::move(world));
                    break;
                }
        return std::move(model_);
    }

private:
    int line(const pugi::xml_node& n) const { return n ? lines_.line_of(n.offset_debug()) : 0; }

    [[noreturn]] void fail(const pugi::xml_node& n, const std::string& message) const {
        throw FileError(model_.file, line(n), message);
    }

    void note(const pugi::xml_node& n, const char* code, const std::string& message) {
        mbx_memory::Diagnostic d;
        d.severity = MBX_SEVERITY_WARNING;
        d.code = code;
        d.subject_kind = MBX_SUBJECT_FILE;
        d.subject_id = model_.file;
        d.file = model_.file;
        d.line = line(n);
        d.message = message;
        model_.diagnostics.push_back(std::move(d));
    }

    // Exactly `count` whitespace-separated finite numbers in an attribute.
    void numbers(const pugi::xml_node& n, const char* attribute, double* out, size_t count) const {
        std::string_view text = n.attribute(attribute).value();
        const std::string what = "<" + std::string(n.name()) + "> " + attribute + "=";
        size_t k = 0;
        while (true) {
            size_t start = 0;
            while (start < text.size() && xml_space(text[start])) ++start;
            text.remove_prefix(start);
            if (text.empty()) break;
            size_t end = 0;
            while (end < text.size() && !xml_space(text[end])) ++end;
            const std::optional<double> x = parse_number(text.substr(0, end));
            if (!x) fail(n, what + q(text.substr(0, end)) + " is not a finite number");
            if (k == count) fail(n, what + " holds more than " + std::to_string(count) + " numbers");
            out[k++] = *x;
            text.remove_prefix(end);
        }
        if (k != count)
            fail(n, what + " holds " + std::to_string(k) + " numbers where " + std::to_string(count) + " belong");
    }

    double number(const pugi::xml_node& n, const char* attribute, double fallback, bool required = false) const {
        const pugi::xml_attribute a = n.attribute(attribute);
        if (!a) {
            if (required) fail(n, "<" + std::string(n.name()) + "> has no " + attribute + "=");
            return fallback;
        }
        double x = 0;
        numbers(n, attribute, &x, 1);
        return x;
    }

    Eigen::Vector3d vector(const pugi::xml_node& n, const char* attribute, const Eigen::Vector3d& fallback) const {
        if (!n.attribute(attribute)) return fallback;
        Eigen::Vector3d v;
        numbers(n, attribute, v.data(), 3);
        return v;
    }

    UrdfOrigin origin(const pugi::xml_node& parent) const {
        UrdfOrigin o;
        if (const pugi::xml_node n = parent.child("origin")) {
            o.xyz = vector(n, "xyz", Eigen::Vector3d::Zero());
            o.rpy = vector(n, "rpy", Eigen::Vector3d::Zero());
        }
        return o;
    }

    UrdfColour colour_of(const pugi::xml_node& material) const {
        UrdfColour c;
        if (const pugi::xml_node colour = material.child("color")) {
            numbers(colour, "rgba", c.rgba, 4);
            c.given = true;
        }
        return c;
    }

    UrdfLink read_link(const pugi::xml_node& n) {
        UrdfLink link;
        link.name = n.attribute("name").value();
        link.line = line(n);
        if (link.name.empty()) fail(n, "a <link> without a name");
        if (const pugi::xml_node in = n.child("inertial")) {
            UrdfInertial& i = link.inertial;
            i.given = true;
            i.line = line(in);
            i.origin = origin(in);
            const pugi::xml_node mass = in.child("mass");
            if (!mass) fail(in, "link " + q(link.name) + ": <inertial> without <mass>");
            i.mass = number(mass, "value", 0, true);
            if (i.mass < 0) fail(mass, "link " + q(link.name) + ": a negative mass");
            const pugi::xml_node inertia = in.child("inertia");
            if (!inertia) fail(in, "link " + q(link.name) + ": <inertial> without <inertia>");
            i.ixx = number(inertia, "ixx", 0, true);
            i.ixy = number(inertia, "ixy", 0, true);
            i.ixz = number(inertia, "ixz", 0, true);
            i.iyy = number(inertia, "iyy", 0, true);
            i.iyz = number(inertia, "iyz", 0, true);
            i.izz = number(inertia, "izz", 0, true);
            // Said here, where the line is known; the translator's check names the body only.
            Eigen::Matrix3d I;
            I << i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz;
            const Eigen::Vector3d p = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
            const double tolerance = 1e-9 * std::max(1e-300, p.cwiseAbs().maxCoeff());
            if (p[0] < -tolerance || p[0] + p[1] < p[2] - tolerance)
                note(inertia, "urdf_inertia_not_physical",
                     "link " + q(link.name) + ": the inertia's principal moments " + std::to_string(p[0]) + ", " +
                         std::to_string(p[1]) + ", " + std::to_string(p[2]) +
                         (p[0] < -tolerance ? " include a negative one" : " break the triangle inequality") +
                         ": no rigid body has them");
        }
        for (const pugi::xml_node& v : n.children("visual")) link.visuals.push_back(read_shape(v, link.name, true));
        for (const pugi::xml_node& c : n.children("collision")) link.collisions.push_back(read_shape(c, link.name, false));
        return link;
    }

    UrdfShape read_shape(const pugi::xml_node& n, const std::string& link, bool visual) {
        UrdfShape s;
        s.name = n.attribute("name").value();
        s.line = line(n);
        s.origin = origin(n);
        const pugi::xml_node g = n.child("geometry");
        pugi::xml_node kind;
        for (const pugi::xml_node& c : g.children())
            if (c.type() == pugi::node_element) {
                kind = c;
                break;
            }
        if (!kind) {
            note(n, "urdf_no_geometry", "link " + q(link) + ": a <" + std::string(n.name()) + "> without geometry; left out");
        } else {
            const std::string_view tag = kind.name();
            UrdfGeometry& geometry = s.geometry;
            s.has_geometry = true;
            if (tag == "box") {
                geometry.kind = UrdfGeometry::Kind::box;
                numbers(kind, "size", geometry.size.data(), 3);
            } else if (tag == "cylinder") {
                geometry.kind = UrdfGeometry::Kind::cylinder;
                geometry.radius = number(kind, "radius", 0, true);
                geometry.length = number(kind, "length", 0, true);
            } else if (tag == "sphere") {
                geometry.kind = UrdfGeometry::Kind::sphere;
                geometry.radius = number(kind, "radius", 0, true);
            } else if (tag == "mesh") {
                geometry.kind = UrdfGeometry::Kind::mesh;
                geometry.filename = kind.attribute("filename").value();
                if (geometry.filename.empty()) fail(kind, "link " + q(link) + ": a <mesh> without a filename");
                geometry.scale = vector(kind, "scale", Eigen::Vector3d::Ones());
            } else {
                s.has_geometry = false;
                note(kind, "urdf_unknown_geometry",
                     "link " + q(link) + ": geometry <" + std::string(tag) + "> is not box, cylinder, sphere or mesh; left out");
            }
            if (s.has_geometry && (geometry.size.minCoeff() < 0 || geometry.radius < 0 || geometry.length < 0))
                fail(kind, "link " + q(link) + ": a negative size");
        }
        if (visual) {
            if (const pugi::xml_node m = n.child("material")) {
                s.material = m.attribute("name").value();
                s.colour = colour_of(m);
                if (!s.colour.given) {
                    const auto named = model_.materials.find(s.material);
                    if (named != model_.materials.end()) s.colour = named->second;
                }
            }
        }
        return s;
    }

    UrdfJoint read_joint(const pugi::xml_node& n) {
        UrdfJoint j;
        j.name = n.attribute("name").value();
        j.type = n.attribute("type").value();
        j.line = line(n);
        if (j.name.empty()) fail(n, "a <joint> without a name");
        if (!kJointTypes.count(j.type))
            fail(n, "joint " + q(j.name) + ": type " + q(j.type) +
                        " is not one of revolute, continuous, prismatic, fixed, floating, planar");
        j.parent = n.child("parent").attribute("link").value();
        j.child = n.child("child").attribute("link").value();
        if (j.parent.empty()) fail(n, "joint " + q(j.name) + " has no <parent link=...>");
        if (j.child.empty()) fail(n, "joint " + q(j.name) + " has no <child link=...>");
        j.origin = origin(n);
        if (const pugi::xml_node axis = n.child("axis")) {
            const Eigen::Vector3d written = vector(axis, "xyz", Eigen::Vector3d::UnitX());
            // A fixed or floating joint has no axis to give: exporters write "0 0 0" there (DFKI's acrobot).
            if (j.type != "fixed" && j.type != "floating") {
                if (!(written.norm() > 1e-12)) fail(axis, "joint " + q(j.name) + ": a zero axis");
                j.axis = written.normalized();
            }
        }
        if (const pugi::xml_node limit = n.child("limit")) {
            j.has_limit = true;
            j.limit_line = line(limit);
            j.lower = number(limit, "lower", 0);
            j.upper = number(limit, "upper", 0);
            j.effort = number(limit, "effort", 0);
            j.velocity = number(limit, "velocity", 0);
            if ((j.type == "revolute" || j.type == "prismatic") && j.lower > j.upper)
                fail(limit, "joint " + q(j.name) + ": lower limit above the upper one");
            if (j.effort < 0 || j.velocity < 0) fail(limit, "joint " + q(j.name) + ": a negative effort or velocity limit");
        } else if (j.type == "revolute" || j.type == "prismatic") {
            note(n, "urdf_no_limit", "joint " + q(j.name) + " (" + j.type + ") has no <limit>, which URDF requires; "
                                     "taken as unlimited");
        }
        if (const pugi::xml_node d = n.child("dynamics")) {
            j.has_dynamics = true;
            j.damping = number(d, "damping", 0);
            j.friction = number(d, "friction", 0);
            if (j.damping < 0 || j.friction < 0) fail(d, "joint " + q(j.name) + ": negative damping or friction");
        }
        if (const pugi::xml_node m = n.child("mimic")) {
            j.has_mimic = true;
            j.mimic_line = line(m);
            j.mimic_joint = m.attribute("joint").value();
            j.mimic_multiplier = number(m, "multiplier", 1);
            j.mimic_offset = number(m, "offset", 0);
            if (j.mimic_joint.empty()) fail(m, "joint " + q(j.name) + ": <mimic> names no joint");
        }
        return j;
    }

    const LineIndex& lines_;
    UrdfModel model_;
};

UrdfModel parse_owned(char* text, size_t size, const std::string& file) {
    const LineIndex lines(std::string_view(text, size));
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed = doc.load_buffer_inplace(text, size, pugi::parse_default, pugi::encoding_utf8);
    if (!parsed)
        throw FileError(file, lines.line_of(parsed.offset), std::string("not well-formed XML: ") + parsed.description());
    return Reader(lines, file).run(doc);
}

}  // namespace

UrdfModel parse_urdf(std::string_view text, const std::string& file) {
    std::string copy(text);
    return parse_owned(copy.data(), copy.size(), file);
}

UrdfModel read_urdf(const std::string& path) {
    const FileBytes bytes = read_file_bytes(path);
    UrdfModel model = parse_owned(bytes.data.get(), bytes.size, path);
    std::error_code ec;
    // The loops mbx's URDF export cut: <stem>.cut_joints.json beside the file.
    const std::filesystem::path p(path);
    const std::string sidecar = (p.parent_path() / (p.stem().string() + ".cut_joints.json")).string();
    if (std::filesystem::is_regular_file(sidecar, ec)) {
        const FileBytes json = read_file_bytes(sidecar);
        model.cut_joints = parse_cut_joints(std::string_view(json.data.get(), json.size), sidecar);
        model.cut_joint_file = sidecar;
    }
    return model;
}

}  // namespace mbx_files

namespace mbx_files {

using mbx::JsonError;
using mbx::JsonValue;
using mbx::parse_json;

std::vector<UrdfCutJoint> parse_cut_joints(std::string_view text, const std::string& file) {
    JsonValue root;
    try {
        root = parse_json(text);
    } catch (const JsonError& e) {
        throw FileError(file, e.line(), std::string("not JSON: ") + e.what());
    }
    auto fail = [&](const JsonValue& at, const std::string& message) { throw FileError(file, at.line, message); };
    const JsonValue* format = root.find("format");
    if (!format || format->string != "mbx-urdf-cut-joints")
        fail(root, "not a cut-joint file: no \"format\": \"mbx-urdf-cut-joints\"");
    const JsonValue* version = root.find("version");
    if (!version || version->kind != JsonValue::Kind::number || version->number != 1)
        fail(version ? *version : root, "cut-joint file version " + (version ? std::to_string(version->number) : "?") +
                                            "; mbx reads version 1");
    const JsonValue* list = root.find("cut_joints");
    if (!list || list->kind != JsonValue::Kind::array) fail(root, "no \"cut_joints\" array");
    auto number = [&](const JsonValue& v) {
        if (v.kind != JsonValue::Kind::number) fail(v, "a number belongs here");
        return v.number;
    };
    auto vector = [&](const JsonValue* v, const char* what, const JsonValue& owner) {
        if (!v || v->kind != JsonValue::Kind::array || v->array.size() != 3)
            fail(v ? *v : owner, std::string("\"") + what + "\" needs three numbers");
        return Eigen::Vector3d(number(v->array[0]), number(v->array[1]), number(v->array[2]));
    };
    auto text_of = [&](const JsonValue& owner, const char* key) {
        const JsonValue* v = owner.find(key);
        if (!v || v->kind != JsonValue::Kind::string || v->string.empty()) fail(owner, std::string("no \"") + key + "\"");
        return v->string;
    };
    std::vector<UrdfCutJoint> out;
    for (const JsonValue& j : list->array) {
        if (j.kind != JsonValue::Kind::object) fail(j, "a cut joint is an object");
        UrdfCutJoint c;
        c.line = j.line;
        c.name = text_of(j, "name");
        c.type = text_of(j, "type");
        if (c.type != "revolute" && c.type != "prismatic" && c.type != "spherical" && c.type != "fixed")
            fail(j, "cut joint '" + c.name + "': type '" + c.type + "' is not revolute, prismatic, spherical or fixed");
        for (const char* side : {"parent", "child"}) {
            const JsonValue* s = j.find(side);
            if (!s || s->kind != JsonValue::Kind::object) fail(j, "cut joint '" + c.name + "': no \"" + side + "\"");
            UrdfOrigin o;
            o.xyz = vector(s->find("xyz"), "xyz", *s);
            o.rpy = vector(s->find("rpy"), "rpy", *s);
            if (std::string(side) == "parent") {
                c.parent = text_of(*s, "link");
                c.parent_origin = o;
                const JsonValue* axis = s->find("axis");
                if (axis && !axis->is_null()) {
                    c.axis = vector(axis, "axis", *s);
                    if (!(c.axis.norm() > 1e-12)) fail(*axis, "cut joint '" + c.name + "': a zero axis");
                    c.axis.normalize();
                    c.has_axis = true;
                }
            } else {
                c.child = text_of(*s, "link");
                c.child_origin = o;
            }
        }
        if ((c.type == "revolute" || c.type == "prismatic") && !c.has_axis)
            fail(j, "cut joint '" + c.name + "': a " + c.type + " joint needs an axis");
        if (const JsonValue* limits = j.find("limits"); limits && !limits->is_null()) {
            const JsonValue* lower = limits->find("lower");
            const JsonValue* upper = limits->find("upper");
            if (!lower || !upper) fail(*limits, "cut joint '" + c.name + "': limits need lower and upper");
            c.has_limit = true;
            c.lower = number(*lower);
            c.upper = number(*upper);
            if (c.lower > c.upper) fail(*limits, "cut joint '" + c.name + "': lower limit above the upper one");
        }
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace mbx_files
