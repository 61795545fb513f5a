// Numbers as text for the model files: shortest form that reads back to the
// same double, locale-independent, with rounding noise below 1e-14 written
// as 0 so frames that are exactly aligned in CAD read that way.
#pragma once
#include <string>

#include "core/math.h"

namespace mbx {

std::string number_text(double v);
// "x y z" (MJCF, URDF) or "{x, y, z}" (Modelica).
std::string spaced_text(const Vec3& v);
std::string modelica_vector(const Vec3& v);

}  // namespace mbx
