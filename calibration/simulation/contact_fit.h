// Contact calibration (docs/calibration.md, "Contact causes"): a free body's
// measured trials (pose_records.h) rolled out by the simulator with contact
// (sim/contact) from each trial's first measured state, scored on position
// and orientation, and the contact causes fitted to them by forward
// selection: contact_stiffness, contact_damping, contact_friction and
// ground_offset. A penalty contact's outcome is not smooth in its parameters
// (a slightly stiffer contact tips a tumbling cube onto another face), so
// the fit is Ceres' Levenberg-Marquardt on Jacobians by wide central
// differences of whole rollouts, not on Jets: a derivative at one instant
// says nothing about where the cube lands. A cause is named only when it cuts
// the error on the validation trials, which the fit never sees.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "calibration/records/pose_records.h"
#include "sim/contact/contact_step.h"

namespace mbx::calibration {

// The measured body and what it touches.
struct ContactScene {
    const sim::Model* model = nullptr;
    int body = 1;                                // sim body whose pose the records measure (a free joint)
    std::vector<sim::contact::Shape> shapes;     // on it, on the world, on other bodies
    double length_scale = 0.1;                   // m: position errors are given in % of it (the body's size)
    sim::IntegratorSettings integrator = euler(1e-4);

    static sim::IntegratorSettings euler(double step) {
        sim::IntegratorSettings s;
        s.kind = sim::IntegratorKind::Euler, s.step = step;
        return s;
    }
};

// What the contact causes change.
struct ContactModel {
    sim::contact::ContactSettings settings;
    double ground_offset = 0;  // m: the world's half-spaces moved along their normals (+: up)
};

struct PoseError {
    double position = 0;  // mean over samples of |p - p_measured|, % of length_scale
    double rotation = 0;  // mean over samples of the angle between the orientations, degrees
    size_t samples = 0;
    int diverged = 0;     // rollouts whose state went non-finite or left the scene
    // One figure to rank models by: degrees weigh as % of the size.
    double score(double rotation_weight = 1) const { return position + rotation_weight * rotation; }
};

struct Rollout {
    PoseError error;
    bool diverged = false;
    // With rest_time > 0: the body left where the trial ends, simulated on;
    // how far it moves in the last half second of it and its speed then.
    double rest_drift = -1, rest_speed = -1;
    std::vector<Eigen::Vector3d> positions;     // at the record's sample times
    std::vector<Eigen::Quaterniond> orientations;
};

// One trial from its first measured state.
Rollout roll_out(const ContactScene& scene, const ContactModel& model, const PoseRecord& record, double rest_time = 0);

// Mean error over trials (every sample weighs the same), rolled out on
// `threads` threads (0: all cores).
PoseError pose_error(const ContactScene& scene, const ContactModel& model, const std::vector<PoseRecord>& records,
                     int threads = 0);

struct ContactFitOptions {
    // Candidates, by their catalogue names (all four by default).
    std::vector<std::string> causes = {"contact_stiffness", "contact_damping", "contact_friction", "ground_offset"};
    double rotation_weight = 1;        // in the fit's residuals and the selection score
    int max_iterations = 6;            // Levenberg-Marquardt iterations per fit
    double min_validation_gain = 0.02; // a cause must cut the validation score by this fraction
    int threads = 0;
    std::function<void(const std::string&)> progress;
};

struct FittedValue {
    std::string name, unit;
    double value = 0, standard_error = 0;
    std::string method;  // how it was measured, when not by least squares
};

struct ContactStep {
    std::string cause;
    std::vector<FittedValue> parameters;  // every named cause's, refitted jointly at this step
    PoseError fit, validation;             // after this step
    std::string evidence;
};

struct ContactFit {
    PoseError baseline_fit, baseline_validation;
    std::vector<ContactStep> steps;  // the named causes in the order chosen
    std::vector<std::string> notes;  // candidates left unnamed and why
    ContactModel model;              // the start with the named causes' parameters
    int rollouts = 0;                // trials simulated in all
};

// Forward selection over options.causes, one at a time, the one that lowers
// the fit error most first. Each candidate is screened alone (the gain
// coefficients on a grid, the ground offset by its rest-height signature),
// the winner refitted jointly with the named ones; stops when the best candidate does not lower the
// validation error by min_validation_gain. Throws mbx::Error for an unknown
// cause, no trials, a scene without shapes on the body, or a start model
// whose rollouts diverge.
ContactFit fit_contact(const ContactScene& scene, const ContactModel& start, const std::vector<PoseRecord>& fit,
                       const std::vector<PoseRecord>& validation, const ContactFitOptions& options = {});

}  // namespace mbx::calibration
