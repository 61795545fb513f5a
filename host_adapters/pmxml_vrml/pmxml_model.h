// A first-generation SimMechanics "Physical Modeling XML" file as read, before
// it becomes an mbx_memory::Assembly. Everything the SDK does not need but a
// user or a test might ask about (subsystem paths, source lines, datum names)
// is kept here.
//
// Conventions: poses are world poses at the CAD configuration, each in the
// length unit of its own frame element; rotations are Eigen matrices whose
// columns are the frame's axes in world (the file stores them column-major).
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <mbx/mbx.h>

#include "host_adapters/memory/memory_host.h"

namespace mbx_files {

struct PmxmlFrame {
    std::string id;            // host frame id, "<body id>::<frame name>"
    std::string name;          // "CG", "CS1", "CS2", ...
    std::string display_name;  // CAD datum name of user-added frames, "" if none
    std::string node_id;       // "" if absent (Inventor exports)
    std::string ref;           // joint-end reference, "" if none
    int body = -1;             // index into PmxmlModel::bodies
    Eigen::Vector3d position = Eigen::Vector3d::Zero();   // world, length unit below
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // world, as printed (rounded)
    std::string length_unit;
    double length_to_m = 1;
    bool to_host = false;  // joint ends and user-added datums; CG and CS1 live in the body
    int line = 0;
};

struct PmxmlBody {
    std::string id;       // nodeID, or "<subsystem path>/<name>" without one; unique
    std::string name;     // display name; repeats ("RootPart")
    std::string node_id;  // "" if absent
    std::vector<std::string> subsystem_path;  // enclosing Subsystem names, outermost first
    uint32_t flags = 0;   // MBX_BODY_GROUND for RootGround, MBX_BODY_HELPER for RootParts
    double mass = 0;
    std::string mass_unit;
    double mass_to_kg = 1;
    double volume = 0;  // CAD solid volume in volume_to_m3 units; 0 if absent
    double volume_to_m3 = 1;
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the CG, CS1 axes, inertia unit
    std::string inertia_unit;
    double inertia_to_kg_m2 = 1;
    Eigen::Vector3d com = Eigen::Vector3d::Zero();  // CG in the CS1 frame, CS1's length unit
    int cs1 = -1;  // frame index: the body (part) frame; the ground's only frame
    int cg = -1;   // frame index, -1 for the ground
    std::string geometry_file;  // as written, "" if none
    int geometry_line = 0;
    int line = 0;
};

struct PmxmlPrimitive {
    mbx_primitive_type type = MBX_PRIMITIVE_WELD;
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // world; meaningless for weld and spherical
    int line = 0;
};

struct PmxmlJoint {
    std::string id;       // nodeID, made unique with a "~k" suffix
    std::string name;     // "Base--Follower"; repeats
    std::string node_id;
    std::vector<std::string> subsystem_path;  // where it is stored (not where its bodies are)
    int base_frame = -1;      // frame indices, resolved through the global refs
    int follower_frame = -1;
    std::vector<PmxmlPrimitive> primitives;  // file order: the first is next to the base
    std::string status;  // exporter diagnostic, "" if none
    int line = 0;
};

struct PmxmlModel {
    std::string file;           // as given to the reader
    std::string name;           // the model container's name
    std::string container;      // "SimMechanics" or "SimscapeMultibody"
    std::string created_using;  // exporter version, "" if absent
    std::vector<PmxmlBody> bodies;
    std::vector<PmxmlFrame> frames;
    std::vector<PmxmlJoint> joints;
    std::vector<mbx_memory::Diagnostic> diagnostics;  // reader warnings, with file and line

    size_t max_subsystem_depth() const {
        size_t d = 0;
        for (const PmxmlBody& b : bodies) d = std::max(d, b.subsystem_path.size());
        return d;
    }
};

// The first field in which two models differ, "" if none (bitwise for
// numbers): what reading a file by parts and as one DOM must agree on.
std::string first_difference(const PmxmlModel& a, const PmxmlModel& b);

// Rotation closest to `r` (polar decomposition), for computing with rounded
// matrices; `r` must have a positive determinant.
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& r);

}  // namespace mbx_files
