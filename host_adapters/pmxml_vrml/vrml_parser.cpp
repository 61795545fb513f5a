#include "vrml_parser.h"

#include <cctype>
#include <set>
#include <unordered_map>

#include "vrml_lexer.h"
#include "vrml_message.h"

namespace mbx_files::vrml {

namespace {

bool is_keyword(std::string_view s) {
    static constexpr std::string_view keywords[] = {"DEF",     "USE",      "PROTO", "EXTERNPROTO", "ROUTE",
                                                    "TO",      "IS",       "NULL",  "TRUE",        "FALSE",
                                                    "eventIn", "eventOut", "field", "exposedField"};
    for (std::string_view k : keywords)
        if (k == s) return true;
    return false;
}

// "nan", "inf" and "infinity" in any case: what printf writes for
// non-finite doubles, so what a broken exporter leaves in a number list.
bool is_non_finite_word(std::string_view s) {
    auto eq = [&](std::string_view w) {
        if (s.size() != w.size()) return false;
        for (size_t i = 0; i < s.size(); ++i)
            if (std::tolower(static_cast<unsigned char>(s[i])) != w[i]) return false;
        return true;
    };
    return eq("nan") || eq("inf") || eq("infinity");
}

const char* kind_name(Value::Kind k) {
    switch (k) {
        case Value::Kind::numbers: return "numbers";
        case Value::Kind::strings: return "strings";
        case Value::Kind::bools: return "booleans";
        case Value::Kind::nodes: return "nodes";
        default: return "values";
    }
}

void check_header(std::string_view& text, const std::string& path, std::vector<std::string>& warnings) {
    if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    if (text.size() >= 2 && static_cast<unsigned char>(text[0]) == 0x1f && static_cast<unsigned char>(text[1]) == 0x8b)
        throw VrmlError(path, 1, "file is gzip-compressed; decompress it (gunzip) before reading");
    std::string_view first = text.substr(0, text.find('\n'));
    if (!first.empty() && first.back() == '\r') first.remove_suffix(1);
    auto starts = [&](std::string_view p) { return first.substr(0, p.size()) == p; };
    if (starts("#VRML V2.0")) {
        std::string_view rest = first.substr(10);
        while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t')) rest.remove_prefix(1);
        if (rest.substr(0, 4) != "utf8")
            warnings.push_back(path + ":1: header does not say 'utf8'; read as VRML97 utf8 anyway");
        return;
    }
    if (starts("#VRML V1.0"))
        throw VrmlError(path, 1, "VRML V1.0 is not supported: only VRML97 files ('#VRML V2.0 utf8') can be read");
    if (starts("#VRML"))
        throw VrmlError(path, 1,
                        "unsupported VRML version in header " + quoted_excerpt(first) +
                            ": only VRML97 ('#VRML V2.0 utf8') can be read");
    if (starts("#X3D"))
        throw VrmlError(path, 1,
                        "X3D classic encoding (" + quoted_excerpt(first) +
                            ") is not supported: only VRML97 ('#VRML V2.0 utf8') can be read");
    throw VrmlError(path, 1, "not a VRML97 file: the first line must be '#VRML V2.0 utf8'");
}

class Parser {
public:
    Parser(std::string_view text, ParsedFile& out, const VrmlLimits& limits, ReadBudget& budget,
           const StackGuard& stack)
        : lex_(text, out.path), out_(out), limits_(limits), budget_(budget), stack_(stack) {}

    void parse_file() {
        scopes_.emplace_back();
        while (lex_.peek().kind != Tok::eof) parse_statement(&out_.roots, 0);
    }

private:
    struct Scope {
        std::unordered_map<std::string, const AstNode*> defs;
        std::unordered_map<std::string, ProtoDecl*> protos;
        const ProtoDecl* body_of = nullptr;  // the PROTO whose body this is; IS refers to its interface
    };

    const Token& peek() const { return lex_.peek(); }
    bool peek_word(std::string_view w) const { return peek().kind == Tok::identifier && peek().text == w; }

    // ---- messages, out of line (see vrml_message.h) ----

    [[noreturn]] MBX_VRML_COLD void fail(int line, std::initializer_list<Piece> pieces) const {
        lex_.fail(line, join(pieces));
    }
    [[noreturn]] MBX_VRML_COLD void fail_found(const char* expected, const Token& t) const {
        fail(t.line, {"expected ", expected, ", found ", t});
    }
    MBX_VRML_COLD void warn(int line, std::initializer_list<Piece> pieces) {
        out_.warnings.push_back(out_.path + ":" + std::to_string(line) + ": " + join(pieces));
    }
    [[noreturn]] MBX_VRML_COLD void fail_nesting(int line) const {
        if (stack_.exhausted()) fail(line, {"nodes nested too deeply for the stack left to the reader"});
        fail(line, {"nodes nested deeper than max_depth (", limits_.max_depth, ")"});
    }

