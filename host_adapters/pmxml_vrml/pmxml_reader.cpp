#include "pmxml_reader.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <pugixml.hpp>

#include "core/input_file.h"
#include "host_adapters/common/line_index.h"
#include "host_adapters/common/numbers.h"
#include "pmxml_outline.h"
#include "pmxml_part_tree.h"
#include "host_adapters/common/units.h"
#include "host_adapters/common/text.h"

namespace mbx_files {
namespace {

// Subsystems mirror CAD sub-assemblies; real files nest 3 deep. The bound
// only keeps hostile input from exhausting the stack.
constexpr size_t kMaxSubsystemDepth = 64;
// The SDK refuses rotations further than this from orthonormal; refusing them
// here already lets the message carry a line number.
constexpr double kRotationLimit = 0.05;
// Bodies with more frames than this check their frame names with a set
// rather than by comparing each with all before it.
constexpr size_t kFewFrames = 16;

// A view into the parsed document, which outlives every use of it here;
// only what the model keeps is copied.
std::string_view unquote(std::string_view text) {
    text = trim(text);
    if (!text.empty() && text.front() == '"') text.remove_prefix(1);
    if (!text.empty() && text.back() == '"') text.remove_suffix(1);
    return trim(text);
}

// lower_case(text) == lowered, without building the lowered copy.
bool equals_lowered(std::string_view text, std::string_view lowered) {
    if (text.size() != lowered.size()) return false;
    for (size_t i = 0; i < text.size(); ++i)
        if (char(std::tolower(static_cast<unsigned char>(text[i]))) != lowered[i]) return false;
    return true;
}

std::string q(std::string_view s) { return "'" + std::string(s) + "'"; }

std::string join(const std::vector<std::string>& parts, const std::string& first) {
    std::string out = first;
    for (const std::string& p : parts) out += "/" + p;
    return out;
}

// The first child of each name in `names`, found in one pass. A <Frame> has a
// dozen children and pugi's child(name) walks them from the first each time,
// which made these lookups a large share of reading. Matches what child(name)
// would return: the first node with that name.
// Names are compared here rather than by strcmp: they are short, and the
// call cost more than the comparison.
template <class Node, size_t N>
std::array<Node, N> children_named(const Node& parent, const char* const (&names)[N]) {
    const auto same = [](const char* a, const char* b) {
        while (*a && *a == *b) ++a, ++b;
        return *a == *b;
    };
    std::array<Node, N> found{};
    for (Node c = parent.first_child(); c; c = c.next_sibling()) {
        const char* name = c.name();
        for (size_t k = 0; k < N; ++k)
            if (!found[k] && same(name, names[k])) {
                found[k] = c;
                break;
            }
    }
    return found;
}

// Names the element a message is about ("frame 'CS2' of body 'LINK_1'").
// Built only when a message is: reading a large file composed this text for
// every element, and almost none of them has anything wrong.
class Who {
public:
    Who(const char* kind, std::string_view name, const Who* owner = nullptr)
        : kind_(kind), name_(name), owner_(owner) {}
    std::string str() const {
        std::string s = std::string(kind_) + " " + q(name_);
        if (owner_) s += " of " + owner_->str();
        return s;
    }

private:
    const char* kind_;
    std::string_view name_;
    const Who* owner_;
};

std::string operator+(const Who& who, const char* text) { return who.str() + text; }

struct PendingJoint {
    pugi::xml_node node;  // in the whole DOM
    int part = -1;        // or the outline's element, read by parts
    size_t path;          // index into Reader::paths_
};

// Thrown where reading by parts gives up: the whole DOM is read instead,
// and says what is wrong if anything is.
struct ReadWholeDom {};

// String -> int by open addressing in one array. A 100k-part file holds a
// quarter of a million frame refs and as many body and joint ids;
// std::unordered_map's node per entry and its rehashing cost more than
// parsing the elements they come from.
class StringTable {
public:
    // The value already held for `key`, or -1 after storing `value` (>= 0) for it.
    int insert(std::string_view key, int value) {
        if (2 * (used_ + 1) > slots_.size()) grow();
        const uint32_t h = hash(key);
        Slot& s = slots_[probe(key, h)];
        if (s.value >= 0) return s.value;
        s.key = key;
        s.hash = h;
        s.value = value;
        ++used_;
        return -1;
    }
    // The value held for `key`, -1 if none.
    int find(std::string_view key) const {
        if (slots_.empty()) return -1;
        return slots_[probe(key, hash(key))].value;
    }

private:
    struct Slot {
        std::string key;
        uint32_t hash = 0;
        int value = -1;  // -1: empty
    };

