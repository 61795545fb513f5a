#include "msl_checker.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <deque>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace msl {

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : s) {
        if (c == sep) {
            out.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

std::string trim(const std::string& s) {
    size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
    return s.substr(a, b - a);
}

// ---------------------------------------------------------------------------
// Tokens
// ---------------------------------------------------------------------------
struct Token {
    enum Kind { Ident, Number, String, Punct, End } kind = End;
    std::string text;  // identifier, number, unescaped string or punctuation
    size_t begin = 0, end = 0;
};

bool ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

std::vector<Token> tokenize(const std::string& s, std::vector<std::string>& errors) {
    std::vector<Token> out;
    size_t i = 0;
    while (i < s.size()) {
        const char c = s[i];
        if (std::isspace(static_cast<unsigned char>(c))) {
            ++i;
        } else if (s.compare(i, 2, "//") == 0) {
            while (i < s.size() && s[i] != '\n') ++i;
        } else if (s.compare(i, 2, "/*") == 0) {
            const size_t e = s.find("*/", i + 2);
            if (e == std::string::npos) {
                errors.push_back("unterminated block comment");
                break;
            }
            i = e + 2;
        } else if (ident_start(c)) {
            Token t{Token::Ident, {}, i, i};
            while (i < s.size() && ident_char(s[i])) ++i;
            t.text = s.substr(t.begin, i - t.begin);
            t.end = i;
            out.push_back(t);
        } else if (std::isdigit(static_cast<unsigned char>(c))) {
            Token t{Token::Number, {}, i, i};
            while (i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '.')) ++i;
            if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
                ++i;
                if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
                while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
            }
            t.text = s.substr(t.begin, i - t.begin);
            t.end = i;
            out.push_back(t);
        } else if (c == '"') {
            Token t{Token::String, {}, i, i};
            ++i;
            bool closed = false;
            while (i < s.size()) {
                const char d = s[i++];
                if (d == '"') {
                    closed = true;
                    break;
                }
                if (d == '\\' && i < s.size()) {
                    const char e = s[i++];
                    switch (e) {
                    case 'n': t.text += '\n'; break;
                    case 'r': t.text += '\r'; break;
                    case 't': t.text += '\t'; break;
                    case '"': case '\\': case '\'': case '?': t.text += e; break;
                    default: errors.push_back(std::string("unknown escape \\") + e + " in a string");
                    }
                    continue;
                }
                if (d == '\n') errors.push_back("raw newline inside a string");
                t.text += d;
            }
            if (!closed) errors.push_back("unterminated string");
            t.end = i;
            out.push_back(t);
        } else if (std::string("(){}[],;=.-+*/:<>").find(c) != std::string::npos) {
            out.push_back({Token::Punct, std::string(1, c), i, i + 1});
            ++i;
        } else {
            errors.push_back(std::string("unexpected character '") + c + "'");
            ++i;
        }
    }
    out.push_back({Token::End, {}, s.size(), s.size()});
    return out;
}

class Parser {
public:
    Parser(const std::string& src, Model& model) : src_(src), model_(model) {
        tokens_ = tokenize(src, model.errors);
    }

