// The mounting's tilt (`<mounting tilt_x tilt_y unit>` in the description
// file, docs/mechatronics.md): a robot on a floor or table that is not level
// sees gravity turned by a few degrees in its base frame. Calibration names
// it (calibration's mounting_tilt) and the simulator, its exports' gravity
// and every replay take gravity turned by it.
#pragma once
#include <string>

#include "core/math.h"

namespace mbx {

struct MountingSpec {
    bool given = false;
    // Gravity turned about the world's x axis by tilt_x, then about its y
    // axis by tilt_y (rad): g' = Rx(tilt_x) Ry(tilt_y) g.
    double tilt_x = 0, tilt_y = 0;
    std::string file;
    int line = 0;
};

Vec3 tilted_gravity(const Vec3& gravity, const MountingSpec& mounting);

}  // namespace mbx
