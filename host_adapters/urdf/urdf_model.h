// A URDF file as read (ROS's Unified Robot Description Format): links with
// their inertial, visual and collision elements, joints with origin, axis,
// limits, dynamics and mimic, and the named materials, each with the line it
// was written on. Numbers are SI as URDF defines them; nothing is composed
// yet (urdf_assembly does that).
#pragma once
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "host_adapters/memory/memory_host.h"

namespace mbx_files {

// x_parent = R(rpy) x_child + xyz, R = Rz(yaw) Ry(pitch) Rx(roll).
struct UrdfOrigin {
    Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
    Eigen::Isometry3d pose() const;
};

struct UrdfGeometry {
    enum class Kind { box, cylinder, sphere, mesh } kind = Kind::box;
    Eigen::Vector3d size = Eigen::Vector3d::Zero();  // box: full side lengths
    double radius = 0, length = 0;                   // cylinder (along z), sphere
    std::string filename;                            // mesh, as written (package://, file://, relative, absolute)
    Eigen::Vector3d scale = Eigen::Vector3d::Ones();
};

struct UrdfColour {
    bool given = false;
    double rgba[4] = {0.7, 0.7, 0.7, 1};
};

// A <visual> or <collision> element.
struct UrdfShape {
    std::string name;
    int line = 0;
    UrdfOrigin origin;
    bool has_geometry = false;
    UrdfGeometry geometry;
    std::string material;  // visual: the material's name (defined here or at the top)
    UrdfColour colour;     // visual: the colour the element or its named material gives
};

struct UrdfInertial {
    bool given = false;
    int line = 0;
    UrdfOrigin origin;  // the centre of mass and the inertia's axes, in the link frame
    double mass = 0;
    // The inertia tensor's entries about the centre of mass (ixy = -sum x y m).
    double ixx = 0, ixy = 0, ixz = 0, iyy = 0, iyz = 0, izz = 0;
};

struct UrdfLink {
    std::string name;
    int line = 0;
    UrdfInertial inertial;
    std::vector<UrdfShape> visuals, collisions;
};

struct UrdfJoint {
    std::string name, type, parent, child;  // type: revolute, continuous, prismatic, fixed, floating, planar
    int line = 0;
    UrdfOrigin origin;                                  // the joint frame in the parent link's frame
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();    // in the joint frame, unit
    bool has_limit = false;
    double lower = 0, upper = 0, effort = 0, velocity = 0;
    int limit_line = 0;
    bool has_dynamics = false;
    double damping = 0, friction = 0;
    bool has_mimic = false;
    std::string mimic_joint;
    double mimic_multiplier = 1, mimic_offset = 0;
    int mimic_line = 0;
};

// A joint that closes a loop, from the cut-joint file mbx's URDF export
// writes beside the URDF (<robot>.cut_joints.json): a URDF is a tree.
struct UrdfCutJoint {
    std::string name, type;  // revolute, prismatic, spherical, fixed
    std::string parent, child;
    UrdfOrigin parent_origin, child_origin;  // the joint frame in each link's frame
    bool has_axis = false;
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // in the parent link's frame
    bool has_limit = false;
    double lower = 0, upper = 0;
    int line = 0;  // in the cut-joint file
};

struct UrdfModel {
    std::string file, name;
    int robot_line = 0;
    std::vector<UrdfLink> links;
    std::vector<UrdfJoint> joints;
    std::map<std::string, UrdfColour> materials;  // top-level named materials
    std::string cut_joint_file;                   // "" when none was found
    std::vector<UrdfCutJoint> cut_joints;
    // What the reader noticed, as the host serves it.
    std::vector<mbx_memory::Diagnostic> diagnostics;
};

}  // namespace mbx_files
