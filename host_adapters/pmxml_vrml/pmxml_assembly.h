// A read PMXML model as the in-memory host serves it: bodies at their CS1
// pose with their own units, joint-end and user-added frames in WORLD,
// SimpleJoints as constraints with world axes and the exporter's status.
#pragma once
#include "host_adapters/memory/memory_host.h"
#include "pmxml_model.h"

namespace mbx_files {

// Shapes are left to the caller; reader warnings become diagnostics.
mbx_memory::Assembly to_assembly(const PmxmlModel& model);

// Body pose, frame pose: rotation written row-major as mbx.h wants.
mbx_pose to_pose(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& position);

}  // namespace mbx_files
