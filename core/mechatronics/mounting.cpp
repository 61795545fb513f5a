#include "core/mechatronics/mounting.h"

#include <Eigen/Geometry>

namespace mbx {

Vec3 tilted_gravity(const Vec3& gravity, const MountingSpec& mounting) {
    if (!mounting.given) return gravity;
    return Eigen::AngleAxisd(mounting.tilt_x, Vec3::UnitX()) * (Eigen::AngleAxisd(mounting.tilt_y, Vec3::UnitY()) * gravity);
}

}  // namespace mbx
