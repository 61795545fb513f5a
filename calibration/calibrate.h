// The whole calibration loop of docs/calibration.md: replay the model along
// the measured records as it is (baseline), identify the causes it lacks
// (calibration/identify.h), extend the model with them one at a time,
// replay again after each, and keep what a report, the JSON file and the
// extended description file need. `mbx calibrate` and mbx_calibrate call it.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calibration/simulation/contact_stage.h"
#include "calibration/identification/identify.h"
#include "calibration/records/records.h"
#include "sim/build_model.h"

namespace mbx::calibration {

// The error of one compared signal on one record, from a replay in the
// simulator. `relative` is 100 ||y - y_sim|| / ||y_ref||, y_ref being the
// signal itself for efforts and, for positions, its motion within each
// replayed window (so a run that stands still is not 0.1 % off).
struct SignalError {
    int record = -1;  // index into the loaded records
    Role role = Role::Fit;
    int joint = -1;   // sim joint
    Quantity quantity = Quantity::Effort;
    int body = -1, component = -1;  // a body quantity (joint -1): its sim body, axis or component
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    double weight = 1;
    double relative = 0;  // %
    double rms = 0;       // SI
};

// One step of the loop: the model before any cause ("baseline"), then after
// each named cause in turn. Identification errors are the inverse-dynamics
// (IDIM) effort errors; simulated ones come from replays.
struct StepErrors {
    std::string label;     // "baseline" or the cause and its subject
    int cause = -1;        // Identification::causes index (-1: baseline)
    double fit_error = 0, validation_error = 0;  // % (inverse dynamics)
    std::vector<SignalError> simulated;           // per record and compared signal
    double simulated_fit = 0, simulated_validation = 0;  // % weighted over the compared signals
};

// A compared signal over one record: measured, the baseline replay and the
// calibrated one, on the record's time (thinned for plotting).
struct Trace {
    int record = -1;
    Role role = Role::Fit;
    int joint = -1;
    Quantity quantity = Quantity::Effort;
    int body = -1, component = -1;  // as SignalError's
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    std::vector<double> t, measured, baseline, calibrated;
};

// The inverse-dynamics residual of one actuated joint on the fit rows
// before and after calibration, against its measured velocity and position
// (the signature plots), thinned.
struct ResidualCloud {
    int joint = -1;
    std::vector<double> velocity, position, before, after;
};

// What calibration changes in the description file for one mechanism joint:
// its joint dynamics after calibration (the input's, with the identified
// causes added).
struct JointUpdate {
    int mechanism_joint = -1;  // Mechanism::joints index
    int sim_joint = -1;
    std::string constraint_id;  // CAD constraint id (the description file's key)
    int primitive = 0;
    std::string name;
    bool linear = false;  // prismatic
    sim::JointDynamics before, after;
    // An elastic transmission (the description's <transmission>): as the
    // model had it and after calibration (compliance), none when absent.
    std::optional<sim::Transmission> transmission_before, transmission_after;
    std::vector<std::string> causes;  // the named causes it carries
};

// A body whose inertia calibration corrected: the description file's
// <body id mass_scale com_shift inertia_change> (docs/mechatronics.md) gets
// `correction` on top of any it already holds (the model calibrated
// already had it).
struct BodyUpdate {
    int sim_body = -1;
    int mechanism_body = -1;  // Mechanism::bodies index
    std::string id;           // the rigid body's id (its principal CAD part id)
    std::string name;
    BodyCorrection correction;  // relative to the model as given
};

// A drive whose controller delay calibration changed.
struct DriveUpdate {
    int drive = -1;  // sim::Model::drives index
    std::string constraint_id;
    std::string name;
    double delay_before = 0, delay_after = 0;  // s
};

// A cause the model file cannot hold (a sensor offset, an actuator gain):
// identified and reported, applied in the replays where they can, but not
// in the description file.
struct UnwrittenCause {
    int cause = -1;  // Identification::causes index
    std::string reason;
};

struct CalibrateOptions {
    IdentifyOptions identify;
    // Called with the stage ("replay", "identify") and the fraction done;
    // return false to cancel (mbx::Error MBX_ERROR_CANCELLED).
    std::function<bool(const char*, double)> progress;
    size_t plot_points = 1500;  // per trace and residual cloud
    // The description's collision shapes and contact materials: a free
    // experiment on a measured free body runs the contact stage on them.
    ContactInput contact;
};

struct CalibrationResult {
    DriveMode mode = DriveMode::ClosedLoop;
    std::vector<std::string> record_paths;
    std::vector<Role> record_roles;
    Identification identification;
    std::vector<StepErrors> steps;  // [0] baseline
    std::vector<Trace> traces;
    std::vector<ResidualCloud> residuals;
    std::vector<JointUpdate> joints;
    std::vector<DriveUpdate> drives;
    std::vector<BodyUpdate> bodies;
    // A mounting tilt found (rad, gravity turned about world x then y), on
    // top of the description's <mounting>.
    Eigen::Vector2d mounting_tilt = Eigen::Vector2d::Zero();
    bool mounting_tilted = false;
    std::vector<UnwrittenCause> unwritten;
    std::vector<std::string> warnings;
    ContactStageResult contact;  // ran: the contact stage instead of identification
    double wall_time = 0;  // s

    const StepErrors& baseline() const { return steps.front(); }
    const StepErrors& final_step() const { return steps.back(); }
};

// Runs the loop for `mechanism` with the drives and joint dynamics of
// `base` (the input description's). Throws mbx::Error naming file and line
// for bad records, the joint for a compared signal the mode cannot produce
// (an effort compared in closed loop on a joint without a drive), and
// MBX_ERROR_SIMULATION when a replay diverges.
CalibrationResult calibrate(const Mechanism& mechanism, const sim::BuildOptions& base, const Experiment& experiment,
                            const CalibrateOptions& options = {});

// The relative error measure of SignalError over plain vectors (%).
double relative_error(const std::vector<double>& measured, const std::vector<double>& simulated);

}  // namespace mbx::calibration
