#include "pmxml_reader.h"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unordered_map>
#include <unordered_set>

#include <pugixml.hpp>

#include "line_index.h"
#include "numbers.h"
#include "units.h"

namespace mbx_files {
namespace {

// Subsystems mirror CAD sub-assemblies; real files nest 3 deep. The bound
// only keeps hostile input from exhausting the stack.
constexpr size_t kMaxSubsystemDepth = 64;
// The SDK refuses rotations further than this from orthonormal; refusing them
// here already lets the message carry a line number.
constexpr double kRotationLimit = 0.05;

std::string unquote(std::string_view text) {
    text = trim(text);
    if (!text.empty() && text.front() == '"') text.remove_prefix(1);
    if (!text.empty() && text.back() == '"') text.remove_suffix(1);
    return std::string(trim(text));
}

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string q(const std::string& s) { return "'" + s + "'"; }

std::string join(const std::vector<std::string>& parts, const std::string& first) {
    std::string out = first;
    for (const std::string& p : parts) out += "/" + p;
    return out;
}

struct PendingJoint {
    pugi::xml_node node;
    std::vector<std::string> path;
};

struct RefDefinition {
    int frame;
    int line;
};

class Reader {
public:
    Reader(std::string_view text, std::string file) : text_(text), lines_(text) { model_.file = std::move(file); }

    PmxmlModel run() {
        pugi::xml_document doc;
        const pugi::xml_parse_result parsed =
            doc.load_buffer(text_.data(), text_.size(), pugi::parse_default, pugi::encoding_auto);
        if (!parsed)
            throw FileError(model_.file, lines_.line_of(parsed.offset),
                            std::string("malformed XML: ") + parsed.description());
        const pugi::xml_node root = doc.document_element();
        const std::string root_name = root.name();
        if (root_name == "SimMechanicsImportXML" || root_name == "SimscapeMultibodyImportXML")
            fail(root, "<" + root_name +
                           "> is second-generation Simscape Multibody import XML, which is not supported; export "
                           "first-generation Physical Modeling XML instead");
        if (root_name != "PhysicalModelingXMLFile")
            fail(root, "not a Physical Modeling XML file: the root element is <" + root_name +
                           ">, expected <PhysicalModelingXMLFile>");

        pugi::xml_node container;
        for (pugi::xml_node child : root.children()) {
            const std::string n = child.name();
            if (n != "SimMechanics" && n != "SimscapeMultibody") continue;
            if (container) fail(child, "a second model element <" + n + ">; a file holds exactly one");
            container = child;
        }
        if (!container) fail(root, "no <SimMechanics> or <SimscapeMultibody> model element");
        model_.container = container.name();
        model_.created_using = text_of(root, "createdUsing");
        model_.name = text_of(container, "name");
        if (model_.name.empty()) model_.name = text_of(root, "name");

        walk(container, {}, 0);
        for (const PendingJoint& j : pending_joints_) read_joint(j.node, j.path);
        return std::move(model_);
    }

private:
    int line(const pugi::xml_node& n) const { return lines_.line_of(n.offset_debug()); }

    [[noreturn]] void fail(const pugi::xml_node& n, const std::string& message) const {
        throw FileError(model_.file, line(n), message);
    }

    void warn(const pugi::xml_node& n, const char* code, mbx_subject_kind kind, const std::string& id,
              const std::string& name, const std::string& message) {
        mbx_memory::Diagnostic d;
        d.severity = MBX_SEVERITY_WARNING;
        d.code = code;
        d.subject_kind = kind;
        d.subject_id = id;
        d.subject_name = name;
        d.file = model_.file;
        d.line = line(n);
        d.message = message;
        model_.diagnostics.push_back(std::move(d));
    }

    // Unquoted text of child `name`, "" if absent.
    static std::string text_of(const pugi::xml_node& parent, const char* name) {
        return unquote(parent.child(name).child_value());
    }

