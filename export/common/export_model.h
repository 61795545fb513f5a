// What every exporter reads: the mechanism, one joint placement per joint (so
// a coordinate means the same in every format), the tree in parent-first
// order, the bodies' meshes (fetched lazily, once) and their file stems. The
// exporters return files as data; export/export_files.cpp writes them.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "core/assembly/shape_loader.h"
#include "core/kinematics/placement.h"
#include "core/mechatronics/drive.h"
#include "core/translator/mechanism.h"

namespace mbx {

struct ExportSettings {
    std::string model_name = "model";  // already a usable file stem; exporters sanitize further
    mbx_mesh_format mesh_format = MBX_MESH_STL;
    double stop_time = 10;  // Modelica experiment
    // Drives resolved against the mechanism (resolve_drives); empty: a passive
    // mechanism. Every format writes the same drive quantities (Drive).
    std::vector<Drive> drives;
    // Joint dynamics resolved against the mechanism (resolve_joint_dynamics):
    // damping, friction, spring, limits and armature of tree joints. A joint
    // that also has a drive gets both (armatures and dampings add up).
    std::vector<ResolvedJointDynamics> joint_dynamics;
    // Collision shapes and contact materials (resolve_contact): MJCF geoms,
    // URDF <collision>, and in the glTF scene when scene_collision is set.
    ResolvedContact contact;
    // The description's <mounting>: MJCF's gravity and Modelica's world
    // direction are turned by its tilt, as the simulator's are.
    MountingSpec mounting;
    // scene.glb also shows the collision shapes (semi-transparent nodes; opt-in).
    bool scene_collision = false;
};

// One output file, path relative to the output directory with '/' separators.
struct OutputFile {
    std::string path;
    std::string contents;
    bool keep_existing = false;  // user-owned: written only when absent (Modelica's user model)
};
using OutputFiles = std::vector<OutputFile>;

// Meshes of rigid body `body` in its frame, metres. May throw mbx::Error.
using BodyShapes = std::function<const std::vector<Mesh>&(int body)>;

class ExportModel {
public:
    // `shapes` may be empty (no geometry available).
    ExportModel(const Mechanism& m, BodyShapes shapes, ExportSettings settings);

    const Mechanism& mechanism() const { return m_; }
    const ExportSettings& settings() const { return settings_; }
    const TreeIndex& tree() const { return tree_; }
    const JointPlacement& placement(int joint) const { return placements_[size_t(joint)]; }
    // The drive on mechanism joint `joint`, nullptr when it is passive.
    const Drive* drive_of(int joint) const {
        const int d = joint >= 0 && size_t(joint) < drive_index_.size() ? drive_index_[size_t(joint)] : -1;
        return d < 0 ? nullptr : &settings_.drives[size_t(d)];
    }
    // The joint dynamics of mechanism joint `joint`, nullptr when it has none.
    const ResolvedJointDynamics* joint_dynamics_of(int joint) const {
        const int d = joint >= 0 && size_t(joint) < dynamics_index_.size() ? dynamics_index_[size_t(joint)] : -1;
        return d < 0 ? nullptr : &settings_.joint_dynamics[size_t(d)];
    }
    // Position limits of a revolute or prismatic joint as every format writes
    // them: the joint dynamics' when given, else the CAD joint's.
    bool limits(int joint, double& lower, double& upper) const;
    // The CAD constraint a joint came from, for notes about it.
    Subject joint_subject(int joint) const;

    // Meshes of `body` (empty when there is no geometry or it failed to load;
    // a failure becomes a note once).
    const std::vector<Mesh>& shapes(int body);
    // File stem of body's mesh, unique over the model ("" when the body has no
    // triangles). Stems are assigned in body order when first asked.
    const std::string& mesh_stem(int body);
    bool has_mesh(int body) { return !mesh_stem(body).empty(); }
    // Path of body's mesh file relative to the output directory, e.g. "meshes/link1.stl".
    std::string mesh_path(int body, mbx_mesh_format format);

    // Export findings (warnings about what a format cannot express). Identical
    // notes are kept once.
    void note(mbx_severity severity, mbx_finding_code code, Subject subject, std::string message);
    const Findings& notes() const { return notes_; }

private:
    void assign_stems();

    const Mechanism& m_;
    BodyShapes fetch_;
    ExportSettings settings_;
    TreeIndex tree_;
    std::vector<JointPlacement> placements_;
    std::vector<int> drive_index_;     // joint -> settings_.drives index, -1 when passive
    std::vector<int> dynamics_index_;  // joint -> settings_.joint_dynamics index, -1 when none
    std::vector<char> loaded_;
    std::vector<std::vector<Mesh>> cache_;
    std::vector<std::string> stems_;
    bool stems_assigned_ = false;
    Findings notes_;
};

const char* mesh_extension(mbx_mesh_format format);  // "stl", "obj", "glb"

}  // namespace mbx