    void check_nesting(size_t depth, int line) const {
        if (depth >= limits_.max_depth || stack_.exhausted()) fail_nesting(line);
    }

    std::string expect_identifier(const char* what) {
        const Token& t = peek();
        if (t.kind != Tok::identifier) fail_found(what, t);
        std::string s(t.text);
        lex_.advance();
        return s;
    }

    void expect(Tok kind, const char* what) {
        if (peek().kind != kind) fail_found(what, peek());
        lex_.advance();
    }

    void count_value(int line) {
        if (++budget_.values > limits_.max_total_values)
            fail(line, {"more than max_total_values (", limits_.max_total_values, ") values"});
    }

    void reject_non_finite_word(const Token& t) const {
        if (t.kind == Tok::identifier && is_non_finite_word(t.text))
            fail(t.line, {"non-finite number ", Piece::quoted(t.text)});
    }

    // ---- statements and nodes ----

    // Statements of a file or PROTO body: nodes go to `into`.
    void parse_statement(std::vector<const AstNode*>* into, size_t depth) {
        if (peek_word("PROTO")) return parse_proto(depth);
        if (peek_word("EXTERNPROTO")) return parse_externproto(depth);
        if (peek_word("ROUTE")) return parse_route();
        const AstNode* n = parse_node_statement(depth, false);
        if (into) into->push_back(n);
    }

    const AstNode* parse_node_statement(size_t depth, bool allow_null) {
        const Token& t = peek();
        if (t.kind != Tok::identifier) fail_found("a node", t);
        if (t.text == "DEF") {
            lex_.advance();
            std::string name = expect_identifier("a name after DEF");
            AstNode* n = parse_node(depth);
            // Bound only now: a USE inside the node's own body cannot see
            // it, so DEF/USE can never form a cycle.
            bind_def(n, std::move(name));
            return n;
        }
        if (t.text == "USE") return parse_use();
        if (t.text == "NULL" && allow_null) {
            lex_.advance();
            return nullptr;
        }
        return parse_node(depth);
    }

    MBX_VRML_COLD void bind_def(AstNode* n, std::string name) {
        n->def_name = name;
        scopes_.back().defs[std::move(name)] = n;
    }

    MBX_VRML_COLD const AstNode* parse_use() {
        const int line = peek().line;
        lex_.advance();
        const std::string name = expect_identifier("a name after USE");
        const auto& defs = scopes_.back().defs;
        const auto it = defs.find(name);
        if (it == defs.end()) fail(line, {"USE of undefined DEF '", name, "'"});
        return it->second;
    }

    const ProtoDecl* find_proto(const std::string& name) const {
        for (auto s = scopes_.rbegin(); s != scopes_.rend(); ++s) {
            const auto it = s->protos.find(name);
            if (it != s->protos.end()) return it->second;
        }
        return nullptr;
    }

    AstNode* parse_node(size_t depth) {
        const Token& t = peek();
        if (t.kind != Tok::identifier) fail_found("a node type", t);
        check_nesting(depth, t.line);
        AstNode& n = start_node(t);
        lex_.advance();
        if (peek().kind != Tok::lbrace) fail_after_type(n);
        lex_.advance();
        parse_body(n, depth);
        return &n;
    }

    // The node for type token `t`, its type resolved.
    MBX_VRML_COLD AstNode& start_node(const Token& t) {
        reject_non_finite_word(t);
        if (is_keyword(t.text)) fail(t.line, {"expected a node type, found keyword ", Piece::quoted(t.text)});
        if (++budget_.parsed_nodes > limits_.max_nodes)
            fail(t.line, {"more than max_nodes (", limits_.max_nodes, ") nodes"});
        AstNode& n = out_.nodes.emplace_back();
        n.type_name = std::string(t.text);
        n.file = &out_.path;
        n.line = t.line;
        if (const ProtoDecl* p = find_proto(n.type_name)) {
            if (p->defining)
                fail(t.line, {"PROTO '", p->name, "' is instantiated inside its own body (recursive PROTO)"});
            n.proto = p;
            n.type = p->external ? NodeType::externproto_instance : NodeType::proto_instance;
        } else {
            n.type = standard_node_type(n.type_name);
            if (n.type == NodeType::unknown && warned_types_.insert(n.type_name).second)
                warn(t.line, {"unknown node type '", n.type_name, "' skipped (no PROTO declares it)"});
        }
        return n;
    }

