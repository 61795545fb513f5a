// Joint twists and the geometry tests of one loop (conventions: mobility.h).
#pragma once
#include <vector>

#include <Eigen/Core>

#include "core/translator/mechanism.h"

namespace mbx::mobility {

using TwistColumns = Eigen::Matrix<double, 6, Eigen::Dynamic>;

// Where a loop's twists are referred to and the length its linear rows are
// divided by.
struct LoopFrame {
    Vec3 reference = Vec3::Zero();  // centroid of the loop's joint points
    double length = 1;              // their largest distance from it, floored
};

// `min_length` keeps a loop whose joints all sit at one point from dividing
// by (nearly) zero.
LoopFrame loop_frame(const Mechanism& mech, const Loop& loop, double min_length);

// One column per freedom: the twist of the joint's child w.r.t. its parent,
// angular part on top, linear part referred to frame.reference and divided
// by frame.length. A prismatic rate is taken in units of `prismatic_length`
// per second, i.e. its column is (0, axis * prismatic_length / frame.length).
TwistColumns joint_twists(const Joint& joint, const LoopFrame& frame, double prismatic_length);

// The 6 x sum(f) closure Jacobian of a traced loop, columns in loop order,
// each multiplied by the joint's loop sign. `prismatic_length[j]` is joint
// j's prismatic unit; if null, frame.length (prismatic columns (0, axis)).
Eigen::MatrixXd loop_jacobian(const Mechanism& mech, const Loop& loop, const LoopFrame& frame,
                              const std::vector<double>* prismatic_length = nullptr);

struct Planarity {
    bool planar = false;
    Vec3 normal = Vec3::Zero();
};

// Planarity as defined in mobility.h; `angle_tolerance` bounds the sine of
// the angle by which an axis may miss being parallel (or perpendicular).
Planarity loop_planarity(const Mechanism& mech, const Loop& loop, double angle_tolerance);

}  // namespace mbx::mobility
