// Replaying measured records in the simulator, the three ways an experiment
// drives a model (docs/calibration.md): in closed loop (the described
// controllers follow the recorded reference, with any recorded signal added
// to their output), by the recorded effort (inverse dynamics along the
// measured motion for compared efforts, forward simulation over short
// horizons from the measured state for compared positions and velocities),
// and freely from the measured initial state.
#pragma once
#include <vector>

#include "calibration/records/experiment.h"
#include "calibration/records/records.h"
#include "sim/data.h"
#include "sim/model.h"

namespace mbx::calibration {

// What a replay applies that the simulation model itself does not hold,
// per velocity coordinate: the actuator gives `effort_gain` times the
// effort it is commanded, `effort_delay` seconds late (the effort-driven
// replays; a drive's delay is its controller's), and the sensor reads the
// position plus `sensor_offset`.
struct ReplayAdjustments {
    std::vector<double> effort_gain, effort_delay, sensor_offset;
    explicit ReplayAdjustments(int nv = 0) : effort_gain(size_t(nv), 1.0), effort_delay(size_t(nv), 0.0), sensor_offset(size_t(nv), 0.0) {}
};

// A compared signal bound to the model.
struct ComparedSignal {
    int joint = -1, dof = -1, q_index = -1;
    // A body quantity (calibration/body_quantities.h): body >= 0, joint -1.
    int body = -1, component = -1;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    int drive = -1;  // the drive on the joint (-1: none)
    Quantity quantity = Quantity::Effort;
    double weight = 1;
    double start = -1, stop = -1;  // s; < 0: open
    int line = 0;
};

// Binds the experiment's <compare> elements; throws mbx::Error naming file
// and line for an unknown joint, a quantity no replay produces, and an
// effort compared in closed loop on a joint without a drive.
std::vector<ComparedSignal> compared_signals(const Experiment& e, const sim::Model& m);

// The simulated value of every compared signal at every sample of `record`
// (one vector per signal, the record's length; NaN outside the signal's
// window). `model` must be built the way the mode needs it: with the
// drives for closed loop, without them for effort and free replays.
// Throws mbx::Error (MBX_ERROR_SIMULATION) naming the record and time when
// the run diverges, and MBX_ERROR_INVALID_INPUT when a signal the mode
// needs (a reference, a measured effort, a measured position) is missing.
std::vector<std::vector<double>> replay(const sim::Model& model, const Experiment& e, const Record& record,
                                        const std::vector<ComparedSignal>& compared, const ReplayAdjustments& adjust);

// The measured state at `sample` of `record`, as every forward replay
// starts from it: each measured position and rate from a quadratic fitted to
// the 10 ms around the sample, the sensor's offset taken off, loops closed
// for the other coordinates. Throws mbx::Error for values no loop can take.
void measured_start_state(const sim::Model& m, sim::Data& d, const Record& record, size_t sample,
                          const ReplayAdjustments& adjust);

// Whether `sample` of `record` counts for `signal` (its time window).
bool in_window(const ComparedSignal& signal, const Record& record, size_t sample);

// The reference ||y_ref|| of the relative error for a compared signal on a
// record: the measured values themselves for efforts (and other signals in
// closed loop), and for positions and velocities replayed from measured
// states their change since the start of each replayed window.
std::vector<double> error_reference(const Experiment& e, const Record& record, const ComparedSignal& signal,
                                    const std::vector<double>& measured);

}  // namespace mbx::calibration
