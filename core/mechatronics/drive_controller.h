// The drive controller of drive.h (ControllerSpec) as a time-stepping block,
// so a simulation can close the loop with the same law, sampling, velocity
// estimate, saturation and delay as the rig, instead of the continuous servo
// equivalent the exporters use. Checked against the EMPS rig's logged
// controller output (tests/unit/test_drive_controller.cpp).
#pragma once
#include <cstddef>
#include <vector>

#include "core/mechatronics/drive.h"

namespace mbx {

// The law is drive.h's. Integrals take the error at the end of each step
// (backward Euler). Anti-windup by conditional integration: while the output
// is saturated, an integrator whose input pushes further into the saturation
// (e for ki, u_p - qdot for kvi) holds its value, so that it does not have
// to unwind, with an overshoot, once the error reverses.
class DriveController {
public:
    // Throws std::invalid_argument for a negative or non-finite gain, period,
    // delay or limit; kvi without a velocity loop; a sampled velocity
    // estimate on a continuous controller; a discrete controller's delay that
    // is not a whole number of samples (1e-9 relative) or is more than 1e7
    // samples (its ring is allocated here). output_limit 0 means no
    // saturation here: resolve_drives supplies the amplifier's bound.
    explicit DriveController(const ControllerSpec& spec);

    // The controller output reaching the amplifier at time t, for the target
    // and the joint's position and velocity at t. Calls must come in
    // non-decreasing t (else std::invalid_argument); a repeated t is allowed
    // and integrates nothing.
    //
    // Continuous (sample_period 0): the integrals advance by the time since
    // the previous call; the delayed output is interpolated linearly in the
    // history of outputs, and is 0 until `delay` after the first call.
    //
    // Discrete: a new output is computed at the first call at or after each
    // sample instant k Ts (1e-9 Ts tolerance, so calls that land on the
    // instants sample there) from the values passed then, and held until the
    // next instant; qdot is used only by VelocityEstimate::Measured. The
    // output is delayed by delay/Ts samples, 0 before the first delayed
    // sample exists. Throws std::invalid_argument if the calls step over a
    // whole sample period (the estimate and delay count consecutive samples).
    double update(double t, double target, double q, double qdot);

    // Back to the state after construction (integrals, history, samples).
    void reset();

    const ControllerSpec& spec() const { return spec_; }

private:
    // Law, integration (with anti-windup) and saturation for one evaluation;
    // dt is the integration step (0 on the first evaluation).
    double compute(double dt, double e, double qdot_est);

    ControllerSpec spec_;
    bool discrete_ = false;

    // Integrator states: of e, and of the velocity error (u_p - qdot).
    double int_e_ = 0, int_v_ = 0;

    bool started_ = false;
    double t_prev_ = 0, t_first_ = 0;

    // Discrete mode: last sample index, the position samples the estimate
    // needs, and the ring of the last delay/Ts + 1 outputs.
    long long k_prev_ = 0;
    long long samples_seen_ = 0;
    double q_prev_ = 0, qf_prev_ = 0;
    int delay_samples_ = 0;
    std::vector<double> ring_;
    double held_ = 0;

    // Continuous mode with a delay: a ring of (t, u) points. A point is kept
    // only if it is at least delay/(capacity-4) after the previous kept one,
    // so the window [t - delay, t] always fits and nothing is allocated
    // after construction, whatever the caller's step.
    struct Point {
        double t, u;
    };
    std::vector<Point> hist_;
    std::size_t head_ = 0, size_ = 0;  // oldest point, number of points
    double min_spacing_ = 0;
    void push(double t, double u);
    double delayed(double t);
};

}  // namespace mbx
