// Mass properties of rigid bodies: compounding parts welded together and
// checking that a tensor can belong to a real body.
#pragma once
#include "core/math.h"

namespace mbx {

struct MassProperties {
    double mass = 0;
    Vec3 com = Vec3::Zero();      // in the reference frame
    Mat3 inertia = Mat3::Zero();  // about com, reference axes
};

// Accumulates parts given in their own frames into one body whose frame is
// `reference` (world pose). Parallel-axis theorem about the compound centre
// of mass, tensors rotated into the reference axes.
class MassAccumulator {
public:
    explicit MassAccumulator(const Pose& reference) : to_ref_(reference.inverse()) {}
    void add(double mass, const Vec3& com, const Mat3& inertia, const Pose& part_pose);
    MassProperties result() const;

private:
    Pose to_ref_;
    double mass_ = 0;
    Vec3 first_moment_ = Vec3::Zero();
    // Second moment about the reference origin, sum(I_rot + m (|c|^2 E - c c^T)).
    Mat3 about_origin_ = Mat3::Zero();
};

enum class InertiaIssue { none, semi_definite, not_positive_definite, triangle_inequality };

// Principal moments (ascending) and what is wrong with them, with a relative
// tolerance that absorbs the 6-significant-digit rounding of CAD exports.
InertiaIssue check_inertia(const Mat3& inertia, Vec3& principal, double relative_tolerance = 1e-5);

}  // namespace mbx
