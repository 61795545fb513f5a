// Inverse-dynamics identification (IDIM-LS) with forward selection of
// causes: the residual of calibration/regression_rows.h is regressed on the
// columns of candidate causes from the catalogue (calibration/causes.h).
// Causes enter one at a time, largest validation gain first, and only while
// the gain on the validation records exceeds what noise explains. A delay's
// lag and a Stribeck law's speeds are refined on the fit records before the
// candidate is judged; two causes the data cannot tell apart are a warning
// (docs/calibration.md, "Forward selection").
#pragma once
#include <cmath>

#include "calibration/identification/causes.h"
#include "calibration/identification/regression_rows.h"

namespace mbx::calibration {

struct Estimate {
    std::string name;
    double value = 0, std_error = 0;
};

// One named cause with what the selection saw.
struct SelectedCause {
    Candidate candidate;
    std::vector<Estimate> parameters;  // from the final joint fit of every named cause
    std::string evidence;              // the signature on the residual, in words and numbers
    double fit_error = 0, validation_error = 0;  // % effort error after this step (inverse dynamics)
    double validation_gain = 0;                  // percentage points the step removed
};

struct Identification {
    double baseline_fit_error = 0, baseline_validation_error = 0;  // %
    double final_fit_error = 0, final_validation_error = 0;        // %
    // % of the weighted validation effort that is the records' own noise
    // after the filter (noise_floor), the least error any model can reach;
    // NaN when not measured (no effort recorded), which every output shows
    // as "not measured", never as a figure.
    double noise_level = NAN;
    std::vector<SelectedCause> causes;
    std::vector<std::string> warnings;
    std::vector<std::string> considered;  // candidates tried in the first round, with their gains
    // Where the validation residual left above the noise concentrates
    // (velocity reversals, high accelerations, a part of a joint's range),
    // in words with its share; empty when it is spread or at the noise.
    std::vector<std::string> residual_concentration;
    // The groups of causes these records could hardly or not at all tell
    // apart (the warnings' groups), each cause as "cause on subject"
    // (subject_text): what an excitation design is asked to separate.
    std::vector<std::vector<std::string>> ambiguous;
};

Identification identify(const sim::Model& m, const RegressionRows& fit, const RegressionRows& validation,
                        const IdentifyOptions& options);

// The inverse-dynamics figures of `id`'s causes at their parameter values:
// each cause's errors with it and every earlier one in the model, its gain in
// percentage points over the step before, and the final errors. For a stage
// after identify() that changed the causes or their values (the transmission
// stage drops causes and refits the rest), whose figures would otherwise be
// those of a cause set the model no longer has.
void recompute_errors(Identification& id, const RegressionRows& fit, const RegressionRows& validation);

// Fills id.residual_concentration from the validation residual of id's
// causes at their values: per actuated joint holding at least a quarter of
// the residual, the region of its rows (speeds below a tenth of its RMS,
// accelerations above 1.5 times theirs, a fifth of its position range)
// whose share of the joint's residual is largest against its share of the
// rows, named when it holds at least a fifth of it at twice the rows' share.
void locate_residual(const sim::Model& m, Identification& id, const RegressionRows& validation);

}  // namespace mbx::calibration
