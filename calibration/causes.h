// The catalogue of physical causes a model may lack (docs/calibration.md):
// each names its subject (a joint or a body), the parameters it adds and,
// for the inverse-dynamics regression, the columns whose coefficients they
// are. Nonlinear settings start from a grid (Stribeck speeds, each grid value
// a candidate of its own) or from a first-order column (the delay) and are
// refined by identify() (calibration/identify.h).
#pragma once
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "calibration/regression_rows.h"

namespace mbx::calibration {

struct Candidate {
    std::string cause;   // the vocabulary name: coulomb_friction, viscous_friction, ...
    int joint = -1;      // sim joint (joint causes)
    int dof = -1;
    int q_index = -1;
    int body = -1;       // sim body (mass_error)
    std::vector<std::string> parameters;  // names of the regression coefficients
    double scale = 0;    // a fixed nonlinear setting (Stribeck velocity, the Coulomb law's smoothing speed)
    // The Stribeck law's smoothing speed of sign(q̇) (0: sign_speed's); refined with `scale`.
    double smoothing = 0;
    // Columns over `rows` (stacked as RegressionRows::y), one per parameter.
    Eigen::MatrixXd columns(const RegressionRows& rows) const;
    // Coefficients a physical effect can have (friction is dissipative, a
    // delay positive, a gain positive); false rules the candidate out.
    bool physical(const Eigen::VectorXd& theta) const;
};

// Every candidate for the actuated joints and the moving bodies of `m`.
std::vector<Candidate> catalogue(const sim::Model& m, const RegressionRows& fit);

// The smoothing speed of sign(q̇) for a coordinate: a small fraction of
// its typical speed, so that the law is a sign away from reversals.
double sign_speed(const RegressionRows& rows, int dof);

}  // namespace mbx::calibration
