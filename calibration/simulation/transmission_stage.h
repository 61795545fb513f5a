// The transmission stage of calibrate() (docs/calibration.md): after the
// linear identification, an elastic transmission (`compliance`) in place of
// the armature or gain the rigid model saw, fitted through the simulator
// (calibration/nonlinear_fit.h add_transmissions), or a dead band
// (`backlash`) where the linear causes leave a large share of the effort,
// where the simulation fit can carry the model; elsewhere a warning says why
// it was not tried.
#pragma once
#include <string>
#include <vector>

#include "calibration/identification/identify.h"
#include "calibration/simulation/nonlinear_fit.h"
#include "calibration/records/records.h"
#include "sim/model.h"

namespace mbx::calibration {

// `linear` with compliance named in place of an armature or actuator gain
// when the simulation fit finds it (add_transmissions' tests), else, when
// the linear causes leave more than `dead_band_left` % of the validation
// effort, with a backlash on the actuated joint where it cuts the simulated
// validation error most (by `backlash_relative_gain` at least, its width
// beyond `backlash_t_ratio` standard errors), else as it was. The stage runs on 1-dof trees whose named causes the simulation can
// carry and that hold no transmission yet; where an armature or gain was
// named and it cannot run, the returned warnings say why. Records whose
// simulation fails (no effort on an actuated joint, too short) give a
// warning too, never an error. The compliance's fit and validation errors
// are the rigid limit's (its motor inertia as the armature): the inverse-
// dynamics figures of the step it replaces; the simulated ones are in its
// evidence.
Identification transmission_stage(const sim::Model& m, const std::vector<const Record*>& fit,
                                  const std::vector<const Record*>& validation, const Identification& linear,
                                  const TransmissionOptions& options = {});

// The model a rigid inverse-dynamics fit sees: every elastic transmission
// taken out, its motor inertia added to its joint's armature (the link at
// the motor's position), the reference inertias updated.
sim::Model rigid_limit(const sim::Model& m);

}  // namespace mbx::calibration
