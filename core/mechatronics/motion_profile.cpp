#include "core/mechatronics/motion_profile.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mbx {

MotionProfile::MotionProfile(std::vector<MotionPoint> points, Interpolation interpolation)
    : points_(std::move(points)), interpolation_(interpolation) {
    for (size_t i = 0; i < points_.size(); ++i) {
        const MotionPoint& p = points_[i];
        if (!std::isfinite(p.time) || !std::isfinite(p.value))
            throw std::invalid_argument("motion point " + std::to_string(i + 1) + " is not a finite number");
        if (i > 0 && !(p.time > points_[i - 1].time))
            throw std::invalid_argument("motion point " + std::to_string(i + 1) +
                                        ": times must increase strictly");
    }
}

MotionSample MotionProfile::at(double t) const {
    MotionSample s;
    if (points_.empty()) return s;
    if (t <= points_.front().time) {
        s.position = points_.front().value;
        return s;
    }
    if (t >= points_.back().time) {
        s.position = points_.back().value;
        return s;
    }
    // Segment [k, k+1] holding t (binary search: long programs stay cheap per step).
    const auto next = std::upper_bound(points_.begin(), points_.end(), t,
                                       [](double time, const MotionPoint& p) { return time < p.time; });
    const MotionPoint& b = *next;
    const MotionPoint& a = *(next - 1);
    const double duration = b.time - a.time;
    const double u = (t - a.time) / duration;
    const double dq = b.value - a.value;
    switch (interpolation_) {
    case Interpolation::Step: s.position = a.value; break;
    case Interpolation::Linear:
        s.position = a.value + dq * u;
        s.velocity = dq / duration;
        break;
    case Interpolation::Smooth: {
        // 10u^3 - 15u^4 + 6u^5: zero velocity and acceleration at both ends.
        const double u2 = u * u, u3 = u2 * u;
        s.position = a.value + dq * u3 * (10 - 15 * u + 6 * u2);
        s.velocity = dq / duration * 30 * u2 * (1 - 2 * u + u2);
        s.acceleration = dq / (duration * duration) * 60 * u * (1 - 3 * u + 2 * u2);
        break;
    }
    }
    return s;
}

bool parse_interpolation(const std::string& word, Interpolation& out) {
    if (word == "linear") out = Interpolation::Linear;
    else if (word == "smooth") out = Interpolation::Smooth;
    else if (word == "step") out = Interpolation::Step;
    else return false;
    return true;
}

const char* interpolation_name(Interpolation interpolation) {
    switch (interpolation) {
    case Interpolation::Smooth: return "smooth";
    case Interpolation::Step: return "step";
    case Interpolation::Linear: break;
    }
    return "linear";
}

}  // namespace mbx
