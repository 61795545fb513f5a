// A small, independent reader and checker for the Modelica the exporter
// writes (there is no Modelica tool on the build machines): a tokenizer and
// statement parser for one model, the MSL 4.0 class index (classes, their
// extends clauses and declared elements), structural checks against that
// index, and the composition of frame poses along the connect graph.
#pragma once
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/math.h"

namespace msl {

struct ClassInfo {
    std::string kind;
    std::vector<std::string> extends;   // as written in the library source
    std::vector<std::string> elements;  // declared in the class itself (public ones)
    // Classes read from generated files (Index::add) also know the class of
    // each element, so their connectors need no table.
    std::map<std::string, std::string> element_types;
};

class Index {
public:
    explicit Index(const std::string& tsv_path);
    size_t size() const { return classes_.size(); }
    bool has(const std::string& cls) const { return classes_.count(cls) != 0; }
    const ClassInfo* find(const std::string& cls) const;
    // Name lookup as Modelica does for an extends clause: from the enclosing
    // package of `context` outwards. "" when nothing matches.
    std::string resolve(const std::string& context, const std::string& name) const;
    // Elements declared in `cls` and every class it extends (transitively).
    std::set<std::string> elements(const std::string& cls) const;
    // `cls` and every class it extends (transitively), `cls` first.
    std::vector<std::string> lineage(const std::string& cls) const;
    // A class of the generated package (its model or block read back with
    // parse_model, see class_info), so models that use it can be checked.
    void add(const std::string& cls, ClassInfo info) { classes_[cls] = std::move(info); }

private:
    std::map<std::string, ClassInfo> classes_;
};

struct Modifier {
    std::string name;   // first identifier ("r_0" for "r_0(start = ...)")
    std::string value;  // source text after '=' ("" for a nested-only modification)
    std::string nested; // source text inside "( ... )" after the name, "" if none
};

struct Component {
    bool inner = false;
    std::vector<std::string> prefixes;  // parameter, discrete, constant, input, output, ... as written
    bool is_protected = false;
    std::string class_name, name, description;  // description unescaped
    std::string dimensions;  // text inside "[...]" after the name, "" if scalar
    std::string binding;     // text after "=" (declaration equation), "" if none
    std::vector<Modifier> modifiers;
    bool has_prefix(const std::string& p) const;
    const Modifier* modifier(const std::string& name) const;
    std::string value(const std::string& name) const;  // "" when absent
};

struct Model {
    std::string kind = "model";  // "model" or "block"
    std::string within, name, description;
    std::vector<std::string> extends;  // base classes, as written
    std::vector<Component> components;
    std::vector<std::pair<std::string, std::string>> connects;  // may end in a subscript: "table.y[1]"
    std::string annotation;          // text inside the model's annotation(...)
    std::vector<std::string> errors; // syntax problems found while parsing
    // Algorithm sections: the source text, and every name they use (the
    // first identifier of a dotted name) with the for-loop variables.
    std::string algorithm;
    std::set<std::string> algorithm_names, loop_variables;
    const Component* find(const std::string& name) const;
};

// One model or block as the exporter writes them: declarations (with
// prefixes, dimensions, modifiers, bindings), `extends`, `protected`, connect
// equations and algorithm sections (read as tokens: when/if/for nest to their
// `end`, names are collected for check_model).
Model parse_model(const std::string& text);

// What a parsed class offers to models that use it: its public components as
// elements, with their classes.
ClassInfo class_info(const Model& model);

// Structural problems: unknown classes, undeclared modifiers or connectors,
// connects between connectors of different kinds or to undeclared names,
// components nothing connects to, duplicate names; for signals (RealInput /
// RealOutput): every input of a component connected exactly once, from an
// output, and no two outputs joined; names used in algorithm sections that
// the class does not declare. Empty when clean.
std::vector<std::string> check_model(const Index& index, const Model& model);

double parse_number(const std::string& text);
mbx::Vec3 parse_vector(const std::string& text);  // "{x, y, z}"
bool parse_bool(const std::string& text);

// Pose of a component's frame_a -> frame_b motion for the composition below.
// Return false to leave the component out (its frames are not walked through).
using JointMotion = std::function<bool(const Component& joint, mbx::Pose& a_to_b)>;

struct FramePoses {
    std::map<std::string, mbx::Pose> pose;  // "component.connector" -> world pose
    std::vector<std::string> conflicts;     // frames reached twice with different poses
};

// World poses of every frame connector reachable from world.frame_b (and from
// free bodies' start poses) through connects, fixed frames (r, n_x, n_y read
// back) and joints (motion from `joint_motion`; a null function means every
// joint at zero).
FramePoses compose_frames(const Model& model, const JointMotion& joint_motion = {}, double tolerance = 1e-9);

}  // namespace msl