    static uint32_t hash(std::string_view key) { return uint32_t(std::hash<std::string_view>()(key)); }

    // The slot holding `key`, else the empty slot where it belongs.
    size_t probe(std::string_view key, uint32_t h) const {
        const size_t mask = slots_.size() - 1;
        for (size_t i = h & mask;; i = (i + 1) & mask) {
            const Slot& s = slots_[i];
            if (s.value < 0 || (s.hash == h && s.key == key)) return i;
        }
    }

    void grow() {
        std::vector<Slot> old(std::max<size_t>(256, 2 * slots_.size()));
        old.swap(slots_);
        const size_t mask = slots_.size() - 1;
        for (Slot& s : old)
            if (s.value >= 0) {
                size_t i = s.hash & mask;
                while (slots_[i].value >= 0) i = (i + 1) & mask;
                slots_[i] = std::move(s);
            }
    }

    std::vector<Slot> slots_;  // a power of two in size, at most half full
    size_t used_ = 0;
};

// `id`, or the first of id~2, id~3, ... not in `used`; records it there.
std::string unique(StringTable& used, const std::string& id) {
    if (used.insert(id, 0) < 0) return id;
    for (int k = 2;; ++k) {
        std::string candidate = id + "~" + std::to_string(k);
        if (used.insert(candidate, 0) < 0) return candidate;
    }
}

// The file's text and the terminator the parser reads after it.
using TextBuffer = std::unique_ptr<char[]>;

TextBuffer allocate_buffer(size_t size) {
    TextBuffer p(new char[size + 1]);
    p[size] = '\0';
    return p;
}

class Reader {
public:
    // `text` holds `size` bytes of the file; `lines` indexes them. Both
    // outlive the reader.
    Reader(const char* text, size_t size, const LineIndex& lines, std::string file)
        : text_(text), size_(size), lines_(lines) {
        model_.file = std::move(file);
    }

    // Reads by parts (pmxml_outline.h): the outline of the file, then each
    // part parsed on its own from a copy of its text (pmxml_part_tree.h), so
    // the text stays as it is for run() should this give up. Gives up (nullopt) on what the
    // outline does not take and on any error, which run() then reports
    // exactly as it always has, XML errors before those of the content.
    std::optional<PmxmlModel> run_by_parts() {
        PmxmlOutline outline;
        if (!outline_pmxml(std::string_view(text_, size_), outline)) return std::nullopt;
        outline_ = &outline;
        // The model's vectors at their final size from the start: growing
        // them moved every frame (six strings and two Eigen blocks each)
        // about twice over (8 % of a 30k-part read's profile). Frames per part are an
        // estimate (4.4 in generated assemblies, about 8 in real exports: one
        // more growth there).
        size_t parts = 0, joints = 0;
        for (const OutlineElement& e : outline.elements)
            if (e.is_part()) ++(e.name == "SimpleJoint" ? joints : parts);
        model_.bodies.reserve(parts);
        model_.joints.reserve(joints);
        model_.frames.reserve(6 * parts);
        try {
            const OutlineElement& root = element(outline.root);
            if (root.name != "PhysicalModelingXMLFile") return std::nullopt;
            int container = -1;
            for (int c = root.first_child; c >= 0; c = element(c).next_sibling) {
                const std::string_view n = element(c).name;
                if (n != "SimMechanics" && n != "SimscapeMultibody") continue;
                if (container >= 0) return std::nullopt;
                container = c;
            }
            if (container < 0) return std::nullopt;
            model_.container = element(container).name;
            model_.created_using = text_of(outline.root, "createdUsing");
            model_.name = text_of(container, "name");
            if (model_.name.empty()) model_.name = text_of(outline.root, "name");
            paths_.emplace_back();
            walk(container, 0, 0);
            for (const PendingJoint& j : pending_joints_) read_joint(part(j.part), paths_[j.path]);
            assign_frame_ids();
        } catch (const ReadWholeDom&) {
            return std::nullopt;
        } catch (const FileError&) {
            return std::nullopt;
        }
        return std::move(model_);
    }

