#include "core/math.h"

#include <Eigen/SVD>

namespace mbx {

double orthonormality_error(const Mat3& r) {
    return (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff();
}

bool nearest_rotation(const Mat3& r, Mat3& out) {
    if (!r.allFinite() || r.determinant() <= 1e-9) return false;
    Eigen::JacobiSVD<Mat3> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
    out = svd.matrixU() * svd.matrixV().transpose();
    return out.determinant() > 0;
}

}  // namespace mbx
