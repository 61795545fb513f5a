#include "core/translator/mass_properties.h"

#include <Eigen/Eigenvalues>

namespace mbx {

namespace {
Mat3 point_mass_term(double m, const Vec3& c) { return m * (c.squaredNorm() * Mat3::Identity() - c * c.transpose()); }
}  // namespace

void MassAccumulator::add(double mass, const Vec3& com, const Mat3& inertia, const Pose& part_pose) {
    const Pose rel = to_ref_ * part_pose;
    const Vec3 c = rel.apply(com);
    mass_ += mass;
    first_moment_ += mass * c;
    about_origin_ += rel.rotation * inertia * rel.rotation.transpose() + point_mass_term(mass, c);
}

MassProperties MassAccumulator::result() const {
    MassProperties out;
    out.mass = mass_;
    if (mass_ > 0) {
        out.com = first_moment_ / mass_;
        out.inertia = about_origin_ - point_mass_term(mass_, out.com);
    } else {
        out.inertia = about_origin_;
    }
    out.inertia = 0.5 * (out.inertia + out.inertia.transpose());
    return out;
}

InertiaIssue check_inertia(const Mat3& inertia, Vec3& principal, double relative_tolerance) {
    Eigen::SelfAdjointEigenSolver<Mat3> solver(0.5 * (inertia + inertia.transpose()), Eigen::EigenvaluesOnly);
    principal = solver.eigenvalues();  // ascending
    const double scale = principal.cwiseAbs().maxCoeff();
    if (scale <= 0) return InertiaIssue::semi_definite;
    const double tol = relative_tolerance * scale;
    if (principal[0] < -tol) return InertiaIssue::not_positive_definite;
    if (principal[0] <= tol * 1e-3) return InertiaIssue::semi_definite;
    if (principal[0] + principal[1] < principal[2] - tol) return InertiaIssue::triangle_inequality;
    return InertiaIssue::none;
}

}  // namespace mbx
