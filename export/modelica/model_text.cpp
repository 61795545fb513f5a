#include "export/modelica/model_text.h"

#include "export/modelica/modelica_text.h"

namespace mbx {

namespace {

constexpr size_t kOneLineLimit = 110;

// Comments must stay on their line whatever a CAD name holds.
std::string comment_line(const std::string& indent, const std::string& text) {
    std::string line = indent + "// ";
    for (char c : text) line += (c == '\n' || c == '\r') ? ' ' : c;
    return line + "\n";
}

std::string modifier_text(const std::pair<std::string, std::string>& m) {
    return m.second.empty() ? m.first : m.first + " = " + m.second;
}

void write_component(std::string& out, const ModelicaComponent& c) {
    if (!c.comment.empty()) out += comment_line("  ", c.comment);
    std::string head = "  ";
    if (c.inner) head += "inner ";
    head += c.class_name + " " + c.name;
    const std::string tail = c.description.empty() ? ";\n" : " " + modelica_string(c.description) + ";\n";
    if (c.modifiers.empty()) {
        out += head + tail;
        return;
    }
    std::string one_line = head + "(";
    for (size_t i = 0; i < c.modifiers.size(); ++i)
        one_line += (i ? ", " : "") + modifier_text(c.modifiers[i]);
    one_line += ")";
    if (one_line.size() + tail.size() <= kOneLineLimit) {
        out += one_line + tail;
        return;
    }
    out += head + "(\n";
    for (size_t i = 0; i < c.modifiers.size(); ++i) {
        out += "    " + modifier_text(c.modifiers[i]);
        out += i + 1 < c.modifiers.size() ? ",\n" : ")";
    }
    out += tail;
}

}  // namespace

std::string format_model(const ModelicaModel& model) {
    std::string out;
    size_t start = 0;
    while (start < model.header.size()) {
        size_t end = model.header.find('\n', start);
        if (end == std::string::npos) end = model.header.size();
        out += comment_line("", model.header.substr(start, end - start));
        start = end + 1;
    }
    out += "within " + model.within + ";\n";
    out += "model " + model.name;
    if (!model.description.empty()) out += " " + modelica_string(model.description);
    out += "\n";
    for (const ModelicaComponent& c : model.components) write_component(out, c);
    if (!model.connects.empty()) {
        out += "equation\n";
        for (const ModelicaConnect& c : model.connects) {
            if (!c.comment.empty()) out += comment_line("  ", c.comment);
            out += "  connect(" + c.a + ", " + c.b + ");\n";
        }
    }
    if (!model.annotation.empty()) out += "  annotation(" + model.annotation + ");\n";
    out += "end " + model.name + ";\n";
    return out;
}

}  // namespace mbx