    // Reads the whole DOM, parsed in place in `writable`: the same text,
    // from allocate_buffer.
    PmxmlModel run(char* writable) {
        const pugi::xml_parse_result parsed = parse(writable);
        if (!parsed)
            throw FileError(model_.file, lines_.line_of(parsed.offset),
                            std::string("malformed XML: ") + parsed.description());
        const pugi::xml_node root = doc_.document_element();
        const std::string root_name = root.name();
        if (root_name == "SimMechanicsImportXML" || root_name == "SimscapeMultibodyImportXML")
            fail(root, "<" + root_name +
                           "> is second-generation Simscape Multibody import XML, not first-generation Physical Modeling "
                           "XML: open it as an input (mbx picks its reader by the root element)");
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

        paths_.emplace_back();
        walk(container, 0, 0);
        for (const PendingJoint& j : pending_joints_) read_joint(j.node, paths_[j.path]);
        assign_frame_ids();
        return std::move(model_);
    }

private:
    // In place, so the text is held once (as pugixml's own load_file holds
    // it), not once read and once copied. With its terminator the parser sees
    // the very bytes a copying load sees, so results and offsets are the same.
    // UTF-8 text, and Latin-1 text that is plain ASCII, is parsed where it
    // lies; any other encoding was converted into a copy, leaving the text
    // as read, and is loaded by copy as before (so are texts under 4 bytes,
    // whose encoding guess the terminator could change).
    pugi::xml_parse_result parse(char* text) {
        constexpr unsigned options = pugi::parse_default;
        if (size_ >= 4) {
            const pugi::xml_parse_result r = doc_.load_buffer_inplace(text, size_ + 1, options, pugi::encoding_auto);
            if (r.encoding == pugi::encoding_utf8) return r;
            if (r.encoding == pugi::encoding_latin1 &&
                std::all_of(text, text + size_, [](char c) { return (unsigned char)c < 0x80; }))
                return r;
        }
        return doc_.load_buffer(text, size_, options, pugi::encoding_auto);
    }

    const OutlineElement& element(int e) const { return outline_->elements[size_t(e)]; }

    // Part `e` of the outline, parsed into part_ (reused from part to part).
    PartNode part(int e) {
        const OutlineElement& p = element(e);
        if (!parse_part(std::string_view(text_ + p.part_begin, p.part_end - p.part_begin), p.part_begin,
                        outline_->conversions, part_))
            throw ReadWholeDom();
        return PartNode(&part_, 0);
    }

    template <class Node>
    int line(const Node& n) const {
        return lines_.line_of(n.offset_debug());
    }
    int line(int outline_element) const { return lines_.line_of(std::ptrdiff_t(element(outline_element).offset)); }

    template <class Node>
    [[noreturn]] void fail(const Node& n, const std::string& message) const {
        throw FileError(model_.file, line(n), message);
    }

    template <class Node>
    void warn(const Node& n, const char* code, mbx_subject_kind kind, const std::string& id,
              const std::string& name, const std::string& message) {
        warn(line(n), code, kind, id, name, message);
    }

    void warn(int line, const char* code, mbx_subject_kind kind, const std::string& id, const std::string& name,
              const std::string& message) {
        mbx_memory::Diagnostic d;
        d.severity = MBX_SEVERITY_WARNING;
        d.code = code;
        d.subject_kind = kind;
        d.subject_id = id;
        d.subject_name = name;
        d.file = model_.file;
        d.line = line;
        d.message = message;
        model_.diagnostics.push_back(std::move(d));
    }

    // Unquoted text of a node, "" for a null node.
    template <class Node>
    static std::string_view text(const Node& n) { return unquote(n.child_value()); }

    // Unquoted text of child `name`, "" if absent.
    template <class Node>
    static std::string_view text_of(const Node& parent, const char* name) {
        return text(parent.child(name));
    }
    std::string_view text_of(int outline_element, const char* name) const {
        const int c = outline_->child(outline_element, name);
        return c < 0 ? std::string_view() : unquote(element(c).text);
    }

    // `n`, the child `name` of `parent` if present.
    template <class Node>
    Node need(const Node& n, const Node& parent, const char* name,
                        const Who& who) const {
        if (!n) fail(parent, who + " has no <" + name + ">");
        return n;
    }

    template <class Node>
    double number(const Node& n, const Who& who) const {
        const std::string_view t = text(n);
        const std::optional<double> v = parse_number(t);
        if (!v) fail(n, who + ": <" + n.name() + "> is not a number: " + q(t));
        return *v;
    }

    template <class Node>
    void numbers(const Node& n, double* out, size_t count, const Who& who) const {
        const std::string_view t = text(n);
        if (!parse_number_list(t, out, count))
            fail(n, who + ": <" + n.name() + "> needs " + std::to_string(count) + " comma-separated numbers, got " +
                        q(t));
    }

