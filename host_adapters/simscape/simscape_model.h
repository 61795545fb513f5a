// A Simscape Multibody second-generation import file
// (<SimscapeMultibodyImportXML version="2.0">) as read, before it becomes an
// assembly: parts shared by instances, the instance tree, typed joints and
// mates, each with the line it was written on. Numbers are as written, in
// the file's DataUnits (length_to_m, mass_to_kg convert them).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "host_adapters/memory/memory_host.h"

namespace mbx_files {

// x_parent = rotation * x_local + translation (the file's row-major 3x3).
struct SimscapeTransform {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

struct SimscapePart {
    std::string uid, name;
    int line = 0;
    bool has_mass_properties = false;
    double mass = 0;
    Eigen::Vector3d com = Eigen::Vector3d::Zero();  // part frame
    // About the centre of mass in part axes; the file's six numbers are
    // Ixx Iyy Izz Iyz Izx Ixy with the products as tensor entries (-sum x y m).
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    std::string geometry_file, geometry_type;
    int geometry_line = 0;
    bool has_colour = false;
    double colour[4] = {0.7, 0.7, 0.7, 1};  // the diffuse colour, rgba
};

struct SimscapeInstance {
    std::string uid, name, entity_uid;
    int line = 0;
    bool grounded = false, rigid = false;
    std::string rigid_group;
    SimscapeTransform local;      // relative to the parent instance (the root assembly for top-level ones)
    int parent = -1;              // index into SimscapeModel::instances
    std::vector<int> children;
    int part = -1;                // index into parts when entity_uid names a part
    int assembly = -1;            // index into assemblies when it names a sub-assembly
    Eigen::Isometry3d world = Eigen::Isometry3d::Identity();
};

// One end of a joint or one geometry of a mate: a path of instance uids down
// the tree from the assembly that holds the joint (a single uid equal to the
// root assembly's: the world), and a transform in that instance's frame.
struct SimscapeFrameRef {
    std::vector<std::string> path;
    SimscapeTransform transform;
    int line = 0;
};

struct SimscapeJoint {
    std::string type;  // the element's name: Revolute, Prismatic, Cylindrical, ...
    std::string name;
    int line = 0;
    SimscapeFrameRef base, follower;
};

struct SimscapeMateGeometry {
    std::string geom_type;  // plane, circle, cylinder, sphere, ...
    SimscapeFrameRef at;    // the instance path; transform unused
    Eigen::Vector3d position = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();
    bool has_position = false, has_axis = false;
    int line = 0;
};

// A mate (Coincident, Concentric, Distance, Parallel, ...).
struct SimscapeMate {
    std::string type, name;
    int line = 0;
    std::vector<SimscapeMateGeometry> geometry;
};

// The joints and mates of the root assembly or of a sub-assembly, whose
// paths start below the instance of that assembly that holds them.
struct SimscapeMechanism {
    std::vector<SimscapeJoint> joints;
    std::vector<SimscapeMate> mates;
};

struct SimscapeAssemblyDef {
    std::string uid, name;
    int line = 0;
    SimscapeMechanism mechanism;
};

struct SimscapeModel {
    std::string file;
    std::string created_by, created_from, created_using;
    double length_to_m = 1, mass_to_kg = 1;
    bool data_units_written = false;
    std::string model_length_unit, model_mass_unit;  // <ModelUnits>, as written (display only)
    std::string root_name, root_uid;
    int root_line = 0;
    std::vector<SimscapePart> parts;
    std::vector<SimscapeAssemblyDef> assemblies;
    std::vector<SimscapeInstance> instances;  // parents before children
    std::vector<int> top;                     // the root assembly's own instances
    SimscapeMechanism root;
    // What the reader noticed (unknown elements, assumptions), as the host serves them.
    std::vector<mbx_memory::Diagnostic> diagnostics;
};

}  // namespace mbx_files
