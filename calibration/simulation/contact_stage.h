// The contact stage of `mbx calibrate` (docs/calibration.md, "Contact causes
// in mbx calibrate"): an experiment driven freely whose records measure a
// free body's pose (body quantities, one record per trial with <trials>),
// on a model whose description gives collision shapes and contact
// materials, is calibrated by the contact fit (contact_fit.h) instead of
// joint identification: the contact causes named with their parameters and
// validation errors, the replays of the compared poses before and after,
// and the fitted material and plane offset for description.xml.
#pragma once
#include <string>
#include <vector>

#include "calibration/simulation/contact_fit.h"
#include "calibration/records/experiment.h"
#include "calibration/records/records.h"

namespace pugi {
class xml_node;
}

namespace mbx::calibration {

struct CalibrationResult;
struct CalibrateOptions;

// The model's contact as the description gives it (the C API fills it from
// the attached description's <collision> and <contact>).
struct ContactInput {
    std::vector<sim::contact::Shape> shapes;  // in sim body frames
    sim::contact::ContactSettings default_settings;
    std::vector<sim::contact::MaterialPair> pairs;
    std::vector<std::string> materials;  // names by material id (0 "default")
    bool empty() const { return shapes.empty(); }
};

struct ContactStageResult {
    bool ran = false;
    int body = -1;  // the measured free body (sim index)
    // The description's <contact> entry the body touches the world with:
    // its materials, or both "" for the entry without a and b (the default).
    std::string material_a, material_b;
    ContactModel start;
    ContactFit fit;
    std::vector<int> fit_trials, validation_trials;  // record indices
    double integrator_step = 0;  // s, the rollouts' explicit Euler step
};

// Whether the experiment is one for the contact stage: free drive mode and a
// free body whose origin position and orientation every record measures in
// full. Throws mbx::Error naming the experiment when it is one but the model
// has no collision shape.
bool contact_experiment(const Experiment& e, const sim::Model& m, const std::vector<Record>& records,
                        const ContactInput& contact);

// Runs the contact fit on the records and fills `out`: its contact section,
// a step per named cause with the compared signals' errors from rollouts
// (positions and orientations), the traces. Throws mbx::Error for a compared
// quantity a rollout does not give (velocities), a compared body other than
// the measured one, and a start contact whose rollouts diverge.
void run_contact_stage(const sim::Model& m, const Experiment& e, const std::vector<Record>& records,
                       const ContactInput& contact, const CalibrateOptions& options, CalibrationResult& out);

// Writes the named contact causes into the description: the <contact>
// entry's stiffness, damping (replacing a restitution), mu_static and
// mu_kinetic, and every world plane moved along its normal by the ground
// offset (in the element's unit). Adds a <contact> entry when the
// description has none for the pair.
// Returns the lines the file's leading comment gets.
std::vector<std::string> write_contact_update(pugi::xml_node root, const ContactStageResult& contact, const std::string& file);

}  // namespace mbx::calibration
