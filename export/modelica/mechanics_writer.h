// The generated mechanical model (Mechanics.mo): world, one Parts.Body per
// dynamic rigid body, fixed frames and MSL joints following the shared joint
// placement, planar-loop cut joints, drive flanges and mesh visuals.
#pragma once
#include <string>

#include "common/export_model.h"

namespace mbx {

// Text of <package>/Mechanics.mo. Notes what MSL cannot express on `model`.
std::string write_mechanics(ExportModel& model, const std::string& package);

// Path of body's STL below the package, e.g. "Resources/Meshes/crank.stl".
std::string modelica_mesh_path(ExportModel& model, int body);

}  // namespace mbx
