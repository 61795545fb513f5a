// Small geometric vocabulary shared by every module: Eigen inside, plain
// arrays only at the C boundary (see capi/).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mbx {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Rigid transform; `rotation` columns are the frame's axes in the parent.
struct Pose {
    Mat3 rotation = Mat3::Identity();
    Vec3 position = Vec3::Zero();

    Vec3 apply(const Vec3& p) const { return rotation * p + position; }
    Pose operator*(const Pose& o) const { return {rotation * o.rotation, rotation * o.position + position}; }
    Pose inverse() const {
        Mat3 rt = rotation.transpose();
        return {rt, -(rt * position)};
    }
};

// Largest entry of |R^T R - I|: how far a host matrix is from a rotation.
double orthonormality_error(const Mat3& r);
// A 3x3 matrix from nine numbers row by row (the C API's rotation and inertia layout).
inline Mat3 from_row_major(const double* r) {
    Mat3 m;
    m << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
    return m;
}

// Nearest proper rotation (polar decomposition through SVD). Returns false if
// `r` is singular or a reflection (det <= 0), which no re-orthonormalization
// can honestly repair.
bool nearest_rotation(const Mat3& r, Mat3& out);

}  // namespace mbx
