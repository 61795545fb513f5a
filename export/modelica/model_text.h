// A Modelica model as declarations and connect equations, formatted one
// statement at a time: short declarations on one line, long ones with one
// modifier per line, so diffs of regenerated files stay readable.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace mbx {

struct ModelicaComponent {
    std::string comment;  // "// ..." line written before it ("" = none)
    bool inner = false;
    std::string class_name;  // fully qualified
    std::string name;
    // name, value text; an empty value writes the name as a whole modification ("v_0(each fixed = true)")
    std::vector<std::pair<std::string, std::string>> modifiers;
    std::string description;  // raw text; quoted and escaped when written
};

struct ModelicaConnect {
    std::string comment;  // "// ..." line written before it ("" = none)
    std::string a, b;
};

struct ModelicaModel {
    std::string header;       // comment lines above `within`, without "//"
    std::string within;       // enclosing package
    std::string name;
    std::string description;  // raw
    std::vector<ModelicaComponent> components;
    std::vector<ModelicaConnect> connects;
    std::string annotation;   // contents of the model's annotation(...), "" = none
};

std::string format_model(const ModelicaModel& model);

}  // namespace mbx