    void parse() {
        if (is_ident("within")) {
            next();
            model_.within = dotted();
            expect(";");
        }
        if (!is_ident("model")) return fail("expected 'model'");
        next();
        model_.name = ident();
        if (peek().kind == Token::String) model_.description = next().text;
        bool equations = false;
        while (peek().kind != Token::End) {
            if (is_ident("end")) {
                next();
                const std::string name = ident();
                if (name != model_.name) fail("'end " + name + "' does not close model " + model_.name);
                expect(";");
                if (peek().kind != Token::End) fail("text after the end of the model");
                return;
            }
            if (is_ident("equation")) {
                next();
                equations = true;
                continue;
            }
            if (is_ident("annotation")) {
                next();
                model_.annotation = parenthesised();
                expect(";");
                continue;
            }
            if (!equations && is_ident("extends")) {
                next();
                model_.extends.push_back(dotted());
                if (is_punct("(")) parenthesised();
                expect(";");
                continue;
            }
            if (equations) equation();
            else declaration();
            if (!model_.errors.empty() && model_.errors.size() > 20) return;
        }
        fail("missing 'end " + model_.name + ";'");
    }

private:
    const Token& peek() const { return tokens_[pos_]; }
    const Token& next() { return tokens_[pos_ < tokens_.size() - 1 ? pos_++ : pos_]; }
    bool is_ident(const char* w) const { return peek().kind == Token::Ident && peek().text == w; }
    bool is_punct(const char* p) const { return peek().kind == Token::Punct && peek().text == p; }
    void fail(const std::string& what) {
        model_.errors.push_back(what + " at offset " + std::to_string(peek().begin));
        // Resynchronise at the next ';' so one mistake gives one message.
        while (peek().kind != Token::End && !is_punct(";")) next();
        if (is_punct(";")) next();
    }
    void expect(const char* p) {
        if (is_punct(p)) next();
        else fail(std::string("expected '") + p + "'");
    }
    std::string ident() {
        if (peek().kind != Token::Ident) {
            fail("expected an identifier");
            return {};
        }
        return next().text;
    }
    std::string dotted() {
        std::string s = ident();
        while (is_punct(".")) {
            next();
            s += "." + ident();
        }
        return s;
    }
    // Text inside a balanced "( ... )"; the parentheses are consumed.
    std::string parenthesised() {
        if (!is_punct("(")) {
            fail("expected '('");
            return {};
        }
        const size_t open = next().end;
        int depth = 1;
        while (peek().kind != Token::End) {
            if (is_punct("(")) ++depth;
            if (is_punct(")") && --depth == 0) {
                const std::string inside = src_.substr(open, peek().begin - open);
                next();
                return trim(inside);
            }
            next();
        }
        fail("unbalanced '('");
        return {};
    }
    // Source text of an expression up to a ',' or ')' at depth 0.
    std::string expression() {
        const size_t start = peek().begin;
        size_t end = start;
        int depth = 0;
        while (peek().kind != Token::End) {
            if (depth == 0 && (is_punct(",") || is_punct(")") || is_punct(";"))) break;
            if (is_punct("(") || is_punct("{")) ++depth;
            if (is_punct(")") || is_punct("}")) --depth;
            end = next().end;
        }
        if (end == start) fail("empty expression");
        return trim(src_.substr(start, end - start));
    }
    void declaration() {
        Component c;
        if (is_ident("inner")) {
            next();
            c.inner = true;
        }
        c.class_name = dotted();
        c.name = ident();
        if (is_punct("(")) {
            next();
            while (!is_punct(")") && peek().kind != Token::End) {
                while (is_ident("each") || is_ident("final")) next();
                Modifier m;
                m.name = ident();
                if (is_punct("(")) m.nested = parenthesised();
                if (is_punct("=")) {
                    next();
                    m.value = expression();
                }
                if (m.value.empty() && m.nested.empty()) fail("modifier '" + m.name + "' without a value");
                c.modifiers.push_back(m);
                if (is_punct(",")) next();
                else if (!is_punct(")")) return fail("expected ',' or ')' in the modifiers of " + c.name);
            }
            expect(")");
        }
        if (peek().kind == Token::String) c.description = next().text;
        expect(";");
        model_.components.push_back(std::move(c));
    }
    void equation() {
        if (!is_ident("connect")) return fail("only connect equations are expected");
        next();
        expect("(");
        const std::string a = dotted();
        expect(",");
        const std::string b = dotted();
        expect(")");
        expect(";");
        model_.connects.emplace_back(a, b);
    }

    const std::string& src_;
    Model& model_;
    std::vector<Token> tokens_;
    size_t pos_ = 0;
};

