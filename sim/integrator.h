// Time integration of a model's state: fixed-step semi-implicit Euler and
// RK4 (real-time use; MuJoCo's schemes, so results compare step for step)
// and the accurate variable-step mode on SUNDIALS CVODE (sim/cvode_session.h).
// After every step the loops are closed again (positions, then velocities).
#pragma once
#include <memory>
#include <string>

#include "sim/drive_loop.h"
#include "sim/forward_dynamics.h"
#include "sim/joint_forces.h"

namespace mbx::sim {

enum class IntegratorKind { Euler, RK4, Accurate };
const char* integrator_name(IntegratorKind k);       // "euler", "rk4", "accurate"
bool parse_integrator(const std::string& word, IntegratorKind& out);

struct IntegratorSettings {
    IntegratorKind kind = IntegratorKind::RK4;
    double step = 1e-3;        // s: the fixed step; the accurate mode's largest step (0: no bound)
    double tolerance = 1e-8;   // accurate mode: relative tolerance (absolute: this times the state's scale)
    // Loop closure after each step, in metres (radians for angular rows).
    double closure_tolerance = 1e-11;
};

// Derivative of the state at (data.q, data.v, data.time): passive joint
// forces, drive efforts from the held controller outputs, external efforts,
// then forward dynamics into data.qacc. `step`: the fixed step the
// regularised friction must stay stable at (0: none).
void evaluate(const Model& m, Data& d, FrictionLaw law, const std::vector<char>* stuck = nullptr, double step = 0,
              bool positions_ready = false);

// data.applied_forces' efforts at the current state into qfrc_applied,
// added to qfrc_total (the kinematics brought up to date first).
void add_applied_forces(const Model& m, Data& d);

// One fixed step of `settings.step` with Euler or RK4, controllers sampled
// at its start, loops closed at its end. Throws mbx::Error for a state that
// becomes non-finite (naming the joint) or loops that no longer close.
void fixed_step(const Model& m, Data& d, const IntegratorSettings& settings);

// Closes the loops at data.q and data.v (minimum-norm changes); throws
// mbx::Error naming the loop if the positions cannot be brought back.
// Returns the largest closure residual left (m or rad). `warm` after a
// step: the chord steps start from the factor of the step's last dynamics
// evaluation (positions one step back, close enough to converge); the
// velocities need the exact rows, whose factor the next step's first
// evaluation then reuses, so a step costs one factorisation, not two.
// `moved`, when given, gets the positions' correction added to it.
double close_loops(const Model& m, Data& d, double tolerance, bool warm = false, Eigen::VectorXd* moved = nullptr);

// Throws mbx::Error(status) naming the first joint with a non-finite coordinate.
void check_finite_state(const Model& m, const Data& d, const char* when, mbx_status status = MBX_ERROR_INVALID_INPUT);

// Advances data to time t_end with the integrator of `settings`: whole
// fixed steps, then a shorter one that lands on t_end. On an error the
// state is the last good one.
void advance(const Model& m, Data& d, const IntegratorSettings& settings, double t_end);

}  // namespace mbx::sim
