#include "simscape_reader.h"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <unordered_map>

#include <pugixml.hpp>

#include "host_adapters/common/file_bytes.h"
#include "host_adapters/common/line_index.h"
#include "host_adapters/common/numbers.h"
#include "host_adapters/common/units.h"

namespace mbx_files {
namespace {

// Sub-assemblies in real exports nest a few deep; the bound keeps hostile
// input from exhausting the stack.
constexpr int kMaxInstanceDepth = 64;
// As for PMXML: rotations further than this from orthonormal are refused
// here, where the message can carry a line.
constexpr double kRotationLimit = 0.05;

// An element's name without its namespace prefix.
std::string_view local_name(const pugi::xml_node& n) {
    const std::string_view name = n.name();
    const size_t colon = name.find(':');
    return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

pugi::xml_node child(const pugi::xml_node& parent, std::string_view name) {
    for (pugi::xml_node c = parent.first_child(); c; c = c.next_sibling())
        if (c.type() == pugi::node_element && local_name(c) == name) return c;
    return {};
}

std::string q(std::string_view s) { return "'" + std::string(s) + "'"; }

// What an error message names ("Revolute joint 'elbow' <BaseFrame>
// <Rotation>"), kept as pieces into the parsed text and put together only
// when there is an error: building it for every element cost a string
// allocation or three per instance and joint.
class Who {
public:
    // "<kind><noun> '<name>'": ("part", name), ("Revolute", name, " joint").
    Who(std::string_view kind, std::string_view name, std::string_view noun = {}) {
        add(kind), add(noun), add(" '"), add(name), add("'");
    }
    Who with(std::string_view tail) const {
        Who w = *this;
        w.add(tail);
        return w;
    }
    std::string str() const {
        std::string out;
        for (size_t k = 0; k < count_; ++k) out += pieces_[k];
        return out;
    }

private:
    void add(std::string_view piece) {
        if (count_ < pieces_.size()) pieces_[count_++] = piece;
    }
    std::array<std::string_view, 8> pieces_{};
    size_t count_ = 0;
};

class Reader {
public:
    Reader(const LineIndex& lines, std::string file) : lines_(lines) { model_.file = std::move(file); }

    SimscapeModel run(const pugi::xml_document& doc) {
        pugi::xml_node root = doc.document_element();
        if (!root || (local_name(root) != kSimscapeRootElement && local_name(root) != kSimMechanicsImportRootElement))
            fail(root, "not a Simscape Multibody import file: the root element is " +
                           (root ? q(local_name(root)) : std::string("missing")) + ", not <" + kSimscapeRootElement + ">");
        const std::string version = root.attribute("version").value();
        if (!version.empty() && version.rfind("2", 0) != 0 && version.rfind("1", 0) != 0)
            note(root, MBX_SEVERITY_WARNING, "simscape_version",
                 "version " + q(version) + " of the import format; mbx reads versions 1 and 2, and this one as if it were 2");
        if (const pugi::xml_node created = child(root, "Created")) {
            model_.created_by = created.attribute("by").value();
            model_.created_from = created.attribute("from").value();
            model_.created_using = created.attribute("using").value();
        }
        read_units(root);
        for (const pugi::xml_node& p : child(root, "Parts").children())
            if (p.type() == pugi::node_element) read_part(p);
        for (const pugi::xml_node& a : child(root, "Assemblies").children())
            if (a.type() == pugi::node_element && local_name(a) == "Assembly") read_assembly_def(a);
        const pugi::xml_node assembly = child(root, "RootAssembly");
        if (!assembly) fail(root, "no <RootAssembly>: the file describes no assembly");
        model_.root_name = assembly.attribute("name").value();
        model_.root_uid = assembly.attribute("uid").value();
        model_.root_line = line(assembly);
        if (const pugi::xml_node tree = child(assembly, "InstanceTree"))
            for (const pugi::xml_node& i : tree.children())
                if (i.type() == pugi::node_element && local_name(i) == "Instance") read_instance(i, -1, 0);
        read_mechanism(assembly, model_.root);
        return std::move(model_);
    }

private:
    int line(const pugi::xml_node& n) const { return n ? lines_.line_of(n.offset_debug()) : 0; }

    [[noreturn]] void fail(const pugi::xml_node& n, const std::string& message) const {
        throw FileError(model_.file, line(n), message);
    }

    void note(const pugi::xml_node& n, mbx_severity severity, const char* code, const std::string& message) {
        mbx_memory::Diagnostic d;
        d.severity = severity;
        d.code = code;
        d.subject_kind = MBX_SUBJECT_FILE;
        d.subject_id = model_.file;
        d.file = model_.file;
        d.line = line(n);
        d.message = message;
        model_.diagnostics.push_back(std::move(d));
    }

    // XML's whitespace, without the locale lookup of std::isspace.
    static bool xml_space(char c) { return c == ' ' || c == '\n' || c == '\t' || c == '\r'; }

    // Exactly `count` numbers separated by whitespace: a child's text.
    void numbers(const pugi::xml_node& n, double* out, size_t count, const Who& who) const {
        std::string_view text = n.text().get();
        size_t k = 0;
        while (true) {
            size_t start = 0;
            while (start < text.size() && xml_space(text[start])) ++start;
            text.remove_prefix(start);
            if (text.empty()) break;
            size_t end = 0;
            while (end < text.size() && !xml_space(text[end])) ++end;
            const std::optional<double> x = parse_number(text.substr(0, end));
            if (!x) fail(n, who.str() + ": " + q(text.substr(0, end)) + " is not a finite number");
            if (k == count) fail(n, who.str() + ": more than " + std::to_string(count) + " numbers");
            out[k++] = *x;
            text.remove_prefix(end);
        }
        if (k != count)
            fail(n, who.str() + ": " + std::to_string(k) + " numbers where " + std::to_string(count) + " belong");
    }

    SimscapeTransform transform(const pugi::xml_node& t, const Who& who) const {
        SimscapeTransform out;
        if (!t) return out;
        const pugi::xml_node r = child(t, "Rotation"), p = child(t, "Translation");
        if (r) {
            double m[9];
            numbers(r, m, 9, who.with(" <Rotation>"));
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) out.rotation(i, j) = m[3 * i + j];
            const double error =
                (out.rotation.transpose() * out.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
            if (error > kRotationLimit || !(out.rotation.determinant() > 0))
                fail(r, who.str() + " <Rotation> is not a rotation (max |R^T R - I| = " + std::to_string(error) +
                            ", determinant " + std::to_string(out.rotation.determinant()) + ")");
        }
        if (p) {
            double v[3];
            numbers(p, v, 3, who.with(" <Translation>"));
            out.translation = Eigen::Vector3d(v[0], v[1], v[2]);
        }
        return out;
    }

    void read_units(const pugi::xml_node& root) {
        const pugi::xml_node display = child(root, "ModelUnits");
        model_.model_length_unit = display.attribute("length").value();
        model_.model_mass_unit = display.attribute("mass").value();
        const pugi::xml_node units = child(root, "DataUnits");
        if (!units) {
            // Older Link versions write none; their ModelUnits are only what a
            // Simulink import would display. The adapter tells the units from
            // the parts' STEP files where it can (data_units_inference.h).
            note(root, MBX_SEVERITY_WARNING, "simscape_no_data_units",
                 "no <DataUnits>: the numbers are taken as metres and kilograms");
            return;
        }
        model_.data_units_written = true;
        const std::string length = units.attribute("length").value(), mass = units.attribute("mass").value();
        try {
            model_.length_to_m = length.empty() ? 1.0 : unit_to_si(length, Quantity::length);
            model_.mass_to_kg = mass.empty() ? 1.0 : unit_to_si(mass, Quantity::mass);
        } catch (const UnitError& e) {
            fail(units, std::string("<DataUnits>: ") + e.what());
        }
    }

    void read_part(const pugi::xml_node& p) {
        if (local_name(p) != "Part") {
            note(p, MBX_SEVERITY_WARNING, "simscape_unknown_element",
                 "<" + std::string(local_name(p)) + "> in <Parts> is not a part; stepped over");
            return;
        }
        SimscapePart part;
        part.uid = p.attribute("uid").value();
        part.name = p.attribute("name").value();
        part.line = line(p);
        if (part.uid.empty()) fail(p, "part " + q(part.name) + " has no uid");
        const Who who("part", p.attribute("name").value());
        if (const pugi::xml_node mp = child(p, "MassProperties")) {
            part.has_mass_properties = true;
            double m = 0, c[3], i[6];
            const pugi::xml_node mass = child(mp, "Mass"), com = child(mp, "CenterOfMass"), inertia = child(mp, "Inertia");
            if (!mass || !com || !inertia) fail(mp, who.str() + ": <MassProperties> needs <Mass>, <CenterOfMass> and <Inertia>");
            numbers(mass, &m, 1, who.with(" <Mass>"));
            numbers(com, c, 3, who.with(" <CenterOfMass>"));
            numbers(inertia, i, 6, who.with(" <Inertia>"));
            if (m < 0) fail(mass, who.str() + ": a negative mass");
            part.mass = m;
            part.com = Eigen::Vector3d(c[0], c[1], c[2]);
            // Ixx Iyy Izz Iyz Izx Ixy, the products already as the tensor's entries.
            part.inertia << i[0], i[5], i[4], i[5], i[1], i[3], i[4], i[3], i[2];
        }
        if (const pugi::xml_node g = child(p, "GeometryFile")) {
            part.geometry_file = g.attribute("name").value();
            part.geometry_type = g.attribute("type").value();
            part.geometry_line = line(g);
        }
        if (const pugi::xml_node visual = child(p, "VisualProperties"))
            if (const pugi::xml_node diffuse = child(visual, "Diffuse")) {
                const char* keys[4] = {"r", "g", "b", "a"};
                bool ok = true;
                double rgba[4];
                for (int k = 0; k < 4; ++k) {
                    const std::optional<double> x = parse_number(diffuse.attribute(keys[k]).value());
                    ok = ok && x && *x >= 0 && *x <= 1;
                    rgba[k] = x ? *x : 0;
                }
                if (ok) {
                    part.has_colour = true;
                    std::copy(rgba, rgba + 4, part.colour);
                }
            }
        if (!parts_by_uid_.emplace(part.uid, int(model_.parts.size())).second)
            fail(p, who.str() + ": uid " + q(part.uid) + " names another part already");
        model_.parts.push_back(std::move(part));
    }

    void read_assembly_def(const pugi::xml_node& a) {
        SimscapeAssemblyDef def;
        def.uid = a.attribute("uid").value();
        def.name = a.attribute("name").value();
        def.line = line(a);
        read_mechanism(a, def.mechanism);
        if (!assemblies_by_uid_.emplace(def.uid, int(model_.assemblies.size())).second)
            fail(a, "assembly " + q(def.name) + ": uid " + q(def.uid) + " names another assembly already");
        model_.assemblies.push_back(std::move(def));
    }

    void read_instance(const pugi::xml_node& n, int parent, int depth) {
        if (depth >= kMaxInstanceDepth)
            fail(n, "instances nested deeper than " + std::to_string(kMaxInstanceDepth));
        SimscapeInstance in;
        in.uid = n.attribute("uid").value();
        in.name = n.attribute("name").value();
        in.entity_uid = n.attribute("entityUid").value();
        in.line = line(n);
        in.grounded = std::string_view(n.attribute("grounded").value()) == "true";
        in.rigid = std::string_view(n.attribute("rigid").value()) == "true";
        in.rigid_group = n.attribute("rigidGroup").value();
        in.parent = parent;
        const Who who("instance", n.attribute("name").value());
        if (in.uid.empty()) fail(n, who.str() + " has no uid");
        in.local = transform(child(n, "Transform"), who);
        if (const auto it = parts_by_uid_.find(in.entity_uid); it != parts_by_uid_.end()) in.part = it->second;
        else if (const auto a = assemblies_by_uid_.find(in.entity_uid); a != assemblies_by_uid_.end()) in.assembly = a->second;
        in.world.linear() = in.local.rotation;
        in.world.translation() = in.local.translation;
        if (parent >= 0) in.world = model_.instances[size_t(parent)].world * in.world;
        const int index = int(model_.instances.size());
        model_.instances.push_back(std::move(in));
        if (parent >= 0) model_.instances[size_t(parent)].children.push_back(index);
        else model_.top.push_back(index);
        // Children directly inside, or inside an <InstanceTree> of their own.
        for (const pugi::xml_node& c : n.children()) {
            if (c.type() != pugi::node_element) continue;
            if (local_name(c) == "Instance") read_instance(c, index, depth + 1);
            else if (local_name(c) == "InstanceTree")
                for (const pugi::xml_node& i : c.children())
                    if (i.type() == pugi::node_element && local_name(i) == "Instance") read_instance(i, index, depth + 1);
        }
        SimscapeInstance& self = model_.instances[size_t(index)];
        if (self.part < 0 && self.assembly < 0 && self.children.empty())
            note(n, MBX_SEVERITY_WARNING, "simscape_missing_part",
                 who.str() + " names " + (self.entity_uid.empty() ? std::string("no part") : "part " + q(self.entity_uid)) +
                     ", which the file does not hold; the instance is left out");
    }

    SimscapeFrameRef frame_ref(const pugi::xml_node& f, const Who& who) const {
        SimscapeFrameRef ref;
        ref.line = line(f);
        const pugi::xml_node path = child(f, "InstancePath");
        if (!path) fail(f, who.str() + ": no <InstancePath>");
        for (const pugi::xml_node& u : path.children())
            if (u.type() == pugi::node_element && local_name(u) == "Uid") ref.path.push_back(u.text().get());
        if (ref.path.empty()) fail(path, who.str() + ": an empty <InstancePath>");
        ref.transform = transform(child(f, "Transform"), who);
        return ref;
    }

    void read_mechanism(const pugi::xml_node& assembly, SimscapeMechanism& out) {
        for (const pugi::xml_node& j : child(assembly, "Joints").children()) {
            if (j.type() != pugi::node_element) continue;
            SimscapeJoint joint;
            joint.type = std::string(local_name(j));
            joint.name = j.attribute("name").value();
            joint.line = line(j);
            const Who who(local_name(j), j.attribute("name").value(), " joint");
            const pugi::xml_node base = child(j, "BaseFrame"), follower = child(j, "FollowerFrame");
            if (!base || !follower) fail(j, who.str() + " needs a <BaseFrame> and a <FollowerFrame>");
            joint.base = frame_ref(base, who.with(" <BaseFrame>"));
            joint.follower = frame_ref(follower, who.with(" <FollowerFrame>"));
            out.joints.push_back(std::move(joint));
        }
        for (const pugi::xml_node& c : child(assembly, "Constraints").children()) {
            if (c.type() != pugi::node_element) continue;
            SimscapeMate mate;
            mate.type = std::string(local_name(c));
            mate.name = c.attribute("name").value();
            mate.line = line(c);
            const Who who(local_name(c), c.attribute("name").value(), " mate");
            for (const pugi::xml_node& g : c.children()) {
                if (g.type() != pugi::node_element || local_name(g) != "ConstraintGeometry") continue;
                SimscapeMateGeometry geometry;
                geometry.line = line(g);
                geometry.geom_type = g.attribute("geomType").value();
                if (geometry.geom_type.empty()) geometry.geom_type = child(g, "GeomType").text().get();
                if (child(g, "InstancePath")) geometry.at = frame_ref(g, who);
                double v[3];
                if (const pugi::xml_node p = child(g, "Position")) {
                    numbers(p, v, 3, who.with(" <Position>"));
                    geometry.position = Eigen::Vector3d(v[0], v[1], v[2]);
                    geometry.has_position = true;
                }
                if (const pugi::xml_node a = child(g, "Axis")) {
                    numbers(a, v, 3, who.with(" <Axis>"));
                    geometry.axis = Eigen::Vector3d(v[0], v[1], v[2]);
                    geometry.has_axis = true;
                }
                mate.geometry.push_back(std::move(geometry));
            }
            out.mates.push_back(std::move(mate));
        }
    }

    const LineIndex& lines_;
    SimscapeModel model_;
    std::unordered_map<std::string, int> parts_by_uid_, assemblies_by_uid_;
};

}  // namespace

namespace {

// Parses `text` in place (it is the reader's own copy): pugixml's offsets
// are then those of the file, and nothing is copied again.
SimscapeModel parse_owned(char* text, size_t size, const std::string& file) {
    const LineIndex lines(std::string_view(text, size));
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed = doc.load_buffer_inplace(text, size, pugi::parse_default, pugi::encoding_utf8);
    if (!parsed)
        throw FileError(file, lines.line_of(parsed.offset), std::string("not well-formed XML: ") + parsed.description());
    return Reader(lines, file).run(doc);
}

}  // namespace

SimscapeModel parse_simscape(std::string_view text, const std::string& file) {
    std::string copy(text);
    return parse_owned(copy.data(), copy.size(), file);
}

SimscapeModel read_simscape(const std::string& path) {
    const FileBytes bytes = read_file_bytes(path);
    return parse_owned(bytes.data.get(), bytes.size, path);
}

}  // namespace mbx_files
