// From named causes to a model that has them: joint dynamics added to the
// description's (friction, offset, spring, armature), a drive's controller
// delay, and what only a replay can apply (an actuator's gain, a sensor's
// offset, a body's inertia, a delay on a recorded effort). The replays of each
// calibration step and the extended description file both come from here.
#pragma once
#include <vector>

#include "calibration/calibrate.h"
#include "calibration/simulation/replay.h"

namespace mbx::calibration {

struct ModelExtension {
    sim::BuildOptions options;            // the description's, with the causes' joint dynamics and delays
    std::vector<BodyCorrection> body_corrections;  // per sim body (identity: unchanged)
    std::vector<double> drive_gain;       // per drive: the actuator's effort per commanded effort
    ReplayAdjustments adjust;
    std::vector<JointUpdate> joints;
    std::vector<DriveUpdate> drives;
    std::vector<BodyUpdate> bodies;
    std::vector<UnwrittenCause> unwritten;
    std::vector<std::string> warnings;
};

// The extension by the first `count` causes of `id` (their parameters from
// the final joint fit). `base_model` is the model built from `base`; `fit`
// the rows the causes were identified on (their smoothing speeds).
ModelExtension extend(const Mechanism& mechanism, const sim::BuildOptions& base, const sim::Model& base_model,
                      const Identification& id, size_t count, const RegressionRows& fit);

// The simulation model a replay in `mode` runs: built with the extension's
// options, body inertias corrected, drive gains applied; effort-driven and free
// replays keep the drives' rotor inertia but not their controllers.
sim::Model extended_model(const Mechanism& mechanism, const ModelExtension& ext, DriveMode mode);

}  // namespace mbx::calibration
