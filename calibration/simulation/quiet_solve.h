// Every Ceres solve of the calibration goes through here, so that Ceres' and
// glog's own log lines never reach a host's stderr (docs/calibration.md,
// "Messages"). Ceres logs through glog whatever the solver's logging_type:
// a residual block that evaluates to NaN (a diverging simulation window)
// prints a multi-line WARNING, and before any InitGoogleLogging() glog adds
// "Logging before InitGoogleLogging() is written to STDERR". What such a
// line means reaches the run's messages from the solver's summary instead
// (solver_note).
#pragma once
#include <string>

#include <ceres/ceres.h>

namespace mbx::calibration {

// ceres::Solve with glog held below FATAL for its duration when the host has
// not initialised glog itself (a host that has keeps its own settings and
// files). Process-wide and reference counted: concurrent solves share one
// hold, and the level the host had is put back when the last one ends.
// Within a run with a heartbeat (core/heartbeat.h) the solve beats between
// iterations and ends early on a cancel, which it then throws; cost
// functions answer a cancel with a failed evaluation.
void solve_quietly(const ceres::Solver::Options& options, ceres::Problem* problem, ceres::Solver::Summary* summary);

// What a user needs to know of a solve that did not converge, in mbx's
// words (`what` names the fit), or "" when it converged.
std::string solver_note(const ceres::Solver::Summary& summary, const std::string& what);

}  // namespace mbx::calibration
