#include "core/mechatronics/object_library.h"

#include <pugixml.hpp>

#include "core/mechatronics/xml_text.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace mbx {

namespace {

// Unit strings in Modelica's syntax ('.' multiplies) that drive parameters
// use; factors to SI.
const std::map<std::string, double>& unit_table() {
    static const std::map<std::string, double> table = {
        {"1", 1},         {"kg", 1},         {"kg.m2", 1},      {"g.cm2", 1e-7},  {"m", 1},
        {"mm", 1e-3},     {"s", 1},          {"ms", 1e-3},      {"V", 1},         {"A", 1},
        {"Ohm", 1},       {"H", 1},          {"mH", 1e-3},      {"rad", 1},       {"deg", M_PI / 180},
        {"rad/s", 1},     {"rpm", 2 * M_PI / 60}, {"N", 1},     {"N.m", 1},       {"mN.m", 1e-3},
        {"N.m/A", 1},     {"V.s/rad", 1},    {"N.m.s/rad", 1},  {"N.s/m", 1},     {"m/rev", 1},
        {"mm/rev", 1e-3}, {"W", 1},          {"%", 0.01},       {"Hz", 1},        {"kg.m2/s", 1}};
    return table;
}

bool is_hex_id(const std::string& id) {
    if (id.size() != 32) return false;
    for (char c : id)
        if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
    return true;
}

std::string upper(std::string s) {
    for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

const char* type_name(ParameterType t) {
    switch (t) {
    case ParameterType::Integer: return "Integer";
    case ParameterType::Boolean: return "Boolean";
    case ParameterType::String: return "String";
    case ParameterType::Real: break;
    }
    return "Real";
}

}  // namespace

std::optional<double> unit_si_factor(const std::string& unit) {
    if (unit.empty()) return 1.0;
    const auto it = unit_table().find(unit);
    if (it == unit_table().end()) return std::nullopt;
    return it->second;
}

const ParameterDecl* LibraryClass::parameter(const std::string& wanted) const {
    for (const ParameterDecl& p : parameters)
        if (p.name == wanted) return &p;
    return nullptr;
}

std::string LibraryError::text() const {
    std::string s = file + ":" + std::to_string(line) + ": ";
    if (!object.empty()) s += object + ": ";
    return s + message;
}

bool ObjectLibrary::load_file(const std::string& path) {
    std::string text, why;
    if (!read_text_file(path, text, &why)) {
        errors_.push_back({path, 0, "", "cannot read the library file: " + why});
        return false;
    }
    std::error_code ec;
    const std::string real = std::filesystem::weakly_canonical(path, ec).string();
    for (const std::string& f : loaded_files_)
        if (f == real) return true;
    loaded_files_.push_back(real);
    load_text(text, path);
    return true;
}

void ObjectLibrary::load_text(const std::string& text, const std::string& file) {
    const XmlLines lines(text);
    auto error = [&](const pugi::xml_node& at, std::string object, std::string message) {
        errors_.push_back({file, lines.line(at), std::move(object), std::move(message)});
    };
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size(), pugi::parse_default);
    if (!parsed) {
        errors_.push_back({file, lines.line_at(parsed.offset), "", std::string("not well-formed XML: ") + parsed.description()});
        return;
    }
    const pugi::xml_node root = doc.child("object_library");
    if (!root) {
        errors_.push_back({file, 1, "", "the root element must be <object_library>"});
        return;
    }
    for (pugi::xml_node folder_node : root.children("object_folder")) {
        const std::string folder_name = folder_node.attribute("name").as_string();
        if (folder_name.empty()) {
            error(folder_node, "", "object_folder has no name");
            continue;
        }
        size_t fi = 0;
        while (fi < folders_.size() && folders_[fi].name != folder_name) ++fi;
        if (fi == folders_.size()) folders_.push_back({folder_name, {}});

        for (pugi::xml_node class_node : folder_node.children("object_class")) {
            LibraryClass cls;
            cls.name = class_node.attribute("name").as_string();
            cls.kind = class_node.attribute("kind").as_string();
            cls.modelica = class_node.attribute("modelica").as_string();
            cls.line = lines.line(class_node);
            if (cls.name.empty()) {
                error(class_node, "", "object_class has no name");
                continue;
            }
            if (!cls.kind.empty() && cls.kind != "dc_motor" && cls.kind != "gearbox" && cls.kind != "ball_screw")
                error(class_node, cls.name, "unknown kind '" + cls.kind + "' (dc_motor, gearbox, ball_screw)");
            const std::string key = folder_name + "\n" + cls.name;
            if (class_index_.count(key)) {
                error(class_node, cls.name, "class declared twice in folder '" + folder_name + "'");
                continue;
            }
            for (pugi::xml_node p : class_node.children("parameter")) {
                ParameterDecl d;
                d.name = p.attribute("name").as_string();
                d.line = lines.line(p);
                const std::string type = p.attribute("type").as_string("Real");
                if (d.name.empty()) {
                    error(p, cls.name, "parameter declaration has no name");
                    continue;
                }
                if (cls.parameter(d.name)) {
                    error(p, cls.name, "parameter '" + d.name + "' declared twice");
                    continue;
                }
                if (type == "Real") d.type = ParameterType::Real;
                else if (type == "Integer") d.type = ParameterType::Integer;
                else if (type == "Boolean") d.type = ParameterType::Boolean;
                else if (type == "String") d.type = ParameterType::String;
                else {
                    error(p, cls.name, "parameter '" + d.name + "' has unknown type '" + type +
                                           "' (Real, Integer, Boolean, String)");
                    continue;
                }
                d.unit = p.attribute("unit").as_string();
                const std::optional<double> factor = unit_si_factor(d.unit);
                if (!factor) {
                    error(p, cls.name, "parameter '" + d.name + "' has unknown unit '" + d.unit + "'");
                    continue;
                }
                if (!d.unit.empty() && (d.type == ParameterType::Boolean || d.type == ParameterType::String)) {
                    error(p, cls.name, "parameter '" + d.name + "' is a " + type + " and cannot have a unit");
                    continue;
                }
                d.si_factor = *factor;
                const std::string editable = p.attribute("editable").as_string("false");
                if (editable != "true" && editable != "false") {
                    error(p, cls.name, "parameter '" + d.name + "': editable must be true or false");
                    continue;
                }
                d.editable = editable == "true";
                d.comment = p.attribute("comment").as_string();
                bool bounds_ok = true;
                for (const char* which : {"lower", "upper"}) {
                    const pugi::xml_attribute a = p.attribute(which);
                    if (!a) continue;
                    double v = 0;
                    if (!parse_xml_number(a.as_string(), v)) {
                        error(p, cls.name, "parameter '" + d.name + "': " + which + " bound '" + a.as_string() +
                                               "' is not a number");
                        bounds_ok = false;
                        continue;
                    }
                    (std::string(which) == "lower" ? d.lower : d.upper) = v;
                }
                if (d.lower && d.upper && *d.lower > *d.upper) {
                    error(p, cls.name, "parameter '" + d.name + "': lower bound above upper bound");
                    bounds_ok = false;
                }
                if (bounds_ok) cls.parameters.push_back(std::move(d));
            }

            for (pugi::xml_node o : class_node.children("object")) {
                LibraryObject obj;
                obj.name = o.attribute("name").as_string();
                obj.id = upper(o.attribute("ID").as_string());
                obj.file = file;
                obj.line = lines.line(o);
                const std::string who = cls.name + "/" + (obj.name.empty() ? "<unnamed>" : obj.name);
                bool good = true;
                if (obj.name.empty()) {
                    error(o, who, "object has no name");
                    good = false;
                }
                if (!is_hex_id(obj.id)) {
                    error(o, who, "ID '" + std::string(o.attribute("ID").as_string()) +
                                      "' is not 32 hexadecimal digits");
                    good = false;
                } else if (const auto it = id_owner_.find(obj.id); it != id_owner_.end()) {
                    error(o, who, "duplicate ID " + obj.id + " (first used at " + it->second + ")");
                    good = false;
                }
                for (pugi::xml_node v : o.children("parameter")) {
                    const std::string name = v.attribute("name").as_string();
                    const ParameterDecl* d = cls.parameter(name);
                    if (!d) {
                        error(v, who, "unknown parameter '" + name + "' (class '" + cls.name + "' declares no such)");
                        good = false;
                        continue;
                    }
                    if (obj.values.count(name)) {
                        error(v, who, "parameter '" + name + "' given twice");
                        good = false;
                        continue;
                    }
                    const pugi::xml_attribute value = v.attribute("value");
                    ParameterValue pv;
                    pv.text = value.as_string();
                    pv.line = lines.line(v);
                    if (!value) {
                        error(v, who, "parameter '" + name + "' has no value");
                        good = false;
                        continue;
                    }
                    bool typed = true;
                    switch (d->type) {
                    case ParameterType::Real: typed = parse_xml_number(pv.text, pv.number); break;
                    case ParameterType::Integer:
                        typed = parse_xml_number(pv.text, pv.number) && pv.number == std::floor(pv.number);
                        break;
                    case ParameterType::Boolean:
                        typed = pv.text == "true" || pv.text == "false";
                        pv.number = pv.text == "true";
                        break;
                    case ParameterType::String: break;
                    }
                    if (!typed) {
                        error(v, who, "parameter '" + name + "' = '" + pv.text + "' is not a valid " +
                                          type_name(d->type));
                        good = false;
                        continue;
                    }
                    const bool numeric = d->type == ParameterType::Real || d->type == ParameterType::Integer;
                    if (numeric && ((d->lower && pv.number < *d->lower) || (d->upper && pv.number > *d->upper))) {
                        auto bound = [](const std::optional<double>& b) {
                            if (!b) return std::string("-");
                            char buf[32];
                            return std::string(buf, std::to_chars(buf, buf + sizeof buf, *b).ptr);
                        };
                        error(v, who, "parameter '" + name + "' = " + pv.text + " " + d->unit + " is outside [" +
                                          bound(d->lower) + ", " + bound(d->upper) + "]");
                        good = false;
                        continue;
                    }
                    obj.values.emplace(name, std::move(pv));
                }
                for (const ParameterDecl& d : cls.parameters)
                    if (!obj.values.count(d.name) &&
                        !(o.find_child_by_attribute("parameter", "name", d.name.c_str()))) {
                        error(o, who, "missing value for parameter '" + d.name + "'");
                        good = false;
                    }
                if (is_hex_id(obj.id) && !id_owner_.count(obj.id))
                    id_owner_.emplace(obj.id, file + ":" + std::to_string(obj.line));
                if (good) cls.objects.push_back(std::move(obj));
            }
            class_index_.emplace(key, std::make_pair(fi, folders_[fi].classes.size()));
            folders_[fi].classes.push_back(std::move(cls));
        }
    }
}

ObjectLibrary::Found ObjectLibrary::find(const std::string& id) const {
    const std::string key = upper(id);
    for (const LibraryFolder& f : folders_)
        for (const LibraryClass& c : f.classes)
            for (const LibraryObject& o : c.objects)
                if (o.id == key) return {&c, &o};
    return {};
}

std::optional<double> ObjectLibrary::value_in_si(const Found& f, const std::string& parameter) const {
    if (!f.cls || !f.object) return std::nullopt;
    const ParameterDecl* d = f.cls->parameter(parameter);
    const auto it = f.object->values.find(parameter);
    if (!d || it == f.object->values.end()) return std::nullopt;
    if (d->type != ParameterType::Real && d->type != ParameterType::Integer) return std::nullopt;
    return it->second.number * d->si_factor;
}

}  // namespace mbx