// ---------------------------------------------------------------------------
// Connectors: the index lists element names but not their types, so the few
// MSL connectors this exporter uses are typed here; the kind of a connector
// class (what it carries) then comes from the index itself.
// ---------------------------------------------------------------------------
const std::string kMB = "Modelica.Mechanics.MultiBody.";
const std::string kFrameA = kMB + "Interfaces.Frame_a";
const std::string kFrameB = kMB + "Interfaces.Frame_b";
const std::string kRotA = "Modelica.Mechanics.Rotational.Interfaces.Flange_a";
const std::string kRotB = "Modelica.Mechanics.Rotational.Interfaces.Flange_b";
const std::string kTransA = "Modelica.Mechanics.Translational.Interfaces.Flange_a";
const std::string kTransB = "Modelica.Mechanics.Translational.Interfaces.Flange_b";

const std::map<std::pair<std::string, std::string>, std::string>& connector_table() {
    static const std::map<std::pair<std::string, std::string>, std::string> table = [] {
        std::map<std::pair<std::string, std::string>, std::string> t;
        t[{kMB + "World", "frame_b"}] = kFrameB;
        t[{kMB + "Parts.Body", "frame_a"}] = kFrameA;
        t[{kMB + "Visualizers.FixedShape", "frame_a"}] = kFrameA;
        for (const char* two : {"Parts.FixedTranslation", "Parts.FixedRotation", "Joints.Revolute", "Joints.Prismatic",
                                "Joints.Spherical", "Joints.RevolutePlanarLoopConstraint"}) {
            t[{kMB + two, "frame_a"}] = kFrameA;
            t[{kMB + two, "frame_b"}] = kFrameB;
        }
        t[{kMB + "Joints.Revolute", "axis"}] = kRotA;
        t[{kMB + "Joints.Revolute", "support"}] = kRotB;
        t[{kMB + "Joints.Prismatic", "axis"}] = kTransA;
        t[{kMB + "Joints.Prismatic", "support"}] = kTransB;
        return t;
    }();
    return table;
}

// Conditional connectors exist only when a parameter enables them.
const std::map<std::string, std::string>& conditional_connectors() {
    static const std::map<std::string, std::string> c = {{"axis", "useAxisFlange"}, {"support", "useAxisFlange"}};
    return c;
}

bool is_keyword(const std::string& w) {
    static const std::set<std::string> k = {
        "algorithm", "and",    "annotation", "block",  "break",    "class",    "connect",     "connector", "constant",
        "constrainedby", "der", "discrete", "each",    "else",     "elseif",   "elsewhen",    "encapsulated", "end",
        "enumeration", "equation", "expandable", "extends", "external", "false", "final",   "flow",      "for",
        "function", "if",      "import",     "impure", "in",       "initial",  "inner",       "input",     "loop",
        "model",    "not",     "operator",   "or",     "outer",    "output",   "package",     "parameter", "partial",
        "protected", "public", "pure",       "record", "redeclare", "replaceable", "return",  "stream",    "then",
        "true",     "type",    "when",       "while",  "within"};
    return k.count(w) != 0;
}

bool valid_identifier(const std::string& s) {
    if (s.empty() || !ident_start(s[0])) return false;
    for (char c : s)
        if (!ident_char(c)) return false;
    return !is_keyword(s);
}

}  // namespace

// ---------------------------------------------------------------------------
// Index
// ---------------------------------------------------------------------------
Index::Index(const std::string& tsv_path) {
    std::ifstream in(tsv_path);
    if (!in) throw std::runtime_error("cannot open MSL index " + tsv_path);
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        const std::vector<std::string> f = split(line, '\t');
        if (f.size() < 2) continue;
        ClassInfo info;
        info.kind = f[1];
        if (f.size() > 2 && !f[2].empty()) info.extends = split(f[2], ',');
        if (f.size() > 3 && !f[3].empty()) info.elements = split(f[3], ',');
        classes_[f[0]] = std::move(info);
    }
}

