// A first-generation PMXML file as the sample tools write it (the layout of
// shared/data/pmxml/FORMAT_NOTES.md section 3): world poses, one set of unit
// strings for the whole file, global frame refs.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace mbx_samples {

struct PmxmlUnits {
    std::string length = "mm", mass = "kg", inertia = "kg*m^2", volume = "mm^3", area = "mm^2";
    // Inertia unit per (mass unit * length unit^2): 1e-6 for kg*mm^2 -> kg*m^2.
    double inertia_factor = 1e-6;
};

struct PmxmlFrame {
    int ref = 0;  // > 0: a joint end
    std::string name, display_name, node_id;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();        // world, length unit
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();    // columns: axes in world
};

struct PmxmlBody {
    std::string name, node_id;
    double mass = 0;
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the CG, CS1 axes, inertia unit
    double volume = 0, area = 0;
    std::vector<PmxmlFrame> frames;  // CG, CS1, then joint frames
    bool has_color = false;
    Eigen::Vector3d color = Eigen::Vector3d::Constant(0.7);
};

struct PmxmlPrimitive {
    std::string name;  // weld, revolute, prismatic, spherical
    Eigen::Vector3d axis = Eigen::Vector3d::Constant(0.57735);
};

struct PmxmlJoint {
    std::string name, node_id, status;
    int base_ref = 0, follower_ref = 0;
    std::vector<PmxmlPrimitive> primitives;  // the first is next to the base
};

struct PmxmlSubsystem {
    std::string name, node_id;
    std::vector<int> bodies;   // indices into PmxmlDocument::bodies
    std::vector<int> joints;   // indices into PmxmlDocument::joints
    std::vector<int> children; // indices into PmxmlDocument::subsystems
};

struct PmxmlDocument {
    std::string model_name;
    std::string created_using = "SimMechanics Link Version 4.0";
    std::string created_from = "mbx_make_samples";
    std::string created_on = "01/01/24||00:00:00";
    std::string created_by = "mbx";
    PmxmlUnits units;
    int digits = 10;  // significant digits; real exporters write 6
    std::vector<PmxmlBody> bodies;
    std::vector<PmxmlJoint> joints;
    std::vector<PmxmlSubsystem> subsystems;  // [0] is the model container
    PmxmlFrame ground_frame;                  // RootGround's only frame
};

// Writes the document; throws std::runtime_error when the file cannot be written.
void write_pmxml(const std::string& path, const PmxmlDocument& document);

}  // namespace mbx_samples
