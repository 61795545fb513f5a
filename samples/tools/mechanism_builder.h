// Builds a PMXML document and its VRML scene together from parts given as
// geometry: mass, centre of mass, inertia, volume and area of every body come
// from its closed meshes and a density, joint-end frames are placed where the
// joint is, refs and node ids are handed out the way SimMechanics Link does,
// and the RootGround/RootPart scaffolding is added around it all.
#pragma once
#include <string>
#include <vector>

#include "pmxml_document.h"
#include "step_writer.h"
#include "vrml_writer.h"

namespace mbx_samples {

struct SimscapeXmlDocument;

PmxmlPrimitive weld();
PmxmlPrimitive revolute(const Eigen::Vector3d& axis);
PmxmlPrimitive prismatic(const Eigen::Vector3d& axis);
PmxmlPrimitive spherical();

class MechanismBuilder {
public:
    // `density` in mass unit per length unit cubed.
    MechanismBuilder(const std::string& model_name, const PmxmlUnits& units, double density);

    // Subsystem 0 is the model itself. A new subsystem gets its own massless
    // RootPart whose CS1 is the sub-assembly's placement.
    int add_subsystem(int parent, const std::string& name, const Eigen::Isometry3d& placement);
    int root_part(int subsystem) const { return subsystems_[size_t(subsystem)].root_part; }

    // A part with its geometry in its part frame, written to `file_name`.
    int add_part(int subsystem, const std::string& name, const Eigen::Isometry3d& cs1, std::vector<VrmlShape> shapes,
                 const std::string& file_name);

    // A rigid CAD sub-assembly that the PMXML exporter wrote as ONE body
    // (thesis section 2.7.1) while the VRML keeps its parts: one Transform at
    // the body's CS1 holding a Transform per part.
    struct SubPart {
        std::string name;
        Eigen::Isometry3d pose;  // in the body frame
        std::vector<VrmlShape> shapes;  // in the sub-part's own frame
        std::string file_name;
    };
    int add_rigid_assembly(int subsystem, const std::string& name, const Eigen::Isometry3d& cs1,
                           std::vector<SubPart> parts);

    // A part whose geometry file is shared with others (the generator): the
    // caller gives the file's unit-density properties in the part frame.
    int add_shared_part(int subsystem, const std::string& name, const Eigen::Isometry3d& cs1,
                        const SolidProperties& unit_density, const std::string& url, const Eigen::Vector3d& color);

    // Base -> primitives -> follower, both end frames at `at` (world),
    // world-aligned as exporters write them.
    void add_joint(int base, int follower, const Eigen::Vector3d& at, std::vector<PmxmlPrimitive> primitives,
                   const std::string& status = "");
    // RootPart of `subsystem` welded to `body` at the body's part frame.
    void weld_to_root_part(int subsystem, int body);

    // Adds the RootGround, its weld to the top RootPart and the RootParts'
    // centres of mass (the assembly's). Call once, after everything else.
    const PmxmlDocument& finish();
    const PmxmlDocument& document() const { return doc_; }

    // The VRML scene: top-level placements in body order; with
    // `nest_subsystems` every subsystem becomes a Transform at its placement
    // holding its parts (CAD assembly structure).
    VrmlAssembly vrml(const std::string& file_name, double unit_in_model, bool nest_subsystems) const;
    void add_geometry_file(VrmlGeometryFile file) { shared_files_.push_back(std::move(file)); }
    // Writes `shape` in place in the body's Transform instead of an Inline.
    void set_shape_in_place(int body, const VrmlShape& shape);

    // The same assembly as a Simscape Multibody second-generation export
    // (simscape_twin.cpp): a part and an instance per body (a rigid
    // sub-assembly's parts inside a rigid instance), subsystems as nested
    // instances holding their joints, the RootPart welds as grounded
    // instances, every part's shapes one STEP file in `directory` in
    // `step_unit`. Mass properties in SI from the same solids.
    SimscapeXmlDocument simscape(const std::string& directory, const StepLengthUnit& step_unit) const;

    size_t body_count() const { return doc_.bodies.size(); }
    const Eigen::Isometry3d& cs1(int body) const { return bodies_[size_t(body)].cs1; }

private:
    struct BodyInfo {
        int subsystem = 0;
        Eigen::Isometry3d cs1 = Eigen::Isometry3d::Identity();
        Eigen::Vector3d cg = Eigen::Vector3d::Zero();  // world
        double mass = 0;
        VrmlPlacement placement;  // pose: world (CS1)
        std::vector<VrmlGeometryFile> files;
        bool helper = false;
    };
    struct JointInfo {
        int base = 0, follower = 0;
        Eigen::Vector3d at = Eigen::Vector3d::Zero();  // world, length unit
        std::vector<PmxmlPrimitive> primitives;
    };
    struct SubsystemInfo {
        int parent = -1;
        int root_part = -1;
        Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
        std::vector<int> children;
    };

    int new_body(int subsystem, const std::string& name, const Eigen::Isometry3d& cs1, bool helper);
    void set_mass(int body, const SolidProperties& unit_density, const Eigen::Vector3d& color);
    int add_frame(int body, const Eigen::Vector3d& at, const std::string& joint_node_id);
    int common_subsystem(int a, int b) const;
    VrmlPlacement nested(int subsystem) const;

    PmxmlDocument doc_;
    double density_;
    int next_node_ = 40;
    int next_ref_ = 1;
    bool finished_ = false;
    std::vector<BodyInfo> bodies_;
    std::vector<SubsystemInfo> subsystems_;
    std::vector<JointInfo> joints_;
    std::vector<VrmlGeometryFile> shared_files_;
};

}  // namespace mbx_samples