    template <class Node>
    double unit(const Node& n, Quantity quantity, const Who& who) {
        const std::string_view t = text(n);
        // A file states the same few units on every element; unit_to_si is
        // pure, so the last good answer per quantity is reused.
        UnitMemo& memo = units_[size_t(quantity)];
        if (memo.valid && memo.text == t) return memo.factor;
        try {
            const double factor = unit_to_si(t, quantity);
            memo = {true, std::string(t), factor};
            return factor;
        } catch (const UnitError& e) {
            fail(n, who + ": <" + n.name() + ">: " + e.what());
        }
    }

    // The unit of a value that may omit it when the value is zero (massless
    // helpers written by hand); otherwise the unit is as critical as the value.
    // `n` is the child `name` of `parent`, or null.
    template <class Node>
    double unit_or_si(const Node& n, const Node& parent, const char* name, bool value_is_zero,
                      Quantity quantity, std::string& unit_text, const Who& who) {
        if (!n || text(n).empty()) {
            if (!value_is_zero) fail(n ? n : parent, who + " has no <" + name + ">");
            unit_text = "";
            return 1.0;
        }
        unit_text = text(n);
        return unit(n, quantity, who);
    }

    // `path` indexes paths_, the enclosing Subsystem names.
    void walk(const pugi::xml_node& node, size_t path, size_t depth) {
        for (pugi::xml_node b : node.child("bodies").children("Body")) read_body(b, paths_[path]);
        for (pugi::xml_node j : node.child("joints").children("SimpleJoint"))
            pending_joints_.push_back({j, -1, path});
        for (pugi::xml_node g : node.child("grounds").children("Ground")) read_ground(g, paths_[path]);
        for (pugi::xml_node s : node.child("subsystems").children("Subsystem")) {
            if (depth + 1 > kMaxSubsystemDepth)
                fail(s, "subsystems nested deeper than " + std::to_string(kMaxSubsystemDepth));
            std::string name(text_of(s, "name"));
            if (name.empty()) name = text_of(s, "nodeID");
            if (name.empty()) name = "Subsystem@" + std::to_string(line(s));
            const std::string_view status = text_of(s, "status");
            if (!status.empty())
                warn(s, "pmxml_subsystem_status", MBX_SUBJECT_MODEL, name, name,
                     "the exporter reports on subsystem " + q(name) + ": " + std::string(status));
            std::vector<std::string> inner = paths_[path];
            inner.push_back(name);
            paths_.push_back(std::move(inner));
            walk(s, paths_.size() - 1, depth + 1);
        }
    }

    // The same walk over the outline; parts are parsed as they are reached.
    void walk(int node, size_t path, size_t depth) {
        const auto each = [&](const char* list, std::string_view name, auto&& visit) {
            const int l = outline_->child(node, list);
            if (l < 0) return;
            for (int c = element(l).first_child; c >= 0; c = element(c).next_sibling)
                if (element(c).name == name) visit(c);
        };
        each("bodies", "Body", [&](int b) { read_body(part(b), paths_[path]); });
        each("joints", "SimpleJoint", [&](int j) { pending_joints_.push_back({pugi::xml_node(), j, path}); });
        each("grounds", "Ground", [&](int g) { read_ground(part(g), paths_[path]); });
        each("subsystems", "Subsystem", [&](int s) {
            if (depth + 1 > kMaxSubsystemDepth) throw ReadWholeDom();
            std::string name(text_of(s, "name"));
            if (name.empty()) name = text_of(s, "nodeID");
            if (name.empty()) name = "Subsystem@" + std::to_string(line(s));
            const std::string_view status = text_of(s, "status");
            if (!status.empty())
                warn(line(s), "pmxml_subsystem_status", MBX_SUBJECT_MODEL, name, name,
                     "the exporter reports on subsystem " + q(name) + ": " + std::string(status));
            std::vector<std::string> inner = paths_[path];
            inner.push_back(name);
            paths_.push_back(std::move(inner));
            walk(s, paths_.size() - 1, depth + 1);
        });
    }

