// How the mechanism maps onto MJCF before any XML is written: which rigid
// bodies become MuJoCo bodies, the joints each one carries (node chains
// merged), inertials MuJoCo accepts, and the equality constraints that close
// the loops. Kept apart from the writer so tests can find bodies and joints
// by the names chosen here.
#pragma once
#include <string>
#include <vector>

#include "export/common/export_model.h"

namespace mbx {

struct MjcfJoint {
    int joint = -1;  // Mechanism::joints index; -1 for the slide of a prismatic-cut helper
    std::string name;
    mbx_primitive_type type = MBX_PRIMITIVE_REVOLUTE;
    // Joint frame in the MuJoCo body's frame at qpos0 (the assembly pose).
    // MuJoCo takes pos and axis in that frame; a ball's quaternion is the
    // joint-frame rotation conjugated by frame.rotation.
    Pose frame;
    Vec3 axis = Vec3::UnitZ();  // body frame
    bool limited = false;
    double lower = 0, upper = 0;
};

struct MjcfBody {
    int body = -1;    // RigidBody index; -1 for a helper (prismatic cut slider)
    int parent = -1;  // MjcfLayout::bodies index; -1 = worldbody
    std::string name;
    Pose world;       // at qpos0
    Pose local;       // in the parent's frame (world for worldbody children)
    bool free = false;
    std::string free_name;
    std::vector<MjcfJoint> joints;  // in MuJoCo's order of application
    double mass = 0;
    Vec3 com = Vec3::Zero();
    Mat3 inertia = Mat3::Zero();  // about com, body axes
    std::vector<int> children;    // MjcfLayout::bodies indices
};

struct MjcfEquality {
    enum Kind { CONNECT, WELD } kind = CONNECT;
    std::string name;
    int cut_joint = -1;
    int body1 = -1, body2 = -1;  // MjcfLayout::bodies; -1 = world
    Vec3 anchor = Vec3::Zero();  // connect: point in body1's frame
};

struct MjcfLayout {
    std::vector<MjcfBody> bodies;  // parents before children
    std::vector<int> top;          // worldbody's children, in order
    std::vector<int> of_body;      // RigidBody index -> MjcfLayout::bodies (-1: world or a merged node)
    std::vector<MjcfEquality> equalities;
    double light_mass = 0;     // stand-in mass for bodies MuJoCo would refuse as massless
    double light_inertia = 0;  // principal moment to go with it
    double axis_spacing = 0;   // distance between the two connects of a revolute cut
    int constraint_rows = 0;   // upper bound on MuJoCo's constraint rows (equalities and limits)
};

// Builds the layout, adding notes to `model` for what MJCF cannot say exactly.
MjcfLayout build_mjcf_layout(ExportModel& model);

}  // namespace mbx
