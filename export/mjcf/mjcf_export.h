// MuJoCo MJCF model (see docs/exporters.md).
#pragma once
#include "export/common/export_model.h"

namespace mbx {

// Appends mjcf/<name>.xml; meshes are referenced in ../meshes (the caller
// writes them, in mjcf_mesh_format()).
void export_mjcf(ExportModel& model, OutputFiles& out);

// MuJoCo reads STL and OBJ, not glTF.
inline mbx_mesh_format mjcf_mesh_format(mbx_mesh_format chosen) {
    return chosen == MBX_MESH_OBJ ? MBX_MESH_OBJ : MBX_MESH_STL;
}

// A drive MJCF holds as a PD servo (general actuator): continuous, without
// integral action or delay. Others become motor actuators.
inline bool mjcf_drive_is_servo(const Drive& d) {
    const ControllerSpec& c = d.spec.controller;
    return c.ki == 0 && c.kvi == 0 && c.sample_period == 0 && c.delay == 0;
}

// Name of the actuator of the drive on MJCF joint `joint_name`.
inline std::string mjcf_actuator_name(const std::string& joint_name) { return "drive_" + joint_name; }

}  // namespace mbx
