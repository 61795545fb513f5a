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
        } else if (std::string("(){}[],;=.-+*/:<>^").find(c) != std::string::npos) {
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

bool is_keyword(const std::string& w);

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
        if (!is_ident("model") && !is_ident("block")) return fail("expected 'model' or 'block'");
        model_.kind = next().text;
        model_.name = ident();
        if (peek().kind == Token::String) model_.description = next().text;
        bool equations = false;
        while (peek().kind != Token::End) {
            if (is_ident("algorithm")) {
                next();
                algorithm_section();
                equations = false;
                continue;
            }
            if (!equations && (is_ident("protected") || is_ident("public"))) {
                protected_ = next().text == "protected";
                continue;
            }
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
    // Text inside a balanced "[ ... ]"; the brackets are consumed.
    std::string bracketed() {
        const size_t open = next().end;
        int depth = 1;
        while (peek().kind != Token::End) {
            if (is_punct("[")) ++depth;
            if (is_punct("]") && --depth == 0) {
                const std::string inside = src_.substr(open, peek().begin - open);
                next();
                return trim(inside);
            }
            next();
        }
        fail("unbalanced '['");
        return {};
    }
    // A connector reference: a.b.c, each identifier with optional subscripts ("table.y[1]").
    std::string reference() {
        std::string s = ident();
        while (true) {
            if (is_punct("[")) {
                s += "[" + bracketed() + "]";
            } else if (is_punct(".")) {
                next();
                s += "." + ident();
            } else {
                return s;
            }
        }
    }
    // Statements up to the next section or the end of the class, read as
    // tokens: when/if/for/while that open a statement must close with their
    // own `end`, and every name used is collected.
    void algorithm_section() {
        const size_t start = peek().begin;
        std::vector<std::string> open;
        bool statement_start = true;
        const Token* previous = nullptr;
        while (peek().kind != Token::End) {
            const Token& t = peek();
            if (t.kind == Token::Ident) {
                if (t.text == "end" && open.empty() && pos_ + 2 < tokens_.size() &&
                    tokens_[pos_ + 1].text == model_.name && tokens_[pos_ + 2].text == ";")
                    break;
                if (open.empty() && (t.text == "equation" || t.text == "algorithm" || t.text == "protected" ||
                                     t.text == "public" || t.text == "annotation"))
                    break;
                if (t.text == "end") {
                    next();
                    const std::string what = peek().kind == Token::Ident ? peek().text : std::string();
                    if (open.empty() || open.back() != what)
                        model_.errors.push_back("'end " + what + "' closes nothing open at offset " +
                                                std::to_string(peek().begin));
                    else
                        open.pop_back();
                    next();
                    previous = nullptr;
                    statement_start = false;
                    continue;
                }
                if (statement_start && (t.text == "when" || t.text == "if" || t.text == "for" || t.text == "while"))
                    open.push_back(t.text);
                if (t.text == "for") {
                    next();
                    if (peek().kind == Token::Ident) model_.loop_variables.insert(peek().text);
                    previous = &t;
                    statement_start = false;
                    continue;
                }
                const bool member = previous && previous->kind == Token::Punct && previous->text == ".";
                if (!member && !is_keyword(t.text)) model_.algorithm_names.insert(t.text);
            }
            statement_start = (t.kind == Token::Punct && t.text == ";") ||
                              (t.kind == Token::Ident &&
                               (t.text == "then" || t.text == "else" || t.text == "loop"));
            previous = &t;
            next();
        }
        if (!open.empty()) model_.errors.push_back("'" + open.back() + "' without its 'end " + open.back() + "'");
        model_.algorithm += trim(src_.substr(start, peek().begin - start)) + "\n";
    }
    // Source text of an expression up to a ',' or ')' at depth 0.
    std::string expression() {
        const size_t start = peek().begin;
        size_t end = start;
        int depth = 0;
        const Token* previous = nullptr;
        while (peek().kind != Token::End) {
            if (depth == 0 && (is_punct(",") || is_punct(")") || is_punct(";"))) break;
            // A string right after a complete operand is the description.
            if (depth == 0 && previous && peek().kind == Token::String &&
                (previous->kind != Token::Punct || std::string(")}]").find(previous->text) != std::string::npos))
                break;
            previous = &peek();
            if (is_punct("(") || is_punct("{") || is_punct("[")) ++depth;
            if (is_punct(")") || is_punct("}") || is_punct("]")) --depth;
            end = next().end;
        }
        if (end == start) fail("empty expression");
        return trim(src_.substr(start, end - start));
    }
    void declaration() {
        Component c;
        c.is_protected = protected_;
        static const std::set<std::string> prefixes = {"parameter", "discrete", "constant", "input", "output",
                                                       "final",     "flow",     "stream",   "outer", "replaceable"};
        while (peek().kind == Token::Ident && (prefixes.count(peek().text) || peek().text == "inner")) {
            if (peek().text == "inner") c.inner = true;
            else c.prefixes.push_back(peek().text);
            next();
        }
        c.class_name = dotted();
        c.name = ident();
        if (is_punct("[")) c.dimensions = bracketed();
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
        if (is_punct("=")) {
            next();
            c.binding = expression();
        }
        if (peek().kind == Token::String) c.description = next().text;
        expect(";");
        model_.components.push_back(std::move(c));
    }
    void equation() {
        if (!is_ident("connect")) return fail("only connect equations are expected");
        next();
        expect("(");
        const std::string a = reference();
        expect(",");
        const std::string b = reference();
        expect(")");
        expect(";");
        model_.connects.emplace_back(a, b);
    }

    const std::string& src_;
    Model& model_;
    std::vector<Token> tokens_;
    size_t pos_ = 0;
    bool protected_ = false;
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
const std::string kRealIn = "Modelica.Blocks.Interfaces.RealInput";
const std::string kRealOut = "Modelica.Blocks.Interfaces.RealOutput";
const std::string kPinP = "Modelica.Electrical.Analog.Interfaces.PositivePin";
const std::string kPinN = "Modelica.Electrical.Analog.Interfaces.NegativePin";

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
        // Drive components: keyed by the class that declares the connector
        // (looked up along the component class's extends chain).
        const std::string rot = "Modelica.Mechanics.Rotational.", trans = "Modelica.Mechanics.Translational.";
        const std::string blocks = "Modelica.Blocks.", analog = "Modelica.Electrical.Analog.";
        t[{rot + "Interfaces.PartialTwoFlanges", "flange_a"}] = kRotA;
        t[{rot + "Interfaces.PartialTwoFlanges", "flange_b"}] = kRotB;
        t[{rot + "Interfaces.PartialElementaryTwoFlangesAndSupport2", "flange_a"}] = kRotA;
        t[{rot + "Interfaces.PartialElementaryTwoFlangesAndSupport2", "flange_b"}] = kRotB;
        t[{rot + "Interfaces.PartialCompliant", "flange_a"}] = kRotA;
        t[{rot + "Interfaces.PartialCompliant", "flange_b"}] = kRotB;
        t[{rot + "Interfaces.PartialCompliantWithRelativeStates", "flange_a"}] = kRotA;
        t[{rot + "Interfaces.PartialCompliantWithRelativeStates", "flange_b"}] = kRotB;
        t[{trans + "Interfaces.PartialTwoFlanges", "flange_a"}] = kTransA;
        t[{trans + "Interfaces.PartialTwoFlanges", "flange_b"}] = kTransB;
        t[{rot + "Interfaces.PartialElementaryRotationalToTranslational", "flangeR"}] = kRotA;
        t[{rot + "Interfaces.PartialElementaryRotationalToTranslational", "flangeT"}] = kTransB;
        t[{rot + "Interfaces.PartialAbsoluteSensor", "flange"}] = kRotA;
        t[{trans + "Interfaces.PartialAbsoluteSensor", "flange"}] = kTransA;
        t[{rot + "Sensors.AngleSensor", "phi"}] = kRealOut;
        t[{rot + "Sensors.SpeedSensor", "w"}] = kRealOut;
        t[{trans + "Sensors.PositionSensor", "s"}] = kRealOut;
        t[{trans + "Sensors.SpeedSensor", "v"}] = kRealOut;
        t[{analog + "Interfaces.TwoPin", "p"}] = kPinP;
        t[{analog + "Interfaces.TwoPin", "n"}] = kPinN;
        for (const char* source : {"Sources.SignalVoltage", "Sources.SignalCurrent", "Basic.RotationalEMF"}) {
            t[{analog + source, "p"}] = kPinP;
            t[{analog + source, "n"}] = kPinN;
        }
        t[{analog + "Sources.SignalVoltage", "v"}] = kRealIn;
        t[{analog + "Sources.SignalCurrent", "i"}] = kRealIn;
        t[{analog + "Basic.RotationalEMF", "flange"}] = kRotB;
        // Sources with a support flange (ConstantTorque, ConstantForce, ...).
        t[{rot + "Interfaces.PartialElementaryOneFlangeAndSupport2", "flange"}] = kRotB;
        t[{rot + "Interfaces.PartialElementaryOneFlangeAndSupport2", "support"}] = rot + "Interfaces.Support";
        t[{trans + "Interfaces.PartialElementaryOneFlangeAndSupport2", "flange"}] = kTransB;
        t[{trans + "Interfaces.PartialElementaryOneFlangeAndSupport2", "support"}] = trans + "Interfaces.Support";
        t[{analog + "Basic.Ground", "p"}] = analog + "Interfaces.Pin";
        for (const char* siso : {"Interfaces.SISO", "Math.Gain"}) {
            t[{blocks + siso, "u"}] = kRealIn;
            t[{blocks + siso, "y"}] = kRealOut;
        }
        for (const char* two : {"Interfaces.SI2SO", "Math.Feedback"}) {
            t[{blocks + two, "u1"}] = kRealIn;
            t[{blocks + two, "u2"}] = kRealIn;
            t[{blocks + two, "y"}] = kRealOut;
        }
        for (const char* in : {"u1", "u2", "u3"}) t[{blocks + "Math.Add3", in}] = kRealIn;
        t[{blocks + "Math.Add3", "y"}] = kRealOut;
        t[{blocks + "Interfaces.SO", "y"}] = kRealOut;
        t[{blocks + "Interfaces.MO", "y"}] = kRealOut;  // a vector: connected as y[i]
        return t;
    }();
    return table;
}

