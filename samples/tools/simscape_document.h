// A Simscape Multibody second-generation import file as the sample tools and
// the tests write it: parts, a nested instance tree with transforms relative
// to the parent, typed joints with frames in their instance's part frame.
// Everything is given in SI and converted to the document's DataUnits when
// written, so one mechanism can be written in metres and in inches.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace mbx_samples {

struct SimscapeXmlPart {
    std::string uid, name;
    bool has_mass_properties = true;
    double mass = 0;                                       // kg
    Eigen::Vector3d com = Eigen::Vector3d::Zero();         // part frame, m
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();     // about the com, part axes, kg m^2 (tensor)
    std::string geometry_file;                             // "" = none
    Eigen::Vector4d colour = Eigen::Vector4d(0.7, 0.7, 0.7, 1);
};

struct SimscapeXmlInstance {
    std::string uid, name, entity_uid;
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();  // relative to the parent instance, m
    bool grounded = false, rigid = false;
    std::string rigid_group;
    std::vector<SimscapeXmlInstance> children;
};

struct SimscapeXmlFrame {
    std::vector<std::string> path;  // instance uids from the joint's assembly down
    Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  // in that instance's frame, m
};

struct SimscapeXmlJoint {
    std::string type, name;  // Revolute, Prismatic, ...
    SimscapeXmlFrame base, follower;
};

// A mate as SolidWorks, Creo and Inventor export them: two geometries, each
// on an instance, position and axis in that instance's frame.
struct SimscapeXmlMateGeometry {
    std::string geom_type;  // plane, cylinder, circle, sphere, point
    std::vector<std::string> path;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
};

struct SimscapeXmlMate {
    std::string type, name;  // Coincident, Concentric, ...
    SimscapeXmlMateGeometry first, second;
};

struct SimscapeXmlAssembly {
    std::string uid, name;
    std::vector<SimscapeXmlJoint> joints;
};

struct SimscapeXmlDocument {
    std::string created_from = "mbx_make_samples", created_by = "mbx";
    // The DataUnits written, and how many of them make a metre and a kilogram.
    std::string length_unit = "meter", mass_unit = "kilogram";
    double per_metre = 1, per_kilogram = 1;
    bool write_data_units = true;
    int digits = 17;  // significant digits written (exporters print 9 or 10)
    std::string root_name, root_uid;
    std::vector<SimscapeXmlPart> parts;
    std::vector<SimscapeXmlAssembly> assemblies;
    std::vector<SimscapeXmlInstance> instances;
    std::vector<SimscapeXmlJoint> joints;
    std::vector<SimscapeXmlMate> mates;  // the root assembly's <Constraints>
};

std::string simscape_xml(const SimscapeXmlDocument& document);
// Written whole or not at all (temp + rename); throws std::runtime_error.
void write_simscape_xml(const std::string& path, const SimscapeXmlDocument& document);

}  // namespace mbx_samples