    pugi::xml_node need(const pugi::xml_node& parent, const char* name, const std::string& who) const {
        const pugi::xml_node n = parent.child(name);
        if (!n) fail(parent, who + " has no <" + name + ">");
        return n;
    }

    double number(const pugi::xml_node& n, const std::string& who) const {
        const std::string text = unquote(n.child_value());
        const std::optional<double> v = parse_number(text);
        if (!v) fail(n, who + ": <" + n.name() + "> is not a number: " + q(text));
        return *v;
    }

    void numbers(const pugi::xml_node& n, double* out, size_t count, const std::string& who) const {
        const std::string text = unquote(n.child_value());
        if (!parse_number_list(text, out, count))
            fail(n, who + ": <" + n.name() + "> needs " + std::to_string(count) + " comma-separated numbers, got " +
                        q(text));
    }

    double unit(const pugi::xml_node& n, Quantity quantity, const std::string& who) const {
        try {
            return unit_to_si(unquote(n.child_value()), quantity);
        } catch (const UnitError& e) {
            fail(n, who + ": <" + n.name() + ">: " + e.what());
        }
    }

    // The unit of a value that may omit it when the value is zero (massless
    // helpers written by hand); otherwise the unit is as critical as the value.
    double unit_or_si(const pugi::xml_node& parent, const char* name, bool value_is_zero, Quantity quantity,
                      std::string& unit_text, const std::string& who) const {
        const pugi::xml_node n = parent.child(name);
        if (!n || unquote(n.child_value()).empty()) {
            if (!value_is_zero) fail(n ? n : parent, who + " has no <" + name + ">");
            unit_text = "";
            return 1.0;
        }
        unit_text = unquote(n.child_value());
        return unit(n, quantity, who);
    }

    std::string unique(std::unordered_set<std::string>& used, const std::string& id) {
        if (used.insert(id).second) return id;
        for (int k = 2;; ++k) {
            std::string candidate = id + "~" + std::to_string(k);
            if (used.insert(candidate).second) return candidate;
        }
    }

    void walk(const pugi::xml_node& node, const std::vector<std::string>& path, size_t depth) {
        for (pugi::xml_node b : node.child("bodies").children("Body")) read_body(b, path);
        for (pugi::xml_node j : node.child("joints").children("SimpleJoint")) pending_joints_.push_back({j, path});
        for (pugi::xml_node g : node.child("grounds").children("Ground")) read_ground(g, path);
        for (pugi::xml_node s : node.child("subsystems").children("Subsystem")) {
            if (depth + 1 > kMaxSubsystemDepth)
                fail(s, "subsystems nested deeper than " + std::to_string(kMaxSubsystemDepth));
            std::string name = text_of(s, "name");
            if (name.empty()) name = text_of(s, "nodeID");
            if (name.empty()) name = "Subsystem@" + std::to_string(line(s));
            const std::string status = text_of(s, "status");
            if (!status.empty())
                warn(s, "pmxml_subsystem_status", MBX_SUBJECT_MODEL, name, name,
                     "the exporter reports on subsystem " + q(name) + ": " + status);
            std::vector<std::string> inner = path;
            inner.push_back(name);
            walk(s, inner, depth + 1);
        }
    }

