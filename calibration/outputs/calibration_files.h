// The three output files of `mbx calibrate` (docs/calibration.md, Outputs):
// calibration.json (the numbers), calibration.html (one self-contained page
// with inline SVG plots) and description.xml (the input description file
// extended with the identified joint dynamics and controller delays).
#pragma once
#include <string>

#include "calibration/calibrate.h"

namespace mbx {
struct Mechanism;
}

namespace mbx::calibration {

// Writes calibration.json, calibration.html and description.xml into `dir`
// (created if missing) as one unit: every file is built in memory, written
// to a temporary beside its target and only then renamed, so a failure
// (bad result, unreadable input description, full disk) leaves nothing new
// behind and throws mbx::Error. `input_description` is the description file
// the model's drives and joint dynamics came from ("" = none).
void write_calibration_files(const std::string& dir, const Mechanism& mechanism, const sim::Model& model,
                             const Experiment& experiment, const CalibrationResult& result,
                             const std::string& input_description);

// The files' contents, for tests and for hosts that store them elsewhere.
std::string calibration_json(const sim::Model& model, const Experiment& experiment, const CalibrationResult& result);
std::string calibration_html(const sim::Model& model, const Experiment& experiment, const CalibrationResult& result);
// Relative paths of the input (<library file>) become absolute so they still
// resolve from wherever the file is written. `result.joints[].after` is
// written as the <joint> values: the description's own joint dynamics with
// the causes added, without a drive's armature (build_model adds that).
std::string calibrated_description(const Mechanism& mechanism, const sim::Model& model,
                                   const CalibrationResult& result, const std::string& input_description);

}  // namespace mbx::calibration
