#include "simscape_document.h"

#include <cstdio>
#include <stdexcept>

#include "whole_file.h"

namespace mbx_samples {
namespace {

std::string escaped(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '&') out += "&amp;";
        else if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '"') out += "&quot;";
        else out += c;
    }
    return out;
}

class Writer {
public:
    explicit Writer(const SimscapeXmlDocument& d) : d_(d) {}

    std::string number(double x) const {
        char buffer[40];
        std::snprintf(buffer, sizeof buffer, "%.*g", d_.digits, x == 0 ? 0.0 : x);
        return buffer;
    }

    std::string run() {
        out_ += "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
        out_ += "<SimscapeMultibodyImportXML xmlns=\"urn:mathworks:SimscapeMultibody:import\" version=\"2.0\">\n";
        out_ += "   <Created by=\"" + escaped(d_.created_by) + "\" from=\"" + escaped(d_.created_from) +
                "\" using=\"mbx sample tools\"/>\n";
        out_ += "   <ModelUnits length=\"" + escaped(d_.length_unit) + "\" mass=\"" + escaped(d_.mass_unit) + "\"/>\n";
        if (d_.write_data_units)
            out_ += "   <DataUnits length=\"" + escaped(d_.length_unit) + "\" mass=\"" + escaped(d_.mass_unit) + "\"/>\n";
        out_ += "   <RootAssembly name=\"" + escaped(d_.root_name) + "\" uid=\"" + escaped(d_.root_uid) + "\">\n";
        out_ += "      <InstanceTree>\n";
        for (const SimscapeXmlInstance& i : d_.instances) instance(i, 3);
        out_ += "      </InstanceTree>\n";
        mates(d_.mates, 2);
        joints(d_.joints, 2);
        out_ += "   </RootAssembly>\n";
        if (!d_.assemblies.empty()) {
            out_ += "   <Assemblies>\n";
            for (const SimscapeXmlAssembly& a : d_.assemblies) {
                out_ += "      <Assembly name=\"" + escaped(a.name) + "\" uid=\"" + escaped(a.uid) + "\">\n";
                out_ += "         <Constraints/>\n";
                joints(a.joints, 3);
                out_ += "      </Assembly>\n";
            }
            out_ += "   </Assemblies>\n";
        }
        out_ += "   <Parts>\n";
        for (const SimscapeXmlPart& p : d_.parts) part(p);
        out_ += "   </Parts>\n";
        out_ += "</SimscapeMultibodyImportXML>\n";
        return std::move(out_);
    }

private:
    static std::string pad(int level) { return std::string(size_t(3 * level), ' '); }