    template <class Node>
    int read_frame(const Node& f, int body, const Who& body_who, int position_in_body) {
        static constexpr const char* kNames[] = {"name",           "displayName",   "nodeID",
                                                 "position",       "positionUnits", "orientation",
                                                 "positionOrigin", "positionReferenceFrame",
                                                 "orientationReferenceFrame",       "orientationType"};
        const auto c = children_named(f, kNames);
        PmxmlFrame fr;
        fr.line = line(f);
        fr.body = body;
        fr.name = text(c[0]);
        if (fr.name.empty()) fr.name = "frame" + std::to_string(position_in_body + 1);
        const Who who("frame", fr.name, &body_who);
        fr.display_name = text(c[1]);
        fr.node_id = text(c[2]);

        double p[3], o[9];
        numbers(need(c[3], f, "position", who), p, 3, who);
        const Node units = need(c[4], f, "positionUnits", who);
        fr.length_unit = text(units);
        fr.length_to_m = unit(units, Quantity::length, who);
        numbers(need(c[5], f, "orientation", who), o, 9, who);
        for (size_t k = 6; k < 9; ++k) {
            const Node n = c[k];
            const std::string_view value = text(n);
            if (n && !equals_lowered(value, "world"))
                fail(n, who + ": <" + kNames[k] + "> is " + q(value) +
                            "; only WORLD is supported (every pose must be absolute)");
        }
        if (const Node n = c[9]) {
            const std::string_view value = text(n);
            if (!equals_lowered(value, "3x3 transform"))
                fail(n, who + ": <orientationType> is " + q(value) + "; only '3x3 Transform' is supported");
        }
        fr.position = Eigen::Vector3d(p[0], p[1], p[2]);
        // Column-major: o1..o3 are the frame's x axis in world (FORMAT_NOTES 5.1).
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) fr.rotation(i, j) = o[3 * j + i];
        const double error =
            (fr.rotation.transpose() * fr.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
        if (error > kRotationLimit || !(fr.rotation.determinant() > 0))
            fail(c[5], who + ": <orientation> is not a rotation matrix (max |R^T R - I| = " + std::to_string(error) +
                           ", determinant " + std::to_string(fr.rotation.determinant()) + ")");

        if (const auto ref = f.attribute("ref")) {
            // The view stays valid: it points into the document, not the frame.
            const std::string_view key = trim(ref.value());
            fr.ref = key;
            if (fr.ref.empty()) fail(f, who + " has an empty ref attribute");
            const int defined = refs_.insert(key, int(model_.frames.size()));
            if (defined >= 0) {
                const PmxmlFrame& other = model_.frames[size_t(defined)];
                fail(f, who + " defines frame ref " + fr.ref + ", already defined by frame " + q(other.name) +
                            " at line " + std::to_string(other.line) + "; refs must be unique in the file");
            }
        }
        fr.to_host = !fr.ref.empty() || (fr.name != "CG" && fr.name != "CS1");
        model_.frames.push_back(std::move(fr));  // its id comes in assign_frame_ids
        return int(model_.frames.size() - 1);
    }

    // Frame ids are "<body id>::<frame name>", made unique with "~k" in file
    // order. Body ids are unique, so two frame ids can only meet across bodies
    // if a frame name holds "::" ("a::b" + "c" against "a" + "b::c");
    // otherwise only a body's own frames, which are consecutive, can collide
    // with its next frame, and checking those few spares a set of every frame
    // id in the file (the reader's largest cost at 100k parts).
    void assign_frame_ids() {
        std::vector<PmxmlFrame>& frames = model_.frames;
        const bool separator_in_names = std::any_of(frames.begin(), frames.end(), [](const PmxmlFrame& f) {
            return f.name.find("::") != std::string::npos;
        });
        if (separator_in_names) {
            StringTable used;
            for (PmxmlFrame& f : frames) f.id = unique(used, model_.bodies[size_t(f.body)].id + "::" + f.name);
            return;
        }
        std::vector<std::string> used;  // this body's frame names so far, with their ~k
        for (size_t first = 0; first < frames.size();) {
            size_t end = first + 1;
            while (end < frames.size() && frames[end].body == frames[first].body) ++end;
            const std::string prefix = model_.bodies[size_t(frames[first].body)].id + "::";
            if (end - first > kFewFrames) {
                StringTable many;
                for (size_t i = first; i < end; ++i) frames[i].id = prefix + unique(many, frames[i].name);
            } else {
                used.clear();
                for (size_t i = first; i < end; ++i) {
                    const auto taken = [&](const std::string& s) {
                        return std::find(used.begin(), used.end(), s) != used.end();
                    };
                    std::string name = frames[i].name;
                    for (int k = 2; taken(name); ++k) name = frames[i].name + "~" + std::to_string(k);
                    used.push_back(name);
                    frames[i].id = prefix + name;
                }
            }
            first = end;
        }
    }

    template <class Node>
    std::string body_id(const Node& n, const std::string& wanted, const std::string& name) {
        std::string id = unique(body_ids_, wanted);
        if (id != wanted)
            warn(n, "pmxml_duplicate_id", MBX_SUBJECT_BODY, id, name,
                 "body id " + q(wanted) + " is used twice; this body is " + q(id));
        return id;
    }