// Conditional connectors exist only when a parameter enables them: the
// support of a one-flange element with useSupport (looked up along the
// component class's extends chain), a MultiBody joint's axis and support with
// useAxisFlange.
const std::map<std::string, std::string>& conditional_connectors() {
    static const std::map<std::string, std::string> c = {{"axis", "useAxisFlange"}, {"support", "useAxisFlange"}};
    return c;
}

std::string conditional_parameter(const Index& index, const std::string& cls, const std::string& element) {
    for (const std::string& c : index.lineage(cls))
        if (element == "support" && (c == "Modelica.Mechanics.Rotational.Interfaces.PartialElementaryOneFlangeAndSupport2" ||
                                     c == "Modelica.Mechanics.Translational.Interfaces.PartialElementaryOneFlangeAndSupport2"))
            return "useSupport";
    const auto it = conditional_connectors().find(element);
    return it != conditional_connectors().end() ? it->second : std::string();
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

// Where the index's line parser missed an extends clause or filed a class
// under the wrong package, for the classes the exporter uses (checked against
// the MSL 4.0.0 sources: IdealGear extends PartialElementaryTwoFlangesAndSupport2,
// Constant extends Interfaces.SO, CombiTimeTable is Modelica.Blocks.Sources's).
void patch_index_gaps(std::map<std::string, ClassInfo>& classes) {
    const auto add_extends = [&](const std::string& cls, const std::string& base) {
        const auto it = classes.find(cls);
        if (it == classes.end()) return;
        std::vector<std::string>& e = it->second.extends;
        if (std::find(e.begin(), e.end(), base) == e.end()) e.push_back(base);
    };
    add_extends("Modelica.Mechanics.Rotational.Components.IdealGear",
                "Modelica.Mechanics.Rotational.Interfaces.PartialElementaryTwoFlangesAndSupport2");
    add_extends("Modelica.Blocks.Sources.Constant", "Interfaces.SO");
    // Joint dynamics components (MSL 4.0 sources: each extends these first).
    add_extends("Modelica.Mechanics.Rotational.Components.Damper",
                "Modelica.Mechanics.Rotational.Interfaces.PartialCompliantWithRelativeStates");
    add_extends("Modelica.Mechanics.Rotational.Components.SpringDamper",
                "Modelica.Mechanics.Rotational.Interfaces.PartialCompliantWithRelativeStates");
    add_extends("Modelica.Mechanics.Rotational.Components.BearingFriction",
                "Modelica.Mechanics.Rotational.Interfaces.PartialElementaryTwoFlangesAndSupport2");
    if (!classes.count("Modelica.Blocks.Sources.CombiTimeTable") &&
        classes.count("Modelica.Blocks.Sources.SineVariableFrequencyAndAmplitude.CombiTimeTable")) {
        ClassInfo info;
        info.kind = "block";
        info.extends = {"Modelica.Blocks.Interfaces.MO"};
        info.elements = {"tableOnFile", "table",     "tableName",  "fileName",  "verboseRead", "columns",
                         "smoothness",  "extrapolation", "timeScale", "offset", "startTime",   "shiftTime",
                         "timeEvents",  "verboseExtrapolation", "t_min", "t_max", "t_minScaled", "t_maxScaled"};
        classes["Modelica.Blocks.Sources.CombiTimeTable"] = std::move(info);
    }
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
    patch_index_gaps(classes_);
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

std::vector<std::string> Index::lineage(const std::string& cls) const {
    std::vector<std::string> out;
    std::set<std::string> seen;
    std::deque<std::string> todo{cls};
    while (!todo.empty()) {
        const std::string c = todo.front();
        todo.pop_front();
        if (!seen.insert(c).second) continue;
        out.push_back(c);
        const ClassInfo* info = find(c);
        if (!info) continue;
        for (const std::string& e : info->extends) {
            const std::string r = resolve(c, e);
            if (!r.empty()) todo.push_back(r);
        }
    }
    return out;
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

bool Component::has_prefix(const std::string& p) const {
    return std::find(prefixes.begin(), prefixes.end(), p) != prefixes.end();
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

ClassInfo class_info(const Model& model) {
    ClassInfo info;
    info.kind = model.kind;
    info.extends = model.extends;
    for (const Component& c : model.components) {
        if (c.is_protected) continue;
        info.elements.push_back(c.name);
        info.element_types[c.name] = c.class_name;
    }
    return info;
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

const std::set<std::string>& builtin_types() {
    static const std::set<std::string> t = {"Real", "Integer", "Boolean", "String"};
    return t;
}

// A class that is (or extends) a built-in type: parameters, variables, SI
// types, RealInput/RealOutput. Its modifiers are attributes, not elements.
bool scalar_class(const Index& index, const std::string& cls) {
    if (builtin_types().count(cls)) return true;
    for (const std::string& c : index.lineage(cls)) {
        const ClassInfo* info = index.find(c);
        if (!info) continue;
        if (info->kind == "type") return true;
        for (const std::string& e : info->extends)
            if (builtin_types().count(e)) return true;
    }
    return false;
}

bool is_attribute(const std::string& name) {
    static const std::set<std::string> a = {"start", "fixed", "min",      "max",        "unit",
                                            "displayUnit", "nominal", "quantity", "stateSelect"};
    return a.count(name) != 0;
}

// Kind of a connector class: the element names it carries, flattened; "Real"
// for signal connectors (whose index entries list no elements).
std::string connector_kind(const Index& index, const std::string& cls) {
    if (scalar_class(index, cls)) return "Real";
    std::string kind;
    for (const std::string& e : index.elements(cls)) kind += e + ",";
    return kind;
}

// Signal direction of a connector class: +1 RealOutput, -1 RealInput, 0 other.
int signal_direction(const Index& index, const std::string& cls) {
    for (const std::string& c : index.lineage(cls)) {
        if (c == kRealOut) return 1;
        if (c == kRealIn) return -1;
    }
    return 0;
}

// Class of connector `element` of a component of class `cls`: from a
// generated class's declarations or the table, along the extends chain.
std::string connector_class(const Index& index, const std::string& cls, const std::string& element) {
    for (const std::string& c : index.lineage(cls)) {
        if (const ClassInfo* info = index.find(c)) {
            const auto it = info->element_types.find(element);
            if (it != info->element_types.end()) return it->second;
        }
        const auto t = connector_table().find({c, element});
        if (t != connector_table().end()) return t->second;
    }
    return {};
}

std::string strip_subscripts(const std::string& ref) {
    std::string out;
    int depth = 0;
    for (char c : ref) {
        if (c == '[') ++depth;
        else if (c == ']') --depth;
        else if (depth == 0) out += c;
    }
    return out;
}

// Names an algorithm may use without declaring them.
bool builtin_name(const std::string& n) {
    static const std::set<std::string> b = {
        "time", "sample", "pre",  "edge",  "change", "initial", "terminal", "noEvent", "smooth", "min",
        "max",  "abs",    "sign", "sqrt",  "size",   "integer", "floor",    "ceil",    "mod",    "rem",
        "div",  "delay",  "der",  "reinit", "assert", "fill",   "zeros",    "ones",    "sum",    "Modelica"};
    return b.count(n) != 0;
}

struct Sets {
    std::map<std::string, std::string> parent;
    std::string find(const std::string& x) {
        auto it = parent.find(x);
        if (it == parent.end()) {
            parent[x] = x;
            return x;
        }
        if (it->second == x) return x;
        const std::string root = find(it->second);
        parent[x] = root;
        return root;
    }
    void unite(const std::string& a, const std::string& b) { parent[find(a)] = find(b); }
};

}  // namespace

std::vector<std::string> check_model(const Index& index, const Model& model) {
    std::vector<std::string> errors = model.errors;
    std::map<std::string, const Component*> by_name;
    for (const std::string& e : model.extends)
        if (!index.has(e)) errors.push_back(model.name + " extends unknown class " + e);
    for (const Component& c : model.components) {
        if (!by_name.emplace(c.name, &c).second) errors.push_back("duplicate component name " + c.name);
        if (!valid_identifier(c.name)) errors.push_back("invalid identifier '" + c.name + "'");
        const bool builtin = builtin_types().count(c.class_name) != 0;
        const ClassInfo* info = index.find(c.class_name);
        if (!info && !builtin) {
            errors.push_back(c.name + ": class " + c.class_name + " is not in MSL 4.0");
            continue;
        }
        if (info && info->kind != "model" && info->kind != "block" && info->kind != "connector" && info->kind != "type")
            errors.push_back(c.name + ": class " + c.class_name + " is a " + info->kind);
        const bool scalar = scalar_class(index, c.class_name);
        const std::set<std::string> elements = scalar ? std::set<std::string>() : index.elements(c.class_name);
        std::set<std::string> given;
        for (const Modifier& m : c.modifiers) {
            if (!given.insert(m.name).second) errors.push_back(c.name + ": modifier " + m.name + " given twice");
            if (scalar ? !is_attribute(m.name) : !elements.count(m.name))
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

    // Names used by algorithm sections.
    if (!model.algorithm_names.empty()) {
        std::set<std::string> known;
        for (const Component& c : model.components) known.insert(c.name);
        for (const std::string& e : model.extends)
            for (const std::string& n : index.elements(e)) known.insert(n);
        for (const std::string& n : model.algorithm_names)
            if (!known.count(n) && !model.loop_variables.count(n) && !builtin_name(n))
                errors.push_back(model.name + ": the algorithm uses undeclared " + n);
    }

    std::map<std::string, int> uses;
    // Signal connection sets: which refs drive them (outputs of components,
    // inputs of the model itself) and which they drive.
    Sets sets;
    std::map<std::string, int> direction;  // ref -> +1 source, -1 sink
    const auto endpoint_kind = [&](const std::string& ref_text) -> std::string {
        const std::string ref = strip_subscripts(ref_text);
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
            // Seen from inside, the model's own input drives its connection set.
            const int d = signal_direction(index, c.class_name);
            if (d != 0) direction[ref_text] = -d;
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
        const std::string cond = conditional_parameter(index, c.class_name, element);
        if (!cond.empty() && (!c.modifier(cond) || !parse_bool(c.value(cond))))
            errors.push_back(ref + " is connected but " + c.name + " does not set " + cond + " = true");
        const std::string type = connector_class(index, c.class_name, element);
        if (type.empty()) {
            errors.push_back(ref + ": not a connector the checker knows");
            return {};
        }
        if (!index.has(type)) errors.push_back(ref + ": connector class " + type + " is not in MSL 4.0");
        const int d = signal_direction(index, type);
        if (d != 0) direction[ref_text] = d;
        return connector_kind(index, type);
    };
    std::set<std::string> connected;
    for (const auto& [a, b] : model.connects) {
        const std::string ka = endpoint_kind(a), kb = endpoint_kind(b);
        if (!ka.empty() && !kb.empty() && ka != kb)
            errors.push_back("connect(" + a + ", " + b + ") joins different connector kinds (" + ka + " / " + kb + ")");
        if (a == b) errors.push_back("connect(" + a + ", " + b + ") joins a connector to itself");
        if (ka == "Real" && kb == "Real") sets.unite(a, b);
        connected.insert(a);
        connected.insert(b);
    }
    // Each signal set: exactly one source.
    std::map<std::string, std::vector<std::string>> sources, members;
    for (const auto& [ref, d] : direction) {
        const std::string root = sets.find(ref);
        members[root].push_back(ref);
        if (d > 0) sources[root].push_back(ref);
    }
    for (const auto& [root, refs] : members) {
        const size_t n = sources.count(root) ? sources[root].size() : 0;
        if (n == 1) continue;
        std::string list;
        for (const std::string& r : refs) list += (list.empty() ? "" : ", ") + r;
        errors.push_back("signals {" + list + "} have " + std::to_string(n) + " sources (outputs) instead of one");
    }
    std::set<std::string> connected_plain;
    for (const std::string& r : connected) connected_plain.insert(strip_subscripts(r));
    std::map<std::string, std::vector<std::string>> inputs_of;  // class -> its signal inputs
    for (const Component& c : model.components) {
        if (c.inner) continue;  // world is used through inner/outer by every component
        const bool scalar = scalar_class(index, c.class_name);
        // Parameters, variables and a block's own signal connectors are used
        // by equations or from outside, not through connects.
        if (!scalar && !uses.count(c.name)) errors.push_back(c.name + " is declared but not connected");
        // Joints and fixed frames need both frames connected (MSL asserts cardinality for joints).
        if (connector_table().count({c.class_name, "frame_b"}) && c.class_name != kMB + "World")
            for (const char* f : {".frame_a", ".frame_b"})
                if (!connected.count(c.name + f)) errors.push_back(c.name + f + " is not connected");
        // Every signal input of a component must be driven.
        if (scalar || !index.find(c.class_name) || index.find(c.class_name)->kind == "connector") continue;
        auto inputs = inputs_of.find(c.class_name);
        if (inputs == inputs_of.end()) {
            std::vector<std::string> list;
            for (const std::string& e : index.elements(c.class_name)) {
                const std::string type = connector_class(index, c.class_name, e);
                if (!type.empty() && signal_direction(index, type) < 0) list.push_back(e);
            }
            inputs = inputs_of.emplace(c.class_name, std::move(list)).first;
        }
        for (const std::string& e : inputs->second)
            if (!connected_plain.count(c.name + "." + e)) errors.push_back("input " + c.name + "." + e + " is not connected");
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