    int read_frame(const pugi::xml_node& f, int body, const std::string& body_id, const std::string& body_who,
                   int position_in_body) {
        PmxmlFrame fr;
        fr.line = line(f);
        fr.body = body;
        fr.name = text_of(f, "name");
        if (fr.name.empty()) fr.name = "frame" + std::to_string(position_in_body + 1);
        const std::string who = "frame " + q(fr.name) + " of " + body_who;
        fr.display_name = text_of(f, "displayName");
        fr.node_id = text_of(f, "nodeID");

        double p[3], o[9];
        numbers(need(f, "position", who), p, 3, who);
        const pugi::xml_node units = need(f, "positionUnits", who);
        fr.length_unit = unquote(units.child_value());
        fr.length_to_m = unit(units, Quantity::length, who);
        numbers(need(f, "orientation", who), o, 9, who);
        for (const char* field : {"positionOrigin", "positionReferenceFrame", "orientationReferenceFrame"}) {
            const pugi::xml_node n = f.child(field);
            const std::string value = unquote(n.child_value());
            if (n && lower(value) != "world")
                fail(n, who + ": <" + field + "> is " + q(value) +
                            "; only WORLD is supported (every pose must be absolute)");
        }
        if (const pugi::xml_node n = f.child("orientationType")) {
            const std::string value = unquote(n.child_value());
            if (lower(value) != "3x3 transform")
                fail(n, who + ": <orientationType> is " + q(value) + "; only '3x3 Transform' is supported");
        }
        fr.position = Eigen::Vector3d(p[0], p[1], p[2]);
        // Column-major: o1..o3 are the frame's x axis in world (FORMAT_NOTES 5.1).
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) fr.rotation(i, j) = o[3 * j + i];
        const double error =
            (fr.rotation.transpose() * fr.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
        if (error > kRotationLimit || !(fr.rotation.determinant() > 0))
            fail(f.child("orientation"),
                 who + ": <orientation> is not a rotation matrix (max |R^T R - I| = " + std::to_string(error) +
                     ", determinant " + std::to_string(fr.rotation.determinant()) + ")");

        if (const pugi::xml_attribute ref = f.attribute("ref")) {
            fr.ref = std::string(trim(ref.value()));
            if (fr.ref.empty()) fail(f, who + " has an empty ref attribute");
            const auto [it, inserted] = refs_.emplace(fr.ref, RefDefinition{int(model_.frames.size()), fr.line});
            if (!inserted) {
                const PmxmlFrame& other = model_.frames[size_t(it->second.frame)];
                fail(f, who + " defines frame ref " + fr.ref + ", already defined by frame " + q(other.name) +
                            " at line " + std::to_string(it->second.line) + "; refs must be unique in the file");
            }
        }
        fr.to_host = !fr.ref.empty() || (fr.name != "CG" && fr.name != "CS1");
        fr.id = unique(frame_ids_, body_id + "::" + fr.name);
        model_.frames.push_back(std::move(fr));
        return int(model_.frames.size() - 1);
    }

    std::string body_id(const pugi::xml_node& n, const std::string& node_id, const std::string& fallback,
                        const std::string& name) {
        const std::string wanted = node_id.empty() ? fallback : node_id;
        std::string id = unique(body_ids_, wanted);
        if (id != wanted)
            warn(n, "pmxml_duplicate_id", MBX_SUBJECT_BODY, id, name,
                 "body id " + q(wanted) + " is used twice; this body is " + q(id));
        return id;
    }

    void read_body(const pugi::xml_node& b, const std::vector<std::string>& path) {
        PmxmlBody body;
        body.line = line(b);
        body.subsystem_path = path;
        body.name = text_of(b, "name");
        body.node_id = text_of(b, "nodeID");
        if (body.name.empty() && body.node_id.empty()) fail(b, "a <Body> has neither a <name> nor a <nodeID>");
        if (body.name.empty()) body.name = body.node_id;
        body.id = body_id(b, body.node_id, join(path, model_.name) + "/" + body.name, body.name);
        if (body.name == "RootPart") body.flags |= MBX_BODY_HELPER;
        const std::string who = "body " + q(body.name);

        body.mass = number(need(b, "mass", who), who);
        body.mass_to_kg = unit_or_si(b, "massUnits", body.mass == 0, Quantity::mass, body.mass_unit, who);
        if (const pugi::xml_node v = b.child("volume"); v && !unquote(v.child_value()).empty()) {
            body.volume = number(v, who);
            std::string volume_unit;
            body.volume_to_m3 = unit_or_si(b, "volumeUnits", body.volume == 0, Quantity::volume, volume_unit, who);
        }
        double inertia[9];
        numbers(need(b, "inertia", who), inertia, 9, who);
        bool zero = true;
        for (double v : inertia) zero = zero && v == 0;
        body.inertia_to_kg_m2 = unit_or_si(b, "inertiaUnits", zero, Quantity::inertia, body.inertia_unit, who);
        Eigen::Matrix3d tensor;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) tensor(i, j) = inertia[3 * i + j];

