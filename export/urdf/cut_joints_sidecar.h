// urdf/<name>.cut_joints.json: the joints the URDF tree leaves out (one per
// closed loop), with where each sits in both of its links, so a consumer can
// add the loop-closure constraints URDF cannot state. Field by field in
// docs/exporters.md, URDF.
#pragma once
#include <string>

#include "export/urdf/urdf_layout.h"

namespace mbx {

// "" when the mechanism has no cut joints.
std::string cut_joints_json(const ExportModel& model, const UrdfLayout& layout);

}  // namespace mbx
