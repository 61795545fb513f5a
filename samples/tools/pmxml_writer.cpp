// Writes PMXML the way SimMechanics Link does: quoted strings, comma lists
// without spaces, column-major orientation, 2-space indentation, blank lines
// between the root's header children, 3-digit exponents ("1.5e-006").
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "pmxml_document.h"

namespace mbx_samples {
namespace {

class XmlOut {
public:
    XmlOut(const std::string& path, int digits) : file_(std::fopen(path.c_str(), "wb"), &std::fclose), digits_(digits) {
        if (!file_) throw std::runtime_error("cannot write " + path);
        std::setvbuf(file_.get(), nullptr, _IOFBF, 1 << 20);
    }
    void finish(const std::string& path) {
        if (std::ferror(file_.get()) || std::fclose(file_.release()) != 0) throw std::runtime_error("cannot write " + path);
    }

    void raw(const char* s) { std::fputs(s, file_.get()); }
    void indent(int level) {
        for (int i = 0; i < level; ++i) raw("  ");
    }
    void open(int level, const char* tag) {
        indent(level);
        std::fprintf(file_.get(), "<%s>\n", tag);
    }
    void close(int level, const char* tag) {
        indent(level);
        std::fprintf(file_.get(), "</%s>\n", tag);
    }
    void empty(int level, const char* tag) {
        indent(level);
        std::fprintf(file_.get(), "<%s></%s>\n", tag, tag);
    }
    // String values carry their quotes inside the element text.
    void text(int level, const char* tag, const std::string& value) {
        indent(level);
        std::fprintf(file_.get(), "<%s>\"%s\"</%s>\n", tag, escaped(value).c_str(), tag);
    }
    void integer(int level, const char* tag, long value) {
        indent(level);
        std::fprintf(file_.get(), "<%s>%ld</%s>\n", tag, value, tag);
    }
    void numbers(int level, const char* tag, const double* v, int n) {
        indent(level);
        std::fprintf(file_.get(), "<%s>", tag);
        for (int i = 0; i < n; ++i) {
            if (i) raw(",");
            number(v[i]);
        }
        std::fprintf(file_.get(), "</%s>\n", tag);
    }

private:
    void number(double v) {
        if (std::abs(v) < 1e-14) v = 0;  // no "-0", no 1e-17 leftovers of cos(90 deg)
        char text[40];
        std::snprintf(text, sizeof text, "%.*g", digits_, v);
        // Windows C runtimes print three exponent digits.
        if (char* e = std::strchr(text, 'e')) {
            const char sign = e[1];
            const char* digits = e + 2;
            if (std::strlen(digits) == 2) {
                char widened[40];
                std::snprintf(widened, sizeof widened, "%.*se%c0%s", int(e - text), text, sign, digits);
                std::memcpy(text, widened, sizeof widened);
            }
        }
        raw(text);
    }
    static std::string escaped(const std::string& s) {
        std::string out;
        for (char c : s) {
            if (c == '&') out += "&amp;";
            else if (c == '<') out += "&lt;";
            else if (c == '>') out += "&gt;";
            else out += c;
        }
        return out;
    }

