// A URDF model as the assembly the memory host serves: a body per link (its
// id the link's name) at the pose the joint origins put it in with every
// joint at zero, a frame pair and a primitive chain per joint (its id the
// joint's name), the root link fixed to the world (a robot bolted down, as
// ROS, MuJoCo and Pinocchio take a URDF by default) or free with
// `floating_base`. The file's tree is checked: every joint's links exist, a
// link has one parent joint, one root, no cycle; anything else is a FileError
// naming the joint and its line.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "host_adapters/memory/memory_host.h"
#include "urdf_model.h"

namespace mbx_files {

struct UrdfAssemblyOptions {
    // The root link free in space: a six-freedom joint 'floating_base' from
    // the world (three slides along the world's axes, then a ball joint).
    bool floating_base = false;
};

struct UrdfAssembly {
    mbx_memory::Assembly assembly;
    std::vector<Eigen::Isometry3d> link_world;  // by link index, at zero joint positions
    std::vector<int> link_order;                // links from the root down (the bodies' order)
    int root = -1;                              // the root link's index
};

// The id of the world body mbx adds for a floating base (a URDF whose root
// link is named "world" and has no inertial already has one: that link).
inline constexpr const char* kUrdfWorldId = "world";
inline constexpr const char* kUrdfFloatingBaseId = "floating_base";

// x as the host's pose (row-major rotation).
mbx_pose urdf_pose(const Eigen::Isometry3d& x);

UrdfAssembly to_assembly(const UrdfModel& model, const UrdfAssemblyOptions& options = {});

}  // namespace mbx_files
