// URDF (spanning tree) plus the cut-joint sidecar (see docs/exporters.md).
#pragma once
#include "export/common/export_model.h"

namespace mbx {

// Appends urdf/<name>.urdf and, when the mechanism has loops,
// urdf/<name>.cut_joints.json; meshes are referenced as ../meshes/<stem>.<ext>.
void export_urdf(ExportModel& model, OutputFiles& out);

inline mbx_mesh_format urdf_mesh_format(mbx_mesh_format chosen) {
    return chosen == MBX_MESH_OBJ ? MBX_MESH_OBJ : MBX_MESH_STL;
}

}  // namespace mbx