    template <class Node>
    void read_body(const Node& b, const std::vector<std::string>& path) {
        static constexpr const char* kNames[] = {"name",         "nodeID", "mass",   "massUnits",
                                                 "volume",       "volumeUnits",      "inertia",
                                                 "inertiaUnits", "frames", "geometryFileName", "status"};
        const auto c = children_named(b, kNames);
        PmxmlBody body;
        body.line = line(b);
        body.subsystem_path = path;
        body.name = text(c[0]);
        body.node_id = text(c[1]);
        if (body.name.empty() && body.node_id.empty()) fail(b, "a <Body> has neither a <name> nor a <nodeID>");
        if (body.name.empty()) body.name = body.node_id;
        body.id = body_id(b, body.node_id.empty() ? join(path, model_.name) + "/" + body.name : body.node_id,
                          body.name);
        if (body.name == "RootPart") body.flags |= MBX_BODY_HELPER;
        const Who who("body", body.name);

        body.mass = number(need(c[2], b, "mass", who), who);
        body.mass_to_kg = unit_or_si(c[3], b, "massUnits", body.mass == 0, Quantity::mass, body.mass_unit, who);
        if (const Node v = c[4]; v && !text(v).empty()) {
            body.volume = number(v, who);
            std::string volume_unit;
            body.volume_to_m3 =
                unit_or_si(c[5], b, "volumeUnits", body.volume == 0, Quantity::volume, volume_unit, who);
        }
        double inertia[9];
        numbers(need(c[6], b, "inertia", who), inertia, 9, who);
        bool zero = true;
        for (double v : inertia) zero = zero && v == 0;
        body.inertia_to_kg_m2 =
            unit_or_si(c[7], b, "inertiaUnits", zero, Quantity::inertia, body.inertia_unit, who);
        Eigen::Matrix3d tensor;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) tensor(i, j) = inertia[3 * i + j];

        const int index = int(model_.bodies.size());
        const Node frames = need(c[8], b, "frames", who);
        int k = 0;
        for (Node f : frames.children("Frame")) {
            const int fi = read_frame(f, index, who, k++);
            const std::string& name = model_.frames[size_t(fi)].name;
            if (name == "CS1" && body.cs1 < 0) body.cs1 = fi;
            if (name == "CG" && body.cg < 0) body.cg = fi;
        }
        if (body.cs1 < 0) fail(frames, who + " has no CS1 frame (its part frame)");
        if (body.cg < 0) {
            if (body.mass != 0) fail(frames, who + " has a mass but no CG frame");
            body.cg = body.cs1;
        }
        if (const Node g = c[9]) {
            body.geometry_file = text(g);
            body.geometry_line = line(g);
        }
        const std::string_view status = text(c[10]);
        if (!status.empty())
            warn(b, "pmxml_body_status", MBX_SUBJECT_BODY, body.id, body.name,
                 "the exporter reports on body " + q(body.name) + ": " + std::string(status));

        // The SDK wants the centre of mass in the body (CS1) frame and the
        // tensor in its axes; the file gives the CG in world and the tensor
        // in CG axes (equal to CS1's in every real file, but not by rule).
        const PmxmlFrame& cs1 = model_.frames[size_t(body.cs1)];
        const PmxmlFrame& cg = model_.frames[size_t(body.cg)];
        const Eigen::Matrix3d r_cs1 = nearest_rotation(cs1.rotation);
        const Eigen::Matrix3d r_cg = body.cg == body.cs1 ? r_cs1 : nearest_rotation(cg.rotation);
        const Eigen::Vector3d cg_position = cg.position * (cg.length_to_m / cs1.length_to_m);
        body.com = r_cs1.transpose() * (cg_position - cs1.position);
        if ((r_cs1 - r_cg).cwiseAbs().maxCoeff() > 1e-12) {
            const Eigen::Matrix3d cg_in_cs1 = r_cs1.transpose() * r_cg;
            tensor = cg_in_cs1 * tensor * cg_in_cs1.transpose();
        }
        body.inertia = tensor;
        model_.bodies.push_back(std::move(body));
    }

