// The accurate variable-step mode (IntegratorKind::Accurate) on SUNDIALS
// CVODE: BDF with error control at the user's tolerance, projection of every
// step onto the loop closures, and root finding for Coulomb friction's
// stick/slip switches; discrete controllers are sampled exactly at their
// instants. docs/simulation.md describes the design. SUNDIALS stays inside
// cvode_session.cpp: the session lives in Data::accurate_session, opaque.
#pragma once
#include <functional>
#include <vector>

#include "sim/integrator.h"

namespace mbx::sim {

// Inputs that vary in time (an external effort profile): called with the
// time before every evaluation of the derivative, to set data.effort there.
// They must be smooth in t; a jump needs a separate accurate_advance call.
using InputFunction = std::function<void(double t, Data& d)>;

struct AccurateRequest {
    double stop_time = 0;
    // Increasing times in (data.time, stop_time] at which `sample` sees the
    // state (interpolated by CVODE, then put back on the loop closures).
    std::vector<double> sample_times;
    // Or, when sample_count > 0, evenly spaced ones made as the run goes
    // (a long run holds no list): sample_start + k sample_step, k = 1..count.
    double sample_start = 0, sample_step = 0;
    long long sample_count = 0;
    std::function<void(Data& d)> sample;
    InputFunction inputs;
    // After every accepted step, with its time (progress, cancel by a
    // throw). Empty: mbx::heartbeat() is called instead.
    std::function<void(double t)> step_taken;
};

// Integrates data from data.time to request.stop_time. A run continues the
// session's history when data still holds the state the last call left
// (same time, state, efforts and settings); otherwise the friction modes are
// found again from the state: a joint with qd = 0 sticks if the effort that
// holds it is within its Coulomb limit. Throws mbx::Error
// (MBX_ERROR_SIMULATION) when CVODE fails (divergence, step size underflow,
// a loop that cannot be closed), naming the time; errors of the model
// (undetermined motion) pass through. On an error data holds the last
// accepted step.
void accurate_advance(const Model& m, Data& d, const IntegratorSettings& settings, const AccurateRequest& request);

// The friction mode of velocity coordinate `dof` in data's accurate session:
// 0 stuck, +1 or -1 slipping in that direction, 2 no Coulomb friction there
// or no session.
int friction_mode(const Data& d, int dof);

}  // namespace mbx::sim