const ClassInfo* Index::find(const std::string& cls) const {
    const auto it = classes_.find(cls);
    return it == classes_.end() ? nullptr : &it->second;
}

std::string Index::resolve(const std::string& context, const std::string& name) const {
    std::string scope = context;
    while (true) {
        const size_t dot = scope.rfind('.');
        scope = dot == std::string::npos ? std::string() : scope.substr(0, dot);
        const std::string candidate = scope.empty() ? name : scope + "." + name;
        if (has(candidate)) return candidate;
        if (scope.empty()) return {};
    }
}

std::set<std::string> Index::elements(const std::string& cls) const {
    std::set<std::string> out;
    std::set<std::string> seen;
    std::vector<std::string> todo{cls};
    while (!todo.empty()) {
        const std::string c = todo.back();
        todo.pop_back();
        if (!seen.insert(c).second) continue;
        const ClassInfo* info = find(c);
        if (!info) continue;
        out.insert(info->elements.begin(), info->elements.end());
        for (const std::string& e : info->extends) {
            const std::string r = resolve(c, e);
            if (!r.empty()) todo.push_back(r);
        }
    }
    return out;
}

// ---------------------------------------------------------------------------
// Model
// ---------------------------------------------------------------------------
const Modifier* Component::modifier(const std::string& n) const {
    for (const Modifier& m : modifiers)
        if (m.name == n) return &m;
    return nullptr;
}

std::string Component::value(const std::string& n) const {
    const Modifier* m = modifier(n);
    return m ? m->value : std::string();
}

const Component* Model::find(const std::string& n) const {
    for (const Component& c : components)
        if (c.name == n) return &c;
    return nullptr;
}

Model parse_model(const std::string& text) {
    Model model;
    Parser(text, model).parse();
    return model;
}

double parse_number(const std::string& text) {
    const std::string t = trim(text);
    double v = std::nan("");
    const char* b = t.data();
    const char* e = t.data() + t.size();
    const auto r = std::from_chars(b, e, v);
    if (r.ec != std::errc() || r.ptr != e) return std::nan("");
    return v;
}

mbx::Vec3 parse_vector(const std::string& text) {
    const std::string t = trim(text);
    mbx::Vec3 v(std::nan(""), std::nan(""), std::nan(""));
    if (t.size() < 2 || t.front() != '{' || t.back() != '}') return v;
    const std::vector<std::string> parts = split(t.substr(1, t.size() - 2), ',');
    if (parts.size() != 3) return v;
    for (int i = 0; i < 3; ++i) v[i] = parse_number(parts[size_t(i)]);
    return v;
}

bool parse_bool(const std::string& text) { return trim(text) == "true"; }

namespace {

// Kind of a connector class: the element names it carries, flattened.
std::string connector_kind(const Index& index, const std::string& cls) {
    std::string kind;
    for (const std::string& e : index.elements(cls)) kind += e + ",";
    return kind;
}

}  // namespace

