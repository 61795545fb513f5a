// Nonlinear refinement through the simulator (output error): a cause's
// parameters, started from the linear inverse-dynamics fit, are refined by
// Ceres to minimise the error of forward simulations over short windows,
// each from the measured state and driven by the recorded effort (the
// effort-mode replay of calibration/replay.h), against the measured
// positions. The integrator (fixed-step RK4) and the dynamics are written on
// the scalar, so Ceres' Jets carry exact derivatives through every step.
// Standard errors come from the Jacobian at the optimum, (J^T J)^-1 s^2.
//
// Besides the catalogue's linear causes it carries the ones that need it,
// each a motor-side inertia (where the drive acts and the encoder reads) as
// one more degree of freedom: `compliance`, a spring and damper to the link,
// and `backlash`, a dead band between stiff stops (docs/calibration.md).
#pragma once
#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "calibration/identification/causes.h"
#include "calibration/identification/identify.h"
#include "calibration/records/records.h"
#include "sim/model.h"

namespace mbx::calibration {

struct SimulationFitOptions {
    double horizon = 0.2;    // s per window
    int max_windows = 24;    // spread evenly over the records
    int max_iterations = 40;
    int substeps = 1;        // RK4 steps per sample period
    int threads = 2;
    // Fit each window's start (the measured coordinates' positions and
    // rates) with the parameters: a rate from a few encoder counts is off by
    // a share of the jerk, and that error would pass into the parameters.
    bool fit_start = true;
    // Hold the causes' parameters and fit the window starts only (the
    // validation error of a model as it is).
    bool hold_parameters = false;
    std::vector<int> held;  // parameters (stacked indices) held at their start
    // Windows where this coordinate's measured effort reverses, in place of
    // windows spread evenly (-1): a dead band shows only when the load
    // crosses it, so evenly spread windows spend most of their residuals on
    // stretches that say nothing about its width.
    int reversal_dof = -1;
};

// A cause and the values its parameters start from (a candidate's
// `parameters` names them, in order).
struct CauseStart {
    Candidate candidate;
    std::vector<double> values;
};

struct SimulationFit {
    std::vector<std::vector<Estimate>> parameters;  // per cause: value and standard error
    // Position error of the windows, % of the motion since each window's start.
    double initial_error = 0, final_error = 0;
    int windows = 0, residuals = 0, iterations = 0;
    double seconds = 0;
    bool converged = false;
    std::string report;  // Ceres' one-line summary
    // Why the solve did not converge, in mbx's words ("" when it did):
    // what a Ceres log line would have said, for the run's messages.
    std::string note;
};

// Whether the simulator can carry `cause` with parameters to refine.
bool simulation_supports(const std::string& cause);

// The simulation error of the windows as a function of the causes'
// parameters. Needs 1-dof joints, measured positions and efforts on the
// actuated joints (load_records); throws mbx::Error (MBX_ERROR_INVALID_INPUT)
// for a cause the simulator cannot carry, a subject it cannot hold (an
// elastic joint in a closed loop) or records too short for one window.
class SimulationProblem {
public:
    SimulationProblem(const sim::Model& m, const std::vector<const Record*>& records, const std::vector<CauseStart>& causes,
                      const SimulationFitOptions& options = {});
    ~SimulationProblem();
    int parameter_count() const;
    int residual_count() const;
    int window_count() const;
    std::vector<double> start() const;  // the causes' starting values, stacked
    // Residuals at theta (stacked over windows) and, when asked, their
    // Jacobian by automatic differentiation. False if a window diverged.
    bool evaluate(const std::vector<double>& theta, Eigen::VectorXd& residuals, Eigen::MatrixXd* jacobian = nullptr) const;
    // 100 ||r|| / ||motion since each window's start||, in the same weights.
    double error_percent(const Eigen::VectorXd& residuals) const;
    // Levenberg-Marquardt from `from` (start() if empty), physical bounds held.
    SimulationFit solve(std::vector<double> from = {}) const;

    struct Impl;  // the windows and the templated simulation (nonlinear_fit.cpp)

private:
    std::unique_ptr<Impl> impl_;
};

// After the linear selection: a transmission the rigid model lacks. Its
// signature in the inverse-dynamics fit is an armature (the motor's inertia,
// which the rigid limit leaves), so on every joint of a tree where one was
// named, `compliance` (stiffness, damping, motor inertia) replaces it in a
// simulation fit with the other named causes, from the best of a grid of
// link resonances. It is named when its stiffness is beyond `min_t_ratio`
// standard errors and the model with it cuts the simulated position error on
// the validation records by `min_relative_gain` of itself; causes the joint
// fit then finds insignificant are dropped. Without it `linear` comes back
// as it was (a cause the simulation cannot carry, a closed chain: the stage
// does not run). `considered` gets a line per joint tried.
struct TransmissionOptions {
    SimulationFitOptions fit = [] {
        SimulationFitOptions o;
        o.max_windows = 10, o.max_iterations = 25;
        return o;
    }();
    double min_t_ratio = 5;
    double min_relative_gain = 0.3;
    // transmission_stage: a backlash is tried (on every actuated joint)
    // where the linear causes leave more than this share of the validation
    // effort (%): a dead band's rigid-model residual is 20-60 % on the
    // hidden-effect cases, every other cause's 0.3-5 %.
    double dead_band_left = 10;
    // A backlash's width from 8 windows has a rough standard error (2.7-6
    // of them on the hidden-effect cases that are right), so it is named on
    // 2 of them and a larger cut of the simulated validation error.
    double backlash_t_ratio = 2, backlash_relative_gain = 0.5;
};
Identification add_transmissions(const sim::Model& m, const std::vector<const Record*>& fit,
                                 const std::vector<const Record*>& validation, const Identification& linear,
                                 const TransmissionOptions& options = {});

// One call: the problem and its solution from the causes' starting values.
SimulationFit refine_by_simulation(const sim::Model& m, const std::vector<const Record*>& records,
                                   const std::vector<CauseStart>& causes, const SimulationFitOptions& options = {});

}  // namespace mbx::calibration
