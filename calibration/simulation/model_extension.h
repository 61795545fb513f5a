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
    // A mounting tilt found (rad about world x, y; options.gravity turned by it).
    Eigen::Vector2d tilt = Eigen::Vector2d::Zero();
    bool tilted = false;
    std::vector<double> drive_gain;       // per drive: the actuator's effort per commanded effort
    ReplayAdjustments adjust;
    std::vector<JointUpdate> joints;
    std::vector<DriveUpdate> drives;
    std::vector<BodyUpdate> bodies;
    std::vector<UnwrittenCause> unwritten;
    std::vector<std::string> warnings;
};

// One cause's step of extend(): what its table entry's `extend`
// (calibration/cause_table.cpp) reads and adds to.
struct ExtensionStep {
    const Mechanism& mechanism;
    const sim::BuildOptions& base;
    const sim::Model& model;
    const RegressionRows& fit;
    ModelExtension& ext;
    int cause = -1;  // Identification::causes index
    // The description file cannot hold what the cause found (why); the replays still apply it.
    void unwritten(const std::string& reason);
    int drive_of(int dof) const;  // the model drive on a coordinate, or -1
    // The update of the cause's joint, the cause's name added to it; null,
    // and the cause unwritten, when the joint is no CAD joint.
    JointUpdate* joint(const SelectedCause& c);
    // Takes the cause's name back from the joint: what it found cannot be written (why).
    void refuse(JointUpdate& u, const std::string& reason);
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
