// Blocks written into the Modelica package for the drives, where MSL 4.0 has
// no block that reproduces mbx's drive law exactly (see mechatronic_writer.h).
#pragma once
#include <string>

namespace mbx {

// Class names below the package (files <package>/<name>.mo).
extern const char* const kDiscreteControllerBlock;  // "DiscreteDriveController"
extern const char* const kSmoothTargetBlock;        // "SmoothTarget"

// <package>.DiscreteDriveController: the sampled controller of
// sdk/src/mechatronics/drive.h (position loop, optional velocity loop,
// velocity measured or estimated from sampled positions, saturation and a
// whole-sample delay), as a `when sample(0, Ts)` algorithm. Inputs q_ref, q,
// qd; output y (held between samples).
std::string discrete_controller_block(const std::string& package);

// <package>.SmoothTarget: mbx's "smooth" motion (MotionProfile,
// Interpolation::Smooth): rest-to-rest quintic segments 10u^3 - 15u^4 + 6u^5
// between the points of `table` ({time, value} rows), the first value before
// the first point and the last after the last. Output y.
std::string smooth_target_block(const std::string& package);

}  // namespace mbx