std::vector<std::string> check_model(const Index& index, const Model& model) {
    std::vector<std::string> errors = model.errors;
    std::map<std::string, const Component*> by_name;
    for (const Component& c : model.components) {
        if (!by_name.emplace(c.name, &c).second) errors.push_back("duplicate component name " + c.name);
        if (!valid_identifier(c.name)) errors.push_back("invalid identifier '" + c.name + "'");
        const ClassInfo* info = index.find(c.class_name);
        if (!info) {
            errors.push_back(c.name + ": class " + c.class_name + " is not in MSL 4.0");
            continue;
        }
        if (info->kind != "model" && info->kind != "connector")
            errors.push_back(c.name + ": class " + c.class_name + " is a " + info->kind);
        const std::set<std::string> elements = index.elements(c.class_name);
        std::set<std::string> given;
        for (const Modifier& m : c.modifiers) {
            if (!given.insert(m.name).second) errors.push_back(c.name + ": modifier " + m.name + " given twice");
            if (!elements.count(m.name))
                errors.push_back(c.name + ": " + c.class_name + " declares no element " + m.name);
            // Enumeration literals and class references must exist too.
            if (m.value.rfind("Modelica.", 0) == 0) {
                const std::string v = m.value;
                const std::string enclosing = v.substr(0, v.rfind('.'));
                if (!index.has(v) && !index.has(enclosing))
                    errors.push_back(c.name + ": " + m.name + " refers to unknown " + v);
            }
        }
    }

    std::map<std::string, int> uses;
    const auto endpoint_kind = [&](const std::string& ref) -> std::string {
        const size_t dot = ref.find('.');
        const std::string comp = ref.substr(0, dot);
        const auto it = by_name.find(comp);
        if (it == by_name.end()) {
            errors.push_back("connect uses undeclared " + comp);
            return {};
        }
        ++uses[comp];
        const Component& c = *it->second;
        const ClassInfo* info = index.find(c.class_name);
        if (!info) return {};
        if (dot == std::string::npos) {
            if (info->kind != "connector") errors.push_back("connect to " + ref + ", which is not a connector");
            return connector_kind(index, c.class_name);
        }
        const std::string element = ref.substr(dot + 1);
        if (element.find('.') != std::string::npos) {
            errors.push_back("connect to a nested element " + ref);
            return {};
        }
        if (!index.elements(c.class_name).count(element)) {
            errors.push_back(ref + ": " + c.class_name + " declares no element " + element);
            return {};
        }
        const auto cond = conditional_connectors().find(element);
        if (cond != conditional_connectors().end() && (!c.modifier(cond->second) || !parse_bool(c.value(cond->second))))
            errors.push_back(ref + " is connected but " + c.name + " does not set " + cond->second + " = true");
        const auto t = connector_table().find({c.class_name, element});
        if (t == connector_table().end()) {
            errors.push_back(ref + ": not a connector the checker knows");
            return {};
        }
        if (!index.has(t->second)) errors.push_back(ref + ": connector class " + t->second + " is not in MSL 4.0");
        return connector_kind(index, t->second);
    };
    std::set<std::string> connected;
    for (const auto& [a, b] : model.connects) {
        const std::string ka = endpoint_kind(a), kb = endpoint_kind(b);
        if (!ka.empty() && !kb.empty() && ka != kb)
            errors.push_back("connect(" + a + ", " + b + ") joins different connector kinds (" + ka + " / " + kb + ")");
        if (a == b) errors.push_back("connect(" + a + ", " + b + ") joins a connector to itself");
        connected.insert(a);
        connected.insert(b);
    }
    for (const Component& c : model.components) {
        if (c.inner) continue;  // world is used through inner/outer by every component
        if (!uses.count(c.name)) errors.push_back(c.name + " is declared but not connected");
        // Joints and fixed frames need both frames connected (MSL asserts cardinality for joints).
        if (connector_table().count({c.class_name, "frame_b"}) && c.class_name != kMB + "World")
            for (const char* f : {".frame_a", ".frame_b"})
                if (!connected.count(c.name + f)) errors.push_back(c.name + f + " is not connected");
    }
    return errors;
}

// ---------------------------------------------------------------------------
// Frame composition
// ---------------------------------------------------------------------------
namespace {

mbx::Mat3 from_nxy(const mbx::Vec3& n_x, const mbx::Vec3& n_y) {
    // MSL Frames.from_nxy: e_x along n_x, e_z normal to n_x and n_y, e_y completing.
    const mbx::Vec3 ex = n_x.normalized();
    const mbx::Vec3 ez = ex.cross(n_y).normalized();
    const mbx::Vec3 ey = ez.cross(ex);
    mbx::Mat3 r;
    r.col(0) = ex;
    r.col(1) = ey;
    r.col(2) = ez;
    return r;
}

mbx::Mat3 cardan_123(const mbx::Vec3& a) {
    return (Eigen::AngleAxisd(a[0], mbx::Vec3::UnitX()) * Eigen::AngleAxisd(a[1], mbx::Vec3::UnitY()) *
            Eigen::AngleAxisd(a[2], mbx::Vec3::UnitZ()))
        .toRotationMatrix();
}

struct Edge {
    std::string to;
    mbx::Pose motion;  // pose of `to` in the frame of the edge's source
};

}  // namespace

