// A simulated trajectory (trajectory.csv, sim/simulation.h) turned into what
// a viewer plays: the world pose of every body that has a mesh at every
// sample, keyed by its node name in scene.glb (the mesh stem). Forward
// kinematics is the simulator's, so the page shows exactly the simulated
// motion, loops included (every tree coordinate is in the file).
#pragma once
#include <string>
#include <vector>

#include "export/common/export_model.h"

namespace mbx {

struct PosedTrajectory {
    std::vector<std::string> nodes;  // scene.glb node names
    std::vector<double> times;       // s
    // Per sample, per node: x y z (m) then the quaternion w x y z.
    std::vector<double> poses;
    size_t frames() const { return times.size(); }
};

// Reads `trajectory_csv` (as `mbx simulate` writes it for this mechanism)
// and poses every meshed body of `model` at each row. Throws mbx::Error
// naming the file: a missing joint column, a cell that is not a number,
// time not increasing.
PosedTrajectory pose_trajectory(ExportModel& model, const std::string& trajectory_csv);

// The same at one configuration q (sim coordinates), for tests and the CAD pose.
PosedTrajectory pose_configuration(ExportModel& model, const std::vector<double>& q);

}  // namespace mbx