    std::unique_ptr<FILE, int (*)(FILE*)> file_;
    int digits_;
};

void write_frame(XmlOut& x, int level, const PmxmlFrame& f, const PmxmlUnits& u) {
    x.indent(level);
    if (f.ref > 0) {
        char open[48];
        std::snprintf(open, sizeof open, "<Frame ref=\"%d\">\n", f.ref);
        x.raw(open);
    } else {
        x.raw("<Frame>\n");
    }
    x.text(level + 1, "name", f.name);
    x.text(level + 1, "displayName", f.display_name);
    x.text(level + 1, "nodeID", f.node_id);
    x.numbers(level + 1, "position", f.position.data(), 3);
    x.text(level + 1, "positionOrigin", "WORLD");
    x.text(level + 1, "positionReferenceFrame", "WORLD");
    x.text(level + 1, "positionUnits", u.length);
    // Eigen stores column-major, which is the file's layout.
    x.numbers(level + 1, "orientation", f.rotation.data(), 9);
    x.text(level + 1, "orientationType", "3x3 Transform");
    x.text(level + 1, "orientationUnits", "rad");
    x.text(level + 1, "orientationReferenceFrame", "WORLD");
    x.close(level, "Frame");
}

void write_body(XmlOut& x, int level, const PmxmlBody& b, const PmxmlUnits& u) {
    x.open(level, "Body");
    x.text(level + 1, "name", b.name);
    x.text(level + 1, "nodeID", b.node_id);
    x.text(level + 1, "status", "");
    x.numbers(level + 1, "mass", &b.mass, 1);
    x.text(level + 1, "massUnits", u.mass);
    x.numbers(level + 1, "inertia", b.inertia.data(), 9);
    x.text(level + 1, "inertiaUnits", u.inertia);
    x.numbers(level + 1, "volume", &b.volume, 1);
    x.text(level + 1, "volumeUnits", u.volume);
    x.numbers(level + 1, "surfaceArea", &b.area, 1);
    x.text(level + 1, "surfaceAreaUnits", u.area);
    x.open(level + 1, "frames");
    for (const PmxmlFrame& f : b.frames) write_frame(x, level + 2, f, u);
    x.close(level + 1, "frames");
    // Geometry comes from the VRML through shape matching.
    x.text(level + 1, "geometryFileName", "");
    if (b.has_color) {
        x.open(level + 1, "MaterialProp");
        x.numbers(level + 2, "color", b.color.data(), 3);
        const double ambient = 0.9, diffuse = 0.9, specular = 0.8, shininess = 0.5, transparency = 0, emission = 0.9;
        x.numbers(level + 2, "ambient", &ambient, 1);
        x.numbers(level + 2, "diffuse", &diffuse, 1);
        x.numbers(level + 2, "specular", &specular, 1);
        x.numbers(level + 2, "shininess", &shininess, 1);
        x.numbers(level + 2, "transparency", &transparency, 1);
        x.numbers(level + 2, "emission", &emission, 1);
        x.close(level + 1, "MaterialProp");
    }
    x.close(level, "Body");
}

void write_joint_side(XmlOut& x, int level, const char* tag, int ref) {
    x.open(level, tag);
    x.open(level + 1, "JointSide");
    x.text(level + 2, "name", "");
    x.open(level + 2, "connection");
    x.indent(level + 3);
    char frame[48];
    std::snprintf(frame, sizeof frame, "<Frame ref=\"%d\"></Frame>\n", ref);
    x.raw(frame);
    x.close(level + 2, "connection");
    x.close(level + 1, "JointSide");
    x.close(level, tag);
}

void write_joint(XmlOut& x, int level, const PmxmlJoint& j) {
    x.open(level, "SimpleJoint");
    x.text(level + 1, "name", j.name);
    x.text(level + 1, "nodeID", j.node_id);
    x.text(level + 1, "status", j.status);
    write_joint_side(x, level + 1, "base", j.base_ref);
    write_joint_side(x, level + 1, "follower", j.follower_ref);
    x.open(level + 1, "primitives");
    for (const PmxmlPrimitive& p : j.primitives) {
        x.open(level + 2, "Primitive");
        x.text(level + 3, "name", p.name);
        x.text(level + 3, "nodeID", "");
        x.text(level + 3, "referenceFrame", "WORLD");
        x.numbers(level + 3, "axis", p.axis.data(), 3);
        x.close(level + 2, "Primitive");
    }
    x.close(level + 1, "primitives");
    x.close(level, "SimpleJoint");
}

void write_subsystem(XmlOut& x, int level, const PmxmlDocument& d, int index, const char* tag) {
    const PmxmlSubsystem& s = d.subsystems[size_t(index)];
    const bool top = index == 0;
    x.open(level, tag);
    x.text(level + 1, "name", s.name);
    x.text(level + 1, "nodeID", s.node_id);
    if (!top) x.text(level + 1, "status", "");
    x.open(level + 1, "bodies");
    for (int b : s.bodies) write_body(x, level + 2, d.bodies[size_t(b)], d.units);
    x.close(level + 1, "bodies");
    x.open(level + 1, "joints");
    for (int j : s.joints) write_joint(x, level + 2, d.joints[size_t(j)]);
    x.close(level + 1, "joints");
    if (top) {
        x.open(level + 1, "grounds");
        x.open(level + 2, "Ground");
        x.text(level + 3, "name", "RootGround");
        x.text(level + 3, "nodeID", "RootGround");
        x.text(level + 3, "status", "");
        x.open(level + 3, "frame");
        write_frame(x, level + 4, d.ground_frame, d.units);
        x.close(level + 3, "frame");
        x.close(level + 2, "Ground");
        x.close(level + 1, "grounds");
    } else {
        x.empty(level + 1, "grounds");
    }
    if (s.children.empty()) {
        x.empty(level + 1, "subsystems");
    } else {
        x.open(level + 1, "subsystems");
        for (int c : s.children) write_subsystem(x, level + 2, d, c, "Subsystem");
        x.close(level + 1, "subsystems");
    }
    x.empty(level + 1, "connectionPorts");
    x.integer(level + 1, "id", 0);
    x.close(level, tag);
}

}  // namespace

void write_pmxml(const std::string& path, const PmxmlDocument& d) {
    XmlOut x(path, d.digits);
    x.raw("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\" ?>\n<PhysicalModelingXMLFile>\n\n");
    x.text(1, "formatVersion", "1.0.4");
    x.raw("\n");
    x.integer(1, "internalVersion", 1);
    x.raw("\n");
    x.text(1, "createdUsing", d.created_using);
    x.raw("\n");
    x.text(1, "createdFrom", d.created_from);
    x.raw("\n");
    x.text(1, "createdOn", d.created_on);
    x.raw("\n");
    x.text(1, "createdBy", d.created_by);
    x.raw("\n");
    x.text(1, "name", d.model_name);
    x.raw("\n");
    write_subsystem(x, 1, d, 0, "SimMechanics");
    x.raw("\n</PhysicalModelingXMLFile>\n");
    x.finish(path);
}

}  // namespace mbx_samples