FramePoses compose_frames(const Model& model, const JointMotion& joint_motion, double tolerance) {
    FramePoses out;
    std::map<std::string, std::vector<Edge>> graph;
    const auto link = [&](const std::string& a, const std::string& b, const mbx::Pose& a_to_b) {
        graph[a].push_back({b, a_to_b});
        graph[b].push_back({a, a_to_b.inverse()});
    };
    for (const auto& [a, b] : model.connects) link(a, b, mbx::Pose());

    std::vector<std::pair<std::string, mbx::Pose>> seeds;
    for (const Component& c : model.components) {
        const std::string& cls = c.class_name;
        mbx::Pose p;
        if (cls == kMB + "World") {
            seeds.emplace_back(c.name + ".frame_b", mbx::Pose());
            continue;
        }
        if (cls == kMB + "Parts.Body") {
            const Modifier* r0 = c.modifier("r_0");
            if (!r0) continue;
            // A free body: its start pose is where the composition begins.
            const size_t s = r0->nested.find("start");
            const size_t open = r0->nested.find('{', s);
            const size_t close = r0->nested.find('}', open);
            if (s == std::string::npos || open == std::string::npos || close == std::string::npos) {
                out.conflicts.push_back(c.name + ": r_0 without a start vector");
                continue;
            }
            p.position = parse_vector(r0->nested.substr(open, close - open + 1));
            if (c.modifier("angles_start")) p.rotation = cardan_123(parse_vector(c.value("angles_start")));
            seeds.emplace_back(c.name + ".frame_a", p);
            continue;
        }
        if (cls == kMB + "Parts.FixedTranslation") {
            p.position = parse_vector(c.value("r"));
        } else if (cls == kMB + "Parts.FixedRotation") {
            p.position = parse_vector(c.value("r"));
            if (c.value("rotationType") != kMB + "Types.RotationTypes.TwoAxesVectors") {
                out.conflicts.push_back(c.name + ": rotationType the checker does not read");
                continue;
            }
            p.rotation = from_nxy(parse_vector(c.value("n_x")), parse_vector(c.value("n_y")));
        } else if (cls.rfind(kMB + "Joints.", 0) == 0) {
            if (joint_motion && !joint_motion(c, p)) continue;
        } else {
            continue;
        }
        if (!p.position.allFinite() || !p.rotation.allFinite()) {
            out.conflicts.push_back(c.name + ": unreadable pose modifiers");
            continue;
        }
        link(c.name + ".frame_a", c.name + ".frame_b", p);
    }

    std::deque<std::string> queue;
    for (const auto& [frame, pose] : seeds) {
        out.pose[frame] = pose;
        queue.push_back(frame);
    }
    while (!queue.empty()) {
        const std::string u = queue.front();
        queue.pop_front();
        const mbx::Pose pu = out.pose[u];
        for (const Edge& e : graph[u]) {
            const mbx::Pose pv = pu * e.motion;
            const auto it = out.pose.find(e.to);
            if (it == out.pose.end()) {
                out.pose[e.to] = pv;
                queue.push_back(e.to);
                continue;
            }
            const double dp = (it->second.position - pv.position).norm();
            const double dr = (it->second.rotation - pv.rotation).cwiseAbs().maxCoeff();
            if (dp > tolerance || dr > tolerance) {
                std::ostringstream msg;
                msg << e.to << " reached with poses " << dp << " m / " << dr << " apart (from " << u << ")";
                out.conflicts.push_back(msg.str());
            }
        }
    }
    return out;
}

}  // namespace msl
