// The generated mechanical model (Mechanics.mo): world, one Parts.Body per
// dynamic rigid body, fixed frames and MSL joints following the shared joint
// placement, planar-loop cut joints, drive flanges and mesh visuals.
#pragma once
#include <string>
#include <vector>

#include "export/common/export_model.h"

namespace mbx {

// The top-level connectors of Mechanics that stand for one joint's drive
// flanges (axis_<joint>, support_<joint>): rotational for a revolute,
// translational for a prismatic. Both empty when the joint has none (cut
// joints, planar-loop constraints, spherical joints).
struct JointFlanges {
    std::string axis, support;
};

// Text of <package>/Mechanics.mo. Notes what MSL cannot express on `model`.
// `flanges`, when given, receives each mechanism joint's flange names (what
// a model that instantiates Mechanics connects its drives to).
std::string write_mechanics(ExportModel& model, const std::string& package,
                            std::vector<JointFlanges>* flanges = nullptr);

// Path of body's STL below the package, e.g. "Resources/Meshes/crank.stl".
std::string modelica_mesh_path(ExportModel& model, int body);

}  // namespace mbx
