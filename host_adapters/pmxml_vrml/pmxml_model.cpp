#include "pmxml_model.h"

namespace mbx_files {

Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& r) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
    return svd.matrixU() * svd.matrixV().transpose();
}

}  // namespace mbx_files