        const int index = int(model_.bodies.size());
        const pugi::xml_node frames = need(b, "frames", who);
        int k = 0;
        for (pugi::xml_node f : frames.children("Frame")) {
            const int fi = read_frame(f, index, body.id, who, k++);
            const std::string& name = model_.frames[size_t(fi)].name;
            if (name == "CS1" && body.cs1 < 0) body.cs1 = fi;
            if (name == "CG" && body.cg < 0) body.cg = fi;
        }
        if (body.cs1 < 0) fail(frames, who + " has no CS1 frame (its part frame)");
        if (body.cg < 0) {
            if (body.mass != 0) fail(frames, who + " has a mass but no CG frame");
            body.cg = body.cs1;
        }
        if (const pugi::xml_node g = b.child("geometryFileName")) {
            body.geometry_file = unquote(g.child_value());
            body.geometry_line = line(g);
        }
        const std::string status = text_of(b, "status");
        if (!status.empty())
            warn(b, "pmxml_body_status", MBX_SUBJECT_BODY, body.id, body.name,
                 "the exporter reports on body " + q(body.name) + ": " + status);

        // The SDK wants the centre of mass in the body (CS1) frame and the
        // tensor in its axes; the file gives the CG in world and the tensor
        // in CG axes (equal to CS1's in every real file, but not by rule).
        const PmxmlFrame& cs1 = model_.frames[size_t(body.cs1)];
        const PmxmlFrame& cg = model_.frames[size_t(body.cg)];
        const Eigen::Matrix3d r_cs1 = nearest_rotation(cs1.rotation);
        const Eigen::Matrix3d r_cg = nearest_rotation(cg.rotation);
        const Eigen::Vector3d cg_position = cg.position * (cg.length_to_m / cs1.length_to_m);
        body.com = r_cs1.transpose() * (cg_position - cs1.position);
        if ((r_cs1 - r_cg).cwiseAbs().maxCoeff() > 1e-12) {
            const Eigen::Matrix3d cg_in_cs1 = r_cs1.transpose() * r_cg;
            tensor = cg_in_cs1 * tensor * cg_in_cs1.transpose();
        }
        body.inertia = tensor;
        model_.bodies.push_back(std::move(body));
    }

    void read_ground(const pugi::xml_node& g, const std::vector<std::string>& path) {
        PmxmlBody body;
        body.line = line(g);
        body.subsystem_path = path;
        body.name = text_of(g, "name");
        body.node_id = text_of(g, "nodeID");
        if (body.name.empty()) body.name = body.node_id.empty() ? "RootGround" : body.node_id;
        body.id = body_id(g, body.node_id, body.name, body.name);
        // The world's datum, not a CAD part: ground and massless helper.
        body.flags = MBX_BODY_GROUND | MBX_BODY_HELPER;
        const std::string who = "ground " + q(body.name);
        pugi::xml_node f = g.child("frame").child("Frame");
        if (!f) f = g.child("Frame");
        if (!f) fail(g, who + " has no <frame><Frame>");
        const int index = int(model_.bodies.size());
        body.cs1 = read_frame(f, index, body.id, who, 0);
        model_.bodies.push_back(std::move(body));
    }

    int end_frame(const pugi::xml_node& j, const char* role, const std::string& who) const {
        const pugi::xml_node side = j.child(role);
        if (!side) fail(j, who + " has no <" + role + ">");
        const pugi::xml_node frame =
            side.find_node([](const pugi::xml_node& n) { return std::strcmp(n.name(), "Frame") == 0; });
        if (!frame) fail(side, who + ": <" + role + "> names no <Frame ref=...>");
        const std::string ref(trim(frame.attribute("ref").value()));
        if (ref.empty()) fail(frame, who + ": the " + role + " <Frame> has no ref");
        const auto it = refs_.find(ref);
        if (it == refs_.end())
            fail(frame, who + " refers to " + role + " frame ref " + ref + ", which no Frame in the file defines");
        return it->second.frame;
    }