    [[noreturn]] MBX_VRML_COLD void fail_after_type(const AstNode& n) const {
        fail(peek().line, {"expected '{' after node type '", n.type_name, "', found ", peek()});
    }

    void parse_body(AstNode& n, size_t depth) {
        for (;;) {
            const Token& t = peek();
            if (t.kind == Tok::rbrace) {
                lex_.advance();
                if (n.fields.size() > few_fields) drop_overridden_fields(n);
                return;
            }
            if (t.kind != Tok::identifier) fail_in_body(n, t);
            if (t.text == "PROTO") {
                parse_proto(depth + 1);
            } else if (t.text == "EXTERNPROTO") {
                parse_externproto(depth + 1);
            } else if (t.text == "ROUTE") {
                parse_route();
            } else if (t.text == "eventIn" || t.text == "eventOut" || t.text == "field" || t.text == "exposedField") {
                // Script nodes declare their own fields; their values carry
                // no geometry, so they are parsed and dropped.
                InterfaceField decl;
                parse_declaration(decl, depth, true);
            } else {
                Field& f = start_field(n, t);
                lex_.advance();
                f.value = parse_value(depth);
            }
        }
    }

    [[noreturn]] MBX_VRML_COLD void fail_in_body(const AstNode& n, const Token& t) const {
        if (t.kind == Tok::eof)
            fail(t.line, {"unexpected end of file inside '", n.type_name, "' node opened at line ", n.line});
        fail(t.line, {"expected a field name or '}' in '", n.type_name, "' node, found ", t});
    }

    // A node with at most this many fields is checked for repeats as each
    // field comes; larger ones (hostile, or huge PROTO instances) once at
    // the end, by hashing.
    static constexpr size_t few_fields = 16;

    // Keeps the last of repeated fields, as the earlier ones are overridden.
    MBX_VRML_COLD static void drop_overridden_fields(AstNode& n) {
        std::unordered_map<std::string_view, size_t> last;
        for (size_t i = 0; i < n.fields.size(); ++i) last[n.fields[i].name] = i;
        if (last.size() == n.fields.size()) return;
        std::vector<char> keep(n.fields.size());
        for (size_t i = 0; i < n.fields.size(); ++i) keep[i] = last[n.fields[i].name] == i;
        std::vector<Field> kept;
        kept.reserve(last.size());
        for (size_t i = 0; i < n.fields.size(); ++i)
            if (keep[i]) kept.push_back(std::move(n.fields[i]));
        n.fields = std::move(kept);
    }

    // The slot for field token `t` of `n`; a repeated field overrides the earlier one.
    MBX_VRML_COLD Field& start_field(AstNode& n, const Token& t) {
        reject_non_finite_word(t);
        if (is_keyword(t.text)) fail(t.line, {"expected a field name, found keyword ", Piece::quoted(t.text)});
        std::string name(t.text);
        const bool known = n.proto ? n.proto->find(name) >= 0
                                   : n.type == NodeType::externproto_instance || is_known_field(n.type, name);
        if (!known && warned_fields_.insert(n.type_name + "." + name).second) {
            if (n.proto)
                warn(t.line, {"PROTO '", n.type_name, "' has no field '", name, "'; ignored"});
            else
                warn(t.line, {n.type_name, " has no field '", name, "'; ignored"});
        }
        if (n.fields.size() <= few_fields)
            for (Field& old : n.fields)
                if (old.name == name) {
                    old = Field();
                    old.name = std::move(name);
                    old.line = t.line;
                    return old;
                }
        Field& f = n.fields.emplace_back();
        f.name = std::move(name);
        f.line = t.line;
        return f;
    }

    // A field value, generically: "[ ... ]", a run of numbers, a string,
    // TRUE/FALSE, NULL, a node, or "IS name" inside a PROTO body.
    Value parse_value(size_t depth) {
        Value v;
        const Token& t = peek();
        v.line = t.line;
        if (t.kind == Tok::identifier && t.text != "TRUE" && t.text != "FALSE" && t.text != "IS") {
            reject_non_finite_word(t);
            v.kind = Value::Kind::nodes;
            v.nodes.push_back(parse_node_statement(depth + 1, true));
        } else if (t.kind == Tok::lbracket) {
            parse_list(v, depth);
        } else {
            parse_scalar(v);
        }
        return v;
    }

