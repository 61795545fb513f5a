// The syntax tree of one VRML97 file, as the parser leaves it and the scene
// builder walks it. Field values are kept untyped (numbers, strings, bools or
// nodes): VRML's classic encoding can be parsed without knowing the field
// types, so unknown nodes and PROTO interfaces need no type tables, and the
// builder checks types only for the fields it uses.
#pragma once
#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "vrml_node_types.h"

namespace mbx_files::vrml {

struct AstNode;
struct ProtoDecl;

struct Value {
    enum class Kind : uint8_t { none, numbers, strings, bools, nodes, is };
    Kind kind = Kind::none;  // none: an empty list "[]"
    int line = 0;            // where the value starts
    std::vector<double> numbers;
    // (index of the first number on a line, that line), one entry per line
    // change: gives every number its line for messages without storing a
    // line per number.
    std::vector<std::pair<uint32_t, int>> number_lines;
    std::vector<std::string> strings;
    std::vector<uint8_t> bools;
    std::vector<const AstNode*> nodes;  // nullptr stands for NULL
    std::string is_name;                // Kind::is: the PROTO interface field it is bound to

    int line_of_number(size_t index) const;
};

struct Field {
    std::string name;
    int line = 0;
    Value value;
};

struct AstNode {
    std::string type_name;
    NodeType type = NodeType::unknown;
    const ProtoDecl* proto = nullptr;  // NodeType::proto_instance / externproto_instance
    std::string def_name;
    const std::string* file = nullptr;  // the ParsedFile's path
    int line = 0;
    std::vector<Field> fields;

    const Field* find(std::string_view name) const {
        for (const Field& f : fields)
            if (f.name == name) return &f;
        return nullptr;
    }
};

struct InterfaceField {
    enum class Kind : uint8_t { field, exposed_field, event_in, event_out };
    Kind kind = Kind::field;
    std::string type;  // "SFString", "MFNode", ...
    std::string name;
    int line = 0;
    Value default_value;  // Kind::field / exposed_field only; EXTERNPROTO: none
};

struct ProtoDecl {
    std::string name;
    int line = 0;
    bool external = false;  // EXTERNPROTO: interface only, instances stay empty
    bool defining = false;  // true while its body is parsed (catches self-instantiation)
    std::vector<InterfaceField> interface;
    std::vector<const AstNode*> body;  // node statements; the first one is what an instance is
    // Interface positions by name, filled once the interface is read when it
    // is large: instances look fields up once each, which must not be quadratic.
    std::unordered_map<std::string_view, int> index;

    int find(std::string_view field) const {
        if (!index.empty()) {
            const auto it = index.find(field);
            return it == index.end() ? -1 : it->second;
        }
        for (size_t i = 0; i < interface.size(); ++i)
            if (interface[i].name == field) return static_cast<int>(i);
        return -1;
    }
};

struct ParsedFile {
    std::string path;
    std::vector<const AstNode*> roots;  // top-level node statements (USE included)
    std::deque<AstNode> nodes;          // deque: addresses stay valid as it grows
    std::deque<ProtoDecl> protos;
    std::vector<std::string> warnings;  // "file:line: message"
};

}  // namespace mbx_files::vrml