    void transform(const Eigen::Isometry3d& x, int level) {
        out_ += pad(level) + "<Transform>\n" + pad(level + 1) + "<Rotation>";
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) out_ += number(x.linear()(r, c)) + " ";
        out_ += "</Rotation>\n" + pad(level + 1) + "<Translation>";
        for (int k = 0; k < 3; ++k) out_ += number(x.translation()[k] * d_.per_metre) + " ";
        out_ += "</Translation>\n" + pad(level) + "</Transform>\n";
    }

    void instance(const SimscapeXmlInstance& i, int level) {
        out_ += pad(level) + "<Instance entityUid=\"" + escaped(i.entity_uid) + "\"";
        if (i.grounded) out_ += " grounded=\"true\"";
        if (i.rigid) out_ += " rigid=\"true\"";
        if (!i.rigid_group.empty()) out_ += " rigidGroup=\"" + escaped(i.rigid_group) + "\"";
        out_ += " name=\"" + escaped(i.name) + "\" uid=\"" + escaped(i.uid) + "\">\n";
        transform(i.local, level + 1);
        for (const SimscapeXmlInstance& c : i.children) instance(c, level + 1);
        out_ += pad(level) + "</Instance>\n";
    }

    void frame(const char* tag, const SimscapeXmlFrame& f, int level) {
        out_ += pad(level) + "<" + tag + ">\n" + pad(level + 1) + "<InstancePath>\n";
        for (const std::string& uid : f.path) out_ += pad(level + 2) + "<Uid>" + escaped(uid) + "</Uid>\n";
        out_ += pad(level + 1) + "</InstancePath>\n";
        transform(f.transform, level + 1);
        out_ += pad(level) + "</" + tag + ">\n";
    }

    void mates(const std::vector<SimscapeXmlMate>& ms, int level) {
        if (ms.empty()) {
            out_ += pad(level) + "<Constraints/>\n";
            return;
        }
        out_ += pad(level) + "<Constraints>\n";
        for (const SimscapeXmlMate& m : ms) {
            out_ += pad(level + 1) + "<" + m.type + " name=\"" + escaped(m.name) + "\">\n";
            for (const SimscapeXmlMateGeometry* g : {&m.first, &m.second}) {
                out_ += pad(level + 2) + "<ConstraintGeometry geomType=\"" + escaped(g->geom_type) + "\">\n";
                out_ += pad(level + 3) + "<InstancePath>\n";
                for (const std::string& uid : g->path) out_ += pad(level + 4) + "<Uid>" + escaped(uid) + "</Uid>\n";
                out_ += pad(level + 3) + "</InstancePath>\n";
                out_ += pad(level + 3) + "<Position>" + number(g->position.x() * d_.per_metre) + " " +
                        number(g->position.y() * d_.per_metre) + " " + number(g->position.z() * d_.per_metre) +
                        "</Position>\n";
                out_ += pad(level + 3) + "<Axis>" + number(g->axis.x()) + " " + number(g->axis.y()) + " " +
                        number(g->axis.z()) + "</Axis>\n";
                out_ += pad(level + 2) + "</ConstraintGeometry>\n";
            }
            out_ += pad(level + 1) + "</" + m.type + ">\n";
        }
        out_ += pad(level) + "</Constraints>\n";
    }

    void joints(const std::vector<SimscapeXmlJoint>& js, int level) {
        if (js.empty()) {
            out_ += pad(level) + "<Joints/>\n";
            return;
        }
        out_ += pad(level) + "<Joints>\n";
        for (const SimscapeXmlJoint& j : js) {
            out_ += pad(level + 1) + "<" + j.type + " name=\"" + escaped(j.name) + "\">\n";
            frame("BaseFrame", j.base, level + 2);
            frame("FollowerFrame", j.follower, level + 2);
            out_ += pad(level + 1) + "</" + j.type + ">\n";
        }
        out_ += pad(level) + "</Joints>\n";
    }

    void part(const SimscapeXmlPart& p) {
        out_ += "      <Part name=\"" + escaped(p.name) + "\" uid=\"" + escaped(p.uid) + "\">\n";
        if (p.has_mass_properties) {
            const double inertia = d_.per_kilogram * d_.per_metre * d_.per_metre;
            const Eigen::Matrix3d& I = p.inertia;
            out_ += "         <MassProperties>\n";
            out_ += "            <Mass>" + number(p.mass * d_.per_kilogram) + "</Mass>\n";
            out_ += "            <CenterOfMass>" + number(p.com.x() * d_.per_metre) + " " +
                    number(p.com.y() * d_.per_metre) + " " + number(p.com.z() * d_.per_metre) + "</CenterOfMass>\n";
            // Ixx Iyy Izz Iyz Izx Ixy, the products as the tensor's entries.
            out_ += "            <Inertia>" + number(I(0, 0) * inertia) + " " + number(I(1, 1) * inertia) + " " +
                    number(I(2, 2) * inertia) + " " + number(I(1, 2) * inertia) + " " + number(I(2, 0) * inertia) +
                    " " + number(I(0, 1) * inertia) + "</Inertia>\n";
            out_ += "         </MassProperties>\n";
        }
        if (!p.geometry_file.empty())
            out_ += "         <GeometryFile name=\"" + escaped(p.geometry_file) + "\" type=\"STEP\"/>\n";
        out_ += "         <VisualProperties>\n            <Diffuse a=\"" + number(p.colour[3]) + "\" b=\"" +
                number(p.colour[2]) + "\" g=\"" + number(p.colour[1]) + "\" r=\"" + number(p.colour[0]) +
                "\"/>\n         </VisualProperties>\n";
        out_ += "      </Part>\n";
    }

    const SimscapeXmlDocument& d_;
    std::string out_;
};

}  // namespace

std::string simscape_xml(const SimscapeXmlDocument& document) { return Writer(document).run(); }

void write_simscape_xml(const std::string& path, const SimscapeXmlDocument& document) {
    write_whole_file(path, simscape_xml(document));
}

}  // namespace mbx_samples