    // Values that hold no nodes: a run of numbers, a string, a boolean, IS.
    MBX_VRML_COLD void parse_scalar(Value& v) {
        const Token& t = peek();
        switch (t.kind) {
            case Tok::number:
                v.kind = Value::Kind::numbers;
                parse_numbers(v);
                reject_non_finite_word(peek());
                return;
            case Tok::string:
                v.kind = Value::Kind::strings;
                count_value(t.line);
                v.strings.push_back(lex_.take_string());
                return;
            case Tok::identifier:
                if (t.text == "IS") {
                    lex_.advance();
                    v.kind = Value::Kind::is;
                    v.is_name = expect_identifier("an interface field name after IS");
                    const ProtoDecl* p = scopes_.back().body_of;
                    if (!p) fail(v.line, {"IS outside a PROTO body"});
                    if (p->find(v.is_name) < 0)
                        fail(v.line, {"IS refers to '", v.is_name, "', which PROTO '", p->name, "' does not declare"});
                    return;
                }
                v.kind = Value::Kind::bools;
                v.bools.push_back(t.text == "TRUE");
                count_value(t.line);
                lex_.advance();
                return;
            default: fail_found("a field value", t);
        }
    }

    void parse_numbers(Value& v) {
        int last_line = -1;
        while (peek().kind == Tok::number) {
            const Token& t = peek();
            if (t.line != last_line) {
                v.number_lines.emplace_back(static_cast<uint32_t>(v.numbers.size()), t.line);
                last_line = t.line;
            }
            count_value(t.line);
            v.numbers.push_back(t.number);
            lex_.advance();
        }
    }

    void parse_list(Value& v, size_t depth) {
        const int open_line = peek().line;
        lex_.advance();
        for (;;) {
            const Token& t = peek();
            if (t.kind == Tok::rbracket) {
                lex_.advance();
                return;
            }
            if (t.kind == Tok::identifier && t.text != "TRUE" && t.text != "FALSE" && t.text != "ROUTE") {
                reject_non_finite_word(t);
                set_kind(v, Value::Kind::nodes, t, open_line);
                v.nodes.push_back(parse_node_statement(depth + 1, true));
            } else {
                parse_list_scalar(v, open_line);
            }
        }
    }

    MBX_VRML_COLD void parse_list_scalar(Value& v, int open_line) {
        const Token& t = peek();
        switch (t.kind) {
            case Tok::eof: fail(t.line, {"unexpected end of file inside '[' opened at line ", open_line});
            case Tok::number:
                set_kind(v, Value::Kind::numbers, t, open_line);
                parse_numbers(v);
                return;
            case Tok::string:
                set_kind(v, Value::Kind::strings, t, open_line);
                count_value(t.line);
                v.strings.push_back(lex_.take_string());
                return;
            case Tok::identifier:
                if (t.text == "ROUTE") return parse_route();
                set_kind(v, Value::Kind::bools, t, open_line);
                count_value(t.line);
                v.bools.push_back(t.text == "TRUE");
                lex_.advance();
                return;
            default: fail(t.line, {"unexpected ", t, " in list opened at line ", open_line});
        }
    }

    void set_kind(Value& v, Value::Kind k, const Token& t, int open_line) const {
        if (v.kind == Value::Kind::none) v.kind = k;
        if (v.kind != k)
            fail(t.line,
                 {"list mixes ", kind_name(v.kind), " and ", kind_name(k), " (opened at line ", open_line, ")"});
    }

    // ---- declarations ----

    // "eventIn|eventOut|field|exposedField type name [value]" of a PROTO
    // interface or a Script node; `in_node` allows "IS name" instead of a value.
    // "field SFString name": the kind, type and name of an interface entry.
    MBX_VRML_COLD void parse_declaration_head(InterfaceField& d) {
        const Token& t = peek();
        d.line = t.line;
        if (t.kind != Tok::identifier) fail_found("eventIn, eventOut, field or exposedField", t);
        if (t.text == "eventIn")
            d.kind = InterfaceField::Kind::event_in;
        else if (t.text == "eventOut")
            d.kind = InterfaceField::Kind::event_out;
        else if (t.text == "field")
            d.kind = InterfaceField::Kind::field;
        else if (t.text == "exposedField")
            d.kind = InterfaceField::Kind::exposed_field;
        else
            fail_found("eventIn, eventOut, field or exposedField", t);
        lex_.advance();
        d.type = expect_identifier("a field type");
        d.name = expect_identifier("a field name");
    }

