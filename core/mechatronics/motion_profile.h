// A joint's motion target over time (the thesis's motion editing, after
// section 2.8.2; a joint without one holds 0): tabulated points joined by
// straight lines, by rest-to-rest quintic segments (position, velocity and
// acceleration continuous; the joint stops at every point) or held as
// steps. Before the first point the first value holds, after the last the
// last.
#pragma once
#include <string>
#include <vector>

namespace mbx {

enum class Interpolation { Linear, Smooth, Step };

struct MotionPoint {
    double time = 0;   // s
    double value = 0;  // rad (revolute) or m (prismatic)
};

struct MotionSample {
    double position = 0, velocity = 0, acceleration = 0;
};

class MotionProfile {
public:
    MotionProfile() = default;  // holds 0, as an actuated joint without a motion does
    // Throws std::invalid_argument naming the point when times are not
    // strictly increasing or a number is not finite.
    MotionProfile(std::vector<MotionPoint> points, Interpolation interpolation);

    MotionSample at(double time) const;
    const std::vector<MotionPoint>& points() const { return points_; }
    Interpolation interpolation() const { return interpolation_; }

private:
    std::vector<MotionPoint> points_;
    Interpolation interpolation_ = Interpolation::Linear;
};

bool parse_interpolation(const std::string& word, Interpolation& out);  // "linear", "smooth", "step"
const char* interpolation_name(Interpolation interpolation);            // the same words

}  // namespace mbx
