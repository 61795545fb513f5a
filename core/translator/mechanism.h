// The translated mechanism: rigid bodies (welded parts merged), a spanning
// tree of primitive joints rooted at ground, cut joints closing the loops,
// and what mobility analysis and validation found. Exporters read only this.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/assembly/assembly.h"
#include "core/finding.h"
#include "core/math.h"

namespace mbx {

struct RigidBody {
    mbx_rigid_body_kind kind = MBX_RIGID_BODY_DYNAMIC;
    std::string id;    // principal part id, or "<constraint id>#<k>" for joint nodes
    std::string name;
    std::vector<int> parts;   // Assembly::parts merged here (empty for nodes)
    int principal_part = -1;  // part whose frame is the body frame
    double mass = 0;
    Vec3 com = Vec3::Zero();      // body frame
    Mat3 inertia = Mat3::Zero();  // about com, body axes
    Pose pose;                    // world at the assembly configuration
    int parent_joint = -1;        // tree joint whose child this is; -1 for roots
    int depth = 0;                // tree depth (ground = 0)
};

struct Joint {
    mbx_primitive_type type = MBX_PRIMITIVE_REVOLUTE;
    std::string name;
    int constraint = -1;      // Assembly::constraints index
    int primitive_index = 0;  // position in that chain (0 = J_N)
    int parent = -1;          // RigidBody index, tree-parent side
    int child = -1;           // RigidBody index, tree-child side
    bool cut = false;
    bool reversed = false;    // parent side is the CAD follower side
    Vec3 axis = Vec3::UnitZ();  // unit, world, as the host gave it (follower relative to base)
    Pose frame;                 // joint frame, world, at the assembly configuration
    bool has_limits = false;
    double lower = 0, upper = 0;
    int loop = -1;  // for cut joints: the loop it closes

    int freedoms() const {
        return type == MBX_PRIMITIVE_SPHERICAL ? 3 : type == MBX_PRIMITIVE_WELD ? 0 : 1;
    }
};

struct Loop {
    int cut_joint = -1;
    // Joints around the loop with the sign of their twist in the closure
    // equation: sum(sign * S_j * qdot_j) = 0, S_j = twist of child w.r.t. parent.
    std::vector<int> joints;
    std::vector<int> signs;
    int dof = 0;
    int gruebler_dof = 0;
    int redundant = 0;
    bool planar = false;
    Vec3 planar_normal = Vec3::Zero();
};

// A part's CAD mass data compared with its own closed meshes.
struct ShapeCheck {
    bool checked = false;
    double volume = 0;             // m^3, from the meshes
    double centroid_mismatch = 0;  // m, mesh centroid to CAD centre of mass
    double density = 0;            // kg/m^3, CAD mass / mesh volume
    double tolerance = 0;          // m, the threshold that applied
};

struct Mechanism {
    Assembly assembly;
    std::vector<RigidBody> bodies;  // [0] ground, then dynamic bodies, then joint nodes
    std::vector<Joint> joints;      // tree joints and cut joints
    std::vector<Loop> loops;
    std::vector<int> part_body;     // Assembly part index -> RigidBody index (-1: dropped helper)

    int weld_count = 0;
    int collapsed_weld_loops = 0;
    int floating_roots = 0;  // tree roots other than ground
    int dof = 0;             // numeric mobility, whole mechanism
    int gruebler_dof = 0;
    int redundant = 0;
    double length_tolerance = 0;  // metres, as used
    std::vector<ShapeCheck> shape_checks;  // per part; empty unless asked for

    Findings findings;

    void add(mbx_severity severity, mbx_finding_code code, Subject subject, std::string message) {
        Finding f;
        f.severity = severity;
        f.code = code;
        f.subject = std::move(subject);
        f.message = std::move(message);
        findings.push_back(std::move(f));
    }
    int count(mbx_severity severity) const {
        int n = 0;
        for (const Finding& f : findings) n += f.severity == severity;
        return n;
    }
};

struct TranslateOptions {
    double length_tolerance = 0;           // 0: automatic
    double orthonormality_tolerance = 1e-5;
    double rank_tolerance = 1e-6;
    bool check_mass_with_shapes = false;
    double centroid_tolerance = 0;         // 0: max(1 mm, 2 % of the mesh size)
};

}  // namespace mbx