    MBX_VRML_COLD void parse_declaration(InterfaceField& d, size_t depth, bool in_node) {
        parse_declaration_head(d);
        const bool has_value = d.kind == InterfaceField::Kind::field || d.kind == InterfaceField::Kind::exposed_field;
        if (in_node && peek_word("IS")) {
            d.default_value = parse_value(depth);
        } else if (has_value) {
            d.default_value = parse_value(depth);
            if (d.default_value.kind == Value::Kind::is)
                fail(d.line, {"interface field '", d.name, "' cannot take its default from IS"});
        }
    }

    static void index_interface(ProtoDecl& p) {
        if (p.interface.size() <= few_fields) return;
        for (size_t i = 0; i < p.interface.size(); ++i)
            p.index.emplace(p.interface[i].name, static_cast<int>(i));  // the first of repeated names wins
    }

    MBX_VRML_COLD void parse_proto(size_t depth) {
        const int line = peek().line;
        lex_.advance();
        check_nesting(depth, line);
        ProtoDecl& p = out_.protos.emplace_back();
        p.line = line;
        p.name = expect_identifier("a PROTO name");
        if (is_keyword(p.name)) fail(line, {"PROTO name cannot be keyword ", Piece::quoted(p.name)});
        expect(Tok::lbracket, "'[' after the PROTO name");
        while (peek().kind != Tok::rbracket) {
            if (peek().kind == Tok::eof)
                fail(peek().line,
                     {"unexpected end of file in the interface of PROTO '", p.name, "' (line ", line, ")"});
            parse_declaration(p.interface.emplace_back(), depth + 1, false);
        }
        lex_.advance();
        index_interface(p);
        expect(Tok::lbrace, "'{' to open the PROTO body");
        // Declared before its body is read: an instance inside the body then
        // finds it still `defining` and is reported as recursion.
        p.defining = true;
        scopes_.back().protos[p.name] = &p;
        scopes_.emplace_back();
        scopes_.back().body_of = &p;
        while (peek().kind != Tok::rbrace) {
            if (peek().kind == Tok::eof)
                fail(peek().line, {"unexpected end of file inside the body of PROTO '", p.name, "' (line ", line, ")"});
            parse_statement(&p.body, depth + 1);
        }
        lex_.advance();
        scopes_.pop_back();
        p.defining = false;
    }

    MBX_VRML_COLD void parse_externproto(size_t depth) {
        const int line = peek().line;
        lex_.advance();
        ProtoDecl& p = out_.protos.emplace_back();
        p.line = line;
        p.external = true;
        p.name = expect_identifier("an EXTERNPROTO name");
        expect(Tok::lbracket, "'[' after the EXTERNPROTO name");
        while (peek().kind != Tok::rbracket) {
            const Token& t = peek();
            if (t.kind == Tok::eof)
                fail(t.line,
                     {"unexpected end of file in the interface of EXTERNPROTO '", p.name, "' (line ", line, ")"});
            parse_declaration_head(p.interface.emplace_back());
        }
        lex_.advance();
        index_interface(p);
        const Value urls = parse_value(depth);
        if (urls.kind != Value::Kind::strings && urls.kind != Value::Kind::none)
            fail(urls.line, {"EXTERNPROTO '", p.name, "' needs a URL string or list of strings"});
        scopes_.back().protos[p.name] = &p;
        warn(line, {"EXTERNPROTO '", p.name, "' is not loaded: its instances are read as empty groups"});
    }

    MBX_VRML_COLD void parse_route() {
        lex_.advance();
        auto part = [&](const char* what) {
            if (peek().kind != Tok::identifier) fail_found(what, peek());
            lex_.advance();
        };
        auto period = [&]() {
            if (peek().kind != Tok::period) fail_found("'.' in ROUTE", peek());
            lex_.advance();
        };
        part("a node name after ROUTE");
        period();
        part("an event name in ROUTE");
        if (!peek_word("TO")) fail(peek().line, {"malformed ROUTE: expected TO, found ", peek()});
        lex_.advance();
        part("a node name after TO");
        period();
        part("an event name in ROUTE");
    }

    Lexer lex_;
    ParsedFile& out_;
    const VrmlLimits& limits_;
    ReadBudget& budget_;
    const StackGuard& stack_;
    std::vector<Scope> scopes_;
    std::set<std::string> warned_types_;
    std::set<std::string> warned_fields_;
};

}  // namespace

std::unique_ptr<ParsedFile> parse_vrml(std::string_view text, const std::string& path, const VrmlLimits& limits,
                                       ReadBudget& budget, const StackGuard& stack) {
    auto file = std::make_unique<ParsedFile>();
    file->path = path;
    check_header(text, path, file->warnings);
    Parser parser(text, *file, limits, budget, stack);
    parser.parse_file();
    return file;
}

}  // namespace mbx_files::vrml