    PmxmlPrimitive read_primitive(const pugi::xml_node& p, const std::string& who) const {
        PmxmlPrimitive prim;
        prim.line = line(p);
        const std::string name = lower(text_of(p, "name"));
        if (name == "weld")
            prim.type = MBX_PRIMITIVE_WELD;
        else if (name == "prismatic")
            prim.type = MBX_PRIMITIVE_PRISMATIC;
        else if (name == "revolute")
            prim.type = MBX_PRIMITIVE_REVOLUTE;
        else if (name == "spherical")
            prim.type = MBX_PRIMITIVE_SPHERICAL;
        else
            fail(p, who + " has unknown primitive " + q(text_of(p, "name")) +
                        " (known: weld, prismatic, revolute, spherical)");
        // A weld's axis is a dummy and a spherical joint has none.
        if (prim.type != MBX_PRIMITIVE_REVOLUTE && prim.type != MBX_PRIMITIVE_PRISMATIC) return prim;
        if (const pugi::xml_node reference = p.child("referenceFrame")) {
            const std::string value = unquote(reference.child_value());
            if (!value.empty() && lower(value) != "world")
                fail(reference, who + ": the " + name + " axis is given in " + q(value) + "; only WORLD is supported");
        }
        double a[3];
        const pugi::xml_node axis = need(p, "axis", who + "'s " + name + " primitive");
        numbers(axis, a, 3, who);
        prim.axis = Eigen::Vector3d(a[0], a[1], a[2]);
        if (!(prim.axis.norm() > 1e-9)) fail(axis, who + " has a zero-length " + name + " axis");
        return prim;
    }

    void read_joint(const pugi::xml_node& j, const std::vector<std::string>& path) {
        PmxmlJoint joint;
        joint.line = line(j);
        joint.subsystem_path = path;
        joint.name = text_of(j, "name");
        joint.node_id = text_of(j, "nodeID");
        if (joint.name.empty())
            joint.name = joint.node_id.empty() ? "joint@" + std::to_string(joint.line) : joint.node_id;
        const std::string wanted = joint.node_id.empty() ? joint.name : joint.node_id;
        joint.id = unique(joint_ids_, wanted);
        if (joint.id != wanted)
            warn(j, "pmxml_duplicate_id", MBX_SUBJECT_CONSTRAINT, joint.id, joint.name,
                 "joint id " + q(wanted) + " is used twice; this joint is " + q(joint.id));
        const std::string who = "joint " + q(joint.name);
        joint.base_frame = end_frame(j, "base", who);
        joint.follower_frame = end_frame(j, "follower", who);
        const pugi::xml_node primitives = need(j, "primitives", who);
        for (pugi::xml_node p : primitives.children("Primitive")) joint.primitives.push_back(read_primitive(p, who));
        if (joint.primitives.empty()) fail(primitives, who + " has no <Primitive>");
        joint.status = text_of(j, "status");
        model_.joints.push_back(std::move(joint));
    }

    std::string_view text_;
    LineIndex lines_;
    PmxmlModel model_;
    std::unordered_map<std::string, RefDefinition> refs_;
    std::unordered_set<std::string> body_ids_, frame_ids_, joint_ids_;
    std::vector<PendingJoint> pending_joints_;
};

}  // namespace

PmxmlModel parse_pmxml(std::string_view text, const std::string& file) { return Reader(text, file).run(); }

PmxmlModel read_pmxml(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw FileError(path, 0, "cannot open the file: it is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path, 0, std::string("cannot open the file: ") + std::strerror(errno));
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(0, std::ios::beg);
    if (size < 0) throw FileError(path, 0, "cannot read the file");
    std::string text(size_t(size), '\0');
    in.read(text.data(), size);
    if (in.gcount() != size) throw FileError(path, 0, "cannot read the file");
    return parse_pmxml(text, path);
}

}  // namespace mbx_files
