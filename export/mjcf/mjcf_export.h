// MuJoCo MJCF model (see docs/exporters.md).
#pragma once
#include "common/export_model.h"

namespace mbx {

// Appends mjcf/<name>.xml; meshes are referenced in ../meshes (the caller
// writes them, in mjcf_mesh_format()).
void export_mjcf(ExportModel& model, OutputFiles& out);

// MuJoCo reads STL and OBJ, not glTF.
inline mbx_mesh_format mjcf_mesh_format(mbx_mesh_format chosen) {
    return chosen == MBX_MESH_OBJ ? MBX_MESH_OBJ : MBX_MESH_STL;
}

}  // namespace mbx
