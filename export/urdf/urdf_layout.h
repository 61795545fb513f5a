// How the mechanism maps onto URDF's tree of links and joints: names, link
// frames, joint origins and axes. Kept apart from the XML so tests (and the
// cut-joint sidecar) see the same plan the writer used.
//
// Frames: every link frame has its rigid body's orientation. The ground link
// and floating roots sit at their body frame; every other link sits at the
// point of its parent joint, so URDF's "child link frame = joint frame" holds
// and <axis> is the joint axis in the child body's axes. A root link "world"
// (the CAD world frame) holds the ground link by a fixed joint and each
// floating root by a floating joint at its CAD pose.
#pragma once
#include <string>
#include <vector>

#include "export/common/export_model.h"

namespace mbx {

struct UrdfLink {
    std::string name;
    int body = -1;  // rigid body, -1 for "world" and the links inside a spherical joint
};

struct UrdfJoint {
    std::string name;
    std::string type;  // revolute, continuous, prismatic, fixed, floating
    int parent_link = -1, child_link = -1;
    Pose origin;  // child link frame at coordinate zero, in the parent link frame
    Vec3 axis = Vec3::UnitX();  // unit, child link frame
    bool has_limit = false;
    double lower = 0, upper = 0;
    bool default_range = false;  // prismatic without CAD limits: the documented stand-in range
    int source = -1;             // mechanism joint, -1 for the joints below "world"
    int spherical_axis = -1;     // 0, 1, 2: the x, y, z revolute of a spherical joint
};

struct UrdfLayout {
    std::string robot;                // sanitized model name: robot name and file stem
    std::vector<UrdfLink> links;      // [0] "world", then parent-first
    std::vector<UrdfJoint> joints;    // in the order written
    std::vector<int> body_link;       // rigid body -> link index
    std::vector<Pose> link_in_body;   // rigid body -> its link frame in the body frame
    std::vector<std::string> joint_name;  // mechanism joint (tree or cut) -> its unique name
};

// Stand-in travel of a prismatic joint without CAD limits, metres either way.
constexpr double kUrdfPrismaticRange = 1000;
// Limits on effort and velocity: URDF requires them, CAD has no actuator data.
constexpr double kUrdfEffortLimit = 1e6;
constexpr double kUrdfVelocityLimit = 1e3;

UrdfLayout plan_urdf(const ExportModel& model);

// URDF "rpy": fixed-axis roll about x, pitch about y, yaw about z, so that
// r = Rz(yaw) * Ry(pitch) * Rx(roll). Exact at and near pitch = +-90 degrees.
Vec3 rpy_from_rotation(const Mat3& r);

}  // namespace mbx