    template <class Node>
    void read_ground(const Node& g, const std::vector<std::string>& path) {
        PmxmlBody body;
        body.line = line(g);
        body.subsystem_path = path;
        body.name = text_of(g, "name");
        body.node_id = text_of(g, "nodeID");
        if (body.name.empty()) body.name = body.node_id.empty() ? "RootGround" : body.node_id;
        body.id = body_id(g, body.node_id.empty() ? body.name : body.node_id, body.name);
        // The world's datum, not a CAD part: ground and massless helper.
        body.flags = MBX_BODY_GROUND | MBX_BODY_HELPER;
        const Who who("ground", body.name);
        Node f = g.child("frame").child("Frame");
        if (!f) f = g.child("Frame");
        if (!f) fail(g, who + " has no <frame><Frame>");
        const int index = int(model_.bodies.size());
        body.cs1 = read_frame(f, index, who, 0);
        model_.bodies.push_back(std::move(body));
    }

    // `side` is the child `role` of joint `j`, or null.
    template <class Node>
    int end_frame(const Node& j, const Node& side, const char* role, const Who& who) const {
        if (!side) fail(j, who + " has no <" + role + ">");
        const Node frame =
            side.find_node([](const auto& n) { return std::strcmp(n.name(), "Frame") == 0; });
        if (!frame) fail(side, who + ": <" + role + "> names no <Frame ref=...>");
        const std::string_view ref = trim(frame.attribute("ref").value());
        if (ref.empty()) fail(frame, who + ": the " + role + " <Frame> has no ref");
        const int defined = refs_.find(ref);
        if (defined < 0)
            fail(frame, who + " refers to " + role + " frame ref " + std::string(ref) +
                            ", which no Frame in the file defines");
        return defined;
    }

    template <class Node>
    PmxmlPrimitive read_primitive(const Node& p, const Who& who) const {
        PmxmlPrimitive prim;
        prim.line = line(p);
        static constexpr const char* kNames[] = {"name", "referenceFrame", "axis"};
        const auto c = children_named(p, kNames);
        const std::string_view raw_name = text(c[0]);
        if (equals_lowered(raw_name, "weld"))
            prim.type = MBX_PRIMITIVE_WELD;
        else if (equals_lowered(raw_name, "prismatic"))
            prim.type = MBX_PRIMITIVE_PRISMATIC;
        else if (equals_lowered(raw_name, "revolute"))
            prim.type = MBX_PRIMITIVE_REVOLUTE;
        else if (equals_lowered(raw_name, "spherical"))
            prim.type = MBX_PRIMITIVE_SPHERICAL;
        else
            fail(p, who + " has unknown primitive " + q(raw_name) +
                        " (known: weld, prismatic, revolute, spherical)");
        // A weld's axis is a dummy and a spherical joint has none.
        if (prim.type != MBX_PRIMITIVE_REVOLUTE && prim.type != MBX_PRIMITIVE_PRISMATIC) return prim;
        const std::string name = lower_case(raw_name);
        if (const Node reference = c[1]) {
            const std::string_view value = text(reference);
            if (!value.empty() && !equals_lowered(value, "world"))
                fail(reference, who + ": the " + name + " axis is given in " + q(value) + "; only WORLD is supported");
        }
        double a[3];
        const Node axis = c[2];
        if (!axis) fail(p, who + "'s " + name + " primitive has no <axis>");
        numbers(axis, a, 3, who);
        prim.axis = Eigen::Vector3d(a[0], a[1], a[2]);
        if (!(prim.axis.norm() > 1e-9)) fail(axis, who + " has a zero-length " + name + " axis");
        return prim;
    }

    template <class Node>
    void read_joint(const Node& j, const std::vector<std::string>& path) {
        static constexpr const char* kNames[] = {"name", "nodeID", "base", "follower", "primitives", "status"};
        const auto c = children_named(j, kNames);
        PmxmlJoint joint;
        joint.line = line(j);
        joint.subsystem_path = path;
        joint.name = text(c[0]);
        joint.node_id = text(c[1]);
        if (joint.name.empty())
            joint.name = joint.node_id.empty() ? "joint@" + std::to_string(joint.line) : joint.node_id;
        const std::string wanted = joint.node_id.empty() ? joint.name : joint.node_id;
        joint.id = unique(joint_ids_, wanted);
        if (joint.id != wanted)
            warn(j, "pmxml_duplicate_id", MBX_SUBJECT_CONSTRAINT, joint.id, joint.name,
                 "joint id " + q(wanted) + " is used twice; this joint is " + q(joint.id));
        const Who who("joint", joint.name);
        joint.base_frame = end_frame(j, c[2], "base", who);
        joint.follower_frame = end_frame(j, c[3], "follower", who);
        const Node primitives = c[4];
        if (!primitives) fail(j, who + " has no <primitives>");
        for (Node p : primitives.children("Primitive")) joint.primitives.push_back(read_primitive(p, who));
        if (joint.primitives.empty()) fail(primitives, who + " has no <Primitive>");
        joint.status = text(c[5]);
        model_.joints.push_back(std::move(joint));
    }

