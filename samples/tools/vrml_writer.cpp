#include "vrml_writer.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace mbx_samples {
namespace {

using File = std::unique_ptr<FILE, int (*)(FILE*)>;

File open_file(const std::string& path) {
    File f(std::fopen(path.c_str(), "wb"), &std::fclose);
    if (!f) throw std::runtime_error("cannot write " + path);
    std::setvbuf(f.get(), nullptr, _IOFBF, 1 << 20);
    return f;
}

void finish(File& f, const std::string& path) {
    if (std::ferror(f.get()) || std::fclose(f.release()) != 0) throw std::runtime_error("cannot write " + path);
}

double clean(double v) { return std::abs(v) < 1e-12 ? 0.0 : v; }

void indent(FILE* f, int level) {
    for (int i = 0; i < level; ++i) std::fputs("  ", f);
}

void write_shape(FILE* f, int level, const VrmlShape& s, double scale) {
    indent(f, level);
    std::fprintf(f, "DEF %s Shape {\n", vrml_identifier(s.name).c_str());
    indent(f, level + 1);
    std::fprintf(f, "appearance Appearance { material Material { diffuseColor %.3g %.3g %.3g } }\n", s.color.x(),
                 s.color.y(), s.color.z());
    indent(f, level + 1);
    std::fputs("geometry IndexedFaceSet {\n", f);
    indent(f, level + 2);
    std::fputs("solid TRUE\n", f);
    indent(f, level + 2);
    std::fputs("coord Coordinate {\n", f);
    indent(f, level + 3);
    std::fputs("point [\n", f);
    for (size_t i = 0; i < s.solid.vertices.size(); ++i) {
        const Eigen::Vector3d v = s.solid.vertices[i] / scale;
        indent(f, level + 4);
        std::fprintf(f, "%.9g %.9g %.9g%s\n", clean(v.x()), clean(v.y()), clean(v.z()),
                     i + 1 < s.solid.vertices.size() ? "," : "");
    }
    indent(f, level + 3);
    std::fputs("]\n", f);
    indent(f, level + 2);
    std::fputs("}\n", f);
    indent(f, level + 2);
    std::fputs("coordIndex [\n", f);
    for (size_t i = 0; i < s.solid.triangles.size(); ++i) {
        const auto& t = s.solid.triangles[i];
        indent(f, level + 3);
        std::fprintf(f, "%u, %u, %u, -1%s\n", t[0], t[1], t[2], i + 1 < s.solid.triangles.size() ? "," : "");
    }
    indent(f, level + 2);
    std::fputs("]\n", f);
    indent(f, level + 1);
    std::fputs("}\n", f);
    indent(f, level);
    std::fputs("}\n", f);
}

void write_placement(FILE* f, int level, const VrmlPlacement& p, double scale) {
    const Eigen::Vector3d t = p.pose.translation() / scale;
    const Eigen::AngleAxisd r(p.pose.linear());
    const bool turned = std::abs(r.angle()) > 1e-15;
    const Eigen::Vector3d axis = turned ? Eigen::Vector3d(r.axis()) : Eigen::Vector3d::UnitZ();
    indent(f, level);
    std::fprintf(f, "DEF %s Transform {\n", vrml_identifier(p.name).c_str());
    indent(f, level + 1);
    std::fprintf(f, "translation %.10g %.10g %.10g\n", clean(t.x()), clean(t.y()), clean(t.z()));
    indent(f, level + 1);
    std::fprintf(f, "rotation %.12g %.12g %.12g %.12g\n", clean(axis.x()), clean(axis.y()), clean(axis.z()),
                 turned ? r.angle() : 0.0);
    indent(f, level + 1);
    std::fputs("children [\n", f);
    indent(f, level + 2);
    std::fprintf(f, "Model_Info { name \"%s\" type \"%s\" }\n", p.name.c_str(), p.type.c_str());
    if (!p.url.empty()) {
        indent(f, level + 2);
        std::fprintf(f, "Inline { url \"%s\" }\n", p.url.c_str());
    }
    for (const VrmlShape& s : p.shapes) write_shape(f, level + 2, s, scale);
    for (const VrmlPlacement& c : p.children) write_placement(f, level + 2, c, scale);
    indent(f, level + 1);
    std::fputs("]\n", f);
    indent(f, level);
    std::fputs("}\n", f);
}

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

}  // namespace

std::string vrml_identifier(const std::string& name) {
    std::string id;
    for (char c : name) {
        const unsigned char u = static_cast<unsigned char>(c);
        // VRML97 identifiers exclude controls, space and " # ' + , - . [ \ ] { }.
        const bool bad = u <= 0x20 || u == 0x7f || c == '"' || c == '#' || c == '\'' || c == '+' || c == ',' ||
                         c == '-' || c == '.' || c == '[' || c == '\\' || c == ']' || c == '{' || c == '}';
        id += bad ? '_' : c;
    }
    if (id.empty() || (id[0] >= '0' && id[0] <= '9')) id = "_" + id;
    return id;
}

void write_vrml(const std::string& directory, const VrmlAssembly& a) {
    const double scale = a.unit_in_model;
    for (const VrmlGeometryFile& g : a.geometry) {
        const std::string path = directory + "/" + g.file_name;
        File f = open_file(path);
        std::fprintf(f.get(), "#VRML V2.0 utf8\n\n# Geometry of part %s in its part frame (CS1).\n\n", g.part_name.c_str());
        for (const VrmlShape& s : g.shapes) write_shape(f.get(), 0, s, scale);
        finish(f, path);
    }
    const std::string path = directory + "/" + a.file_name;
    File f = open_file(path);
    FILE* out = f.get();
    std::fputs("#VRML V2.0 utf8\n\n", out);
    std::fprintf(out, "WorldInfo {\n  title %s\n  info [", quoted(a.title).c_str());
    for (size_t i = 0; i < a.info.size(); ++i) std::fprintf(out, "%s\n    %s", i ? "," : "", quoted(a.info[i]).c_str());
    std::fputs(a.info.empty() ? "]\n}\n\n" : "\n  ]\n}\n\n", out);
    // CAD exporters carry part names in a PROTO of their own; its body is an
    // empty Group so viewers ignore it.
    std::fputs("PROTO Model_Info [\n  field SFString name \"\"\n  field SFString type \"\"\n] {\n  Group { }\n}\n\n", out);
    for (const VrmlPlacement& p : a.placements) write_placement(out, 0, p, scale);
    finish(f, path);
}

}  // namespace mbx_samples
