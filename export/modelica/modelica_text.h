// Small pieces of Modelica text shared by the package writers: quoted
// strings, the package identifier, and the pose tests that decide whether a
// fixed frame is needed at all.
#pragma once
#include <string>
#include <string_view>

#include "core/math.h"

namespace mbx {

// A Modelica string literal: quotes, backslashes and control characters
// escaped, so CAD names can go into description strings verbatim.
std::string modelica_string(std::string_view text);

// A Modelica quoted identifier ('name'): any CAD name becomes a component name.
inline std::string quoted_identifier(const std::string& name) { return "'" + name + "'"; }

// The package (and directory) name for a model: a sanitized identifier with a
// capital first letter, never a keyword nor a name that would hide the MSL.
std::string modelica_package_name(std::string_view model_name);

// True when `pose` moves nothing beyond rounding (1e-12 m, 1e-12 rad), so
// the writer connects the two frames directly instead of adding a part.
bool is_identity_pose(const Pose& pose);

// Cardan angles {a, b, c} with R = Rx(a) * Ry(b) * Rz(c): what MSL's
// sequence {1, 2, 3} (the Body's angles_start) means for a frame's world axes.
Vec3 cardan_angles_123(const Mat3& rotation);

}  // namespace mbx