    struct UnitMemo {
        bool valid = false;
        std::string text;
        double factor = 1;
    };

    const char* text_;
    size_t size_;
    const LineIndex& lines_;
    pugi::xml_document doc_;
    const PmxmlOutline* outline_ = nullptr;  // while reading by parts
    PartTree part_;                          // the part being read
    PmxmlModel model_;
    StringTable refs_;  // frame ref -> frame index
    StringTable body_ids_, joint_ids_;
    std::vector<std::vector<std::string>> paths_;  // of the subsystems walked, [0] the top level
    std::vector<PendingJoint> pending_joints_;
    UnitMemo units_[5];  // by Quantity
};

}  // namespace

// Text is copied and read in chunks of this size, each indexed for lines
// while it is still in the cache.
constexpr size_t kChunk = size_t(1) << 20;

namespace {

// `writable`: the same text in a buffer from allocate_buffer, in which the
// whole DOM may be parsed in place; null: a copy is made should it be needed.
PmxmlModel read_text(const char* text, size_t size, char* writable, const LineIndex& lines, const std::string& file,
                     PmxmlParse how, PmxmlParse* used) {
    if (how != PmxmlParse::whole_dom) {
        Reader by_parts(text, size, lines, file);
        if (std::optional<PmxmlModel> m = by_parts.run_by_parts()) {
            if (used) *used = PmxmlParse::by_parts;
            return std::move(*m);
        }
    }
    if (used) *used = PmxmlParse::whole_dom;
    TextBuffer copy;
    if (!writable) {
        copy = allocate_buffer(size);
        std::memcpy(copy.get(), text, size);
        writable = copy.get();
    }
    return Reader(text, size, lines, file).run(writable);
}

// A file mapped into memory, read-only and populated up front: reading by
// parts copies nothing out of the page cache (read() copied the whole file
// and faulted in as many pages again for the copy).
class MappedFile {
public:
    // False where the file cannot be mapped (empty, not a regular file).
    bool map(const std::string& path) {
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return false;
        struct stat st {};
        if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
            void* p = ::mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
            if (p != MAP_FAILED) data_ = static_cast<const char*>(p), size_ = size_t(st.st_size);
        }
        ::close(fd);
        return data_ != nullptr;
    }
    ~MappedFile() {
        if (data_) ::munmap(const_cast<char*>(data_), size_);
    }
    const char* data() const { return data_; }
    size_t size() const { return size_; }

private:
    const char* data_ = nullptr;
    size_t size_ = 0;
};

}  // namespace

PmxmlModel parse_pmxml(std::string_view text, const std::string& file, PmxmlParse how, PmxmlParse* used) {
    TextBuffer buffer = allocate_buffer(text.size());
    LineIndex lines;
    for (size_t at = 0; at < text.size(); at += kChunk) {
        const size_t n = std::min(kChunk, text.size() - at);
        std::memcpy(buffer.get() + at, text.data() + at, n);
        lines.append(text.substr(at, n));
    }
    return read_text(buffer.get(), text.size(), buffer.get(), lines, file, how, used);
}

PmxmlModel read_pmxml(const std::string& path, PmxmlParse how, PmxmlParse* used) {
    if (const std::string why = mbx::input_file_problem(path); !why.empty()) throw FileError(path, 0, why);
    if (how != PmxmlParse::whole_dom) {
        MappedFile mapped;
        if (mapped.map(path)) {
            LineIndex lines;
            for (size_t at = 0; at < mapped.size(); at += kChunk)
                lines.append(std::string_view(mapped.data() + at, std::min(kChunk, mapped.size() - at)));
            return read_text(mapped.data(), mapped.size(), nullptr, lines, path, how, used);
        }
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path, 0, std::string("cannot open the file: ") + std::strerror(errno));
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(0, std::ios::beg);
    if (size < 0) throw FileError(path, 0, "cannot read the file");
    // Straight into the buffer the parser works in: the text is held once.
    TextBuffer text = allocate_buffer(size_t(size));
    LineIndex lines;
    for (size_t at = 0; at < size_t(size); at += kChunk) {
        const size_t n = std::min(kChunk, size_t(size) - at);
        in.read(text.get() + at, std::streamsize(n));
        if (size_t(in.gcount()) != n) throw FileError(path, 0, "cannot read the file");
        lines.append(std::string_view(text.get() + at, n));
    }
    return read_text(text.get(), size_t(size), text.get(), lines, path, how, used);
}

}  // namespace mbx_files
