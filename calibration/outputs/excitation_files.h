// What `mbx excite` writes (docs/calibration.md, "Excitation design"), all
// in one folder and as one unit:
//   excitation.csv   the references at the records' rate: t, and per joint
//                    its position, speed and acceleration (SI)
//   experiment.xml   the experiment file of the record to be made, ready
//                    for the measured columns (docs/calibration.md)
//   excitation.json  the design: options, limits, coefficients, the
//                    predicted standard errors
//   excitation.html  the references and the predicted standard errors
//                    against those of the records the design replaces
#pragma once
#include <string>
#include <vector>

#include "calibration/excitation/excitation.h"

namespace mbx::calibration {

struct ExcitationReport {
    std::vector<ExcitationLimits> limits;  // per design dof, as the design used them
    std::vector<std::string> limit_sources;  // per design dof, in words ("CAD", "drive", "option", ...)
    ExcitationOptions options;
    std::string input;  // the model's file, for the page's title
    // The standard errors the records it replaces gave (calibration.json),
    // by PredictedErrors name ("cause.parameter on subject"); may be empty.
    std::vector<std::pair<std::string, double>> measured_std_error;
};

// The records' standard error of a parameter (PredictedErrors name), NaN
// when the report has none.
double measured_std_error(const ExcitationReport& r, const std::string& name);

// Column names of a design dof's reference in excitation.csv and of the
// measured quantities experiment.xml expects: letters, digits and '_'.
std::string excitation_column_stem(const sim::Model& m, int dof);

std::string excitation_csv(const sim::Model& m, const ExcitationDesign& d, double rate);
std::string excitation_experiment(const sim::Model& m, const ExcitationDesign& d, const ExcitationReport& r);
std::string excitation_json(const sim::Model& m, const ExcitationDesign& d, const ExcitationReport& r);
std::string excitation_html(const sim::Model& m, const ExcitationDesign& d, const ExcitationReport& r);

// Writes the four files into `dir` (created) as one unit; throws mbx::Error.
void write_excitation_files(const std::string& dir, const sim::Model& m, const ExcitationDesign& d,
                            const ExcitationReport& r);

}  // namespace mbx::calibration
