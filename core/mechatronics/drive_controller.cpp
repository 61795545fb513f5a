#include "core/mechatronics/drive_controller.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace mbx {

namespace {

// Enough points that a variable-step caller keeps a fine history of the
// delay window (delay/4092 apart at worst), small enough to allocate once.
constexpr std::size_t kHistoryCapacity = 4096;
// Longest discrete delay, in samples: the ring is allocated up front.
constexpr double kMaxDelaySamples = 1e7;

std::string num(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

void check(bool ok, const std::string& why) {
    if (!ok) throw std::invalid_argument("DriveController: " + why);
}

}  // namespace

DriveController::DriveController(const ControllerSpec& spec) : spec_(spec) {
    for (const auto& [name, value] : controller_values(spec)) {
        check(std::isfinite(value), std::string(name) + " must be finite");
        check(value >= 0, std::string(name) + " must not be negative (got " + num(value) + ")");
    }
    // Without a velocity loop the law has no place for kvi; accepting it
    // would silently drop integral action the user asked for.
    check(spec.kvi == 0 || spec.kv > 0, "kvi needs a velocity loop (kv > 0)");
    discrete_ = spec.sample_period > 0;
    if (!discrete_) {
        check(spec.velocity_estimate == VelocityEstimate::Measured,
              "a continuous controller measures the velocity; a sampled velocity estimate needs a sample_period");
        if (spec.delay > 0) {
            hist_.resize(kHistoryCapacity);
            min_spacing_ = spec.delay / static_cast<double>(kHistoryCapacity - 4);
        }
    } else {
        const double samples = spec.delay / spec.sample_period;
        check(delay_in_whole_samples(spec),
              "a discrete controller's delay must be a whole number of sample periods (delay " +
                  num(spec.delay) + " s, sample_period " + num(spec.sample_period) + " s)");
        check(samples <= kMaxDelaySamples, "delay of more than 1e7 samples");
        delay_samples_ = static_cast<int>(std::round(samples));
        ring_.assign(static_cast<std::size_t>(delay_samples_) + 1, 0.0);
    }
}

void DriveController::reset() {
    int_e_ = int_v_ = 0;
    started_ = false;
    t_prev_ = t_first_ = 0;
    k_prev_ = 0;
    samples_seen_ = 0;
    q_prev_ = qf_prev_ = 0;
    held_ = 0;
    std::fill(ring_.begin(), ring_.end(), 0.0);
    head_ = size_ = 0;
}

double DriveController::compute(double dt, double e, double qdot_est) {
    const ControllerSpec& c = spec_;
    const bool velocity_loop = c.kv > 0;
    double ie = int_e_ + e * dt;
    double up = c.kp * e + c.ki * ie - c.kd * qdot_est;
    double ev = up - qdot_est;
    double iv = int_v_ + ev * dt;
    double u = velocity_loop ? c.kv * ev + c.kvi * iv : up;

    // Anti-windup by conditional integration: while the output is saturated,
    // an integrator whose input pushes further into the saturation keeps its
    // value, so it does not wind up and overshoot once the error reverses;
    // an input that pulls out of saturation still integrates.
    if (c.output_limit > 0 && std::fabs(u) > c.output_limit) {
        const double dir = u > 0 ? 1.0 : -1.0;
        if (e * dir > 0) ie = int_e_;
        up = c.kp * e + c.ki * ie - c.kd * qdot_est;
        ev = up - qdot_est;
        iv = ev * dir > 0 ? int_v_ : int_v_ + ev * dt;
        u = velocity_loop ? c.kv * ev + c.kvi * iv : up;
    }
    int_e_ = ie;
    int_v_ = iv;
    if (c.output_limit > 0) u = std::fmax(-c.output_limit, std::fmin(c.output_limit, u));
    return u;
}

double DriveController::update(double t, double target, double q, double qdot) {
    if (started_ && t < t_prev_)
        throw std::invalid_argument("DriveController: time went back from " + num(t_prev_) + " s to " + num(t) + " s");
    const double e = target - q;

    if (!discrete_) {
        const double dt = started_ ? t - t_prev_ : 0.0;
        if (!started_) t_first_ = t;
        started_ = true;
        t_prev_ = t;
        const double u = compute(dt, e, qdot);
        if (spec_.delay == 0) return u;
        push(t, u);
        return delayed(t);
    }

    const double Ts = spec_.sample_period;
    const auto k = static_cast<long long>(std::floor(t / Ts + 1e-9));
    if (started_ && k == k_prev_) {
        t_prev_ = t;
        return held_;
    }
    if (started_ && k > k_prev_ + 1)
        throw std::invalid_argument("DriveController: update skipped sample " + std::to_string(k_prev_ + 1) +
                                    " (call it at least once per sample period)");
    started_ = true;
    t_prev_ = t;
    k_prev_ = k;

    // The estimate starts from the samples it has: zero velocity on the
    // first one, and the filter takes the first position as its own past.
    double v = qdot;
    if (spec_.velocity_estimate == VelocityEstimate::Difference) {
        v = samples_seen_ > 0 ? (q - q_prev_) / Ts : 0.0;
    } else if (spec_.velocity_estimate == VelocityEstimate::FilteredDifference) {
        const double qf = samples_seen_ > 0 ? 0.5 * q + 0.5 * q_prev_ : q;
        v = samples_seen_ > 0 ? (qf - qf_prev_) / Ts : 0.0;
        qf_prev_ = qf;
    }
    q_prev_ = q;

    const double u = compute(samples_seen_ > 0 ? Ts : 0.0, e, v);
    const auto slots = static_cast<long long>(ring_.size());
    ring_[static_cast<std::size_t>(samples_seen_ % slots)] = u;
    held_ = samples_seen_ >= delay_samples_ ? ring_[static_cast<std::size_t>((samples_seen_ - delay_samples_) % slots)]
                                            : 0.0;
    ++samples_seen_;
    return held_;
}

void DriveController::push(double t, double u) {
    if (size_ > 0) {
        const Point& last = hist_[(head_ + size_ - 1) % hist_.size()];
        if (t - last.t < min_spacing_) return;
    }
    if (size_ == hist_.size()) {  // cannot happen with the spacing rule; never overwrite the newest
        head_ = (head_ + 1) % hist_.size();
        --size_;
    }
    hist_[(head_ + size_) % hist_.size()] = {t, u};
    ++size_;
}

double DriveController::delayed(double t) {
    const double td = t - spec_.delay;
    // A small tolerance so that t = t_first + delay, reached by summing
    // steps, gives the first output rather than 0.
    if (td < t_first_ - 1e-9 * spec_.delay) return 0.0;
    // The query time only moves forward: drop points no longer needed.
    const std::size_t cap = hist_.size();
    while (size_ >= 2 && hist_[(head_ + 1) % cap].t <= td) {
        head_ = (head_ + 1) % cap;
        --size_;
    }
    const Point& a = hist_[head_];
    if (size_ == 1 || td <= a.t) return a.u;
    const Point& b = hist_[(head_ + 1) % cap];
    return a.u + (b.u - a.u) * (td - a.t) / (b.t - a.t);
}

}  // namespace mbx
