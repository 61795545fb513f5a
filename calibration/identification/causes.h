// Candidates: a cause of the table (calibration/cause_table.h) on one
// subject (a joint or a body), with the parameters it adds and, for the
// inverse-dynamics regression, the columns whose coefficients they are.
// Nonlinear settings start from a grid (Stribeck speeds, each grid value a
// candidate of its own) or from a first-order column (the delay) and are
// refined by identify() (calibration/identification/identify.h). A body's
// inertia correction (mass_error) is worked out here too.
#pragma once
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "calibration/identification/regression_rows.h"

namespace mbx::calibration {

struct CauseKind;

// A body's inertia as a mass_error corrects it, relative to the model:
// mass and inertia times mass_scale, then the centre of mass shifted (the
// inertia about it kept) and the inertia about it changed (xx yy zz xy xz yz).
struct BodyCorrection {
    double mass_scale = 1;
    Eigen::Vector3d com_shift = Eigen::Vector3d::Zero();
    Eigen::Matrix<double, 6, 1> inertia_change = Eigen::Matrix<double, 6, 1>::Zero();
    bool identity() const { return mass_scale == 1 && com_shift.isZero(0) && inertia_change.isZero(0); }
    // This correction on top of `first` (both relative to their own model).
    BodyCorrection after(const BodyCorrection& first) const;
};

// The inertia about the centre of mass (body axes): from_com's inverse.
template <class S> sim::Mat3T<S> about_com(const sim::Inertia<S>& inertia) {
    const sim::Vec3T<S> c = inertia.h / inertia.mass;
    return inertia.I - inertia.mass * (c.dot(c) * sim::Mat3T<S>::Identity() - c * c.transpose());
}

// `inertia` (the body frame's) with the correction applied. Templated so the
// simulation fit's Jets carry it.
template <class S>
sim::Inertia<S> corrected_inertia(const sim::Inertia<S>& inertia, const S& mass_scale, const S* com_shift,
                                  const S* inertia_change) {
    const S m = inertia.mass;
    const sim::Vec3T<S> c = inertia.h / m;
    sim::Mat3T<S> about_com = calibration::about_com(inertia);
    sim::Mat3T<S> change;
    change << inertia_change[0], inertia_change[3], inertia_change[4], inertia_change[3], inertia_change[1],
        inertia_change[5], inertia_change[4], inertia_change[5], inertia_change[2];
    about_com = about_com * mass_scale + change;
    const sim::Vec3T<S> shifted(c[0] + com_shift[0], c[1] + com_shift[1], c[2] + com_shift[2]);
    return sim::Inertia<S>::from_com(m * mass_scale, shifted, about_com);
}

// The largest centre-of-mass shift a mass_error may have: the body's radius
// of gyration about its centre of mass, or half the centre's distance from
// the body origin, whichever is larger.
double largest_com_shift(const sim::Inertia<double>& inertia);

struct Candidate {
    std::string cause;   // the table's name: coulomb_friction, viscous_friction, ...
    int joint = -1;      // sim joint (joint causes)
    int dof = -1;
    int q_index = -1;
    int body = -1;       // sim body (mass_error)
    // mass_error: the change of the body's inertial parameters
    // (kInertialParameters) per unit of each parameter, at the model's inertia.
    // Its parameters are mass_change (relative), com_shift_x|y|z (m, body
    // frame) or inertia_change_xx|yy|zz|xy|xz|yz (kg m^2, about the centre of
    // mass, body axes); a variant holds those the records can tell apart.
    Eigen::MatrixXd inertial_directions;
    sim::Inertia<double> body_inertia;  // mass_error: the body's, in the model
    // A centre-of-mass shift moves the inertia about the body origin by a
    // quadratic term too; its columns are the secant through this shift
    // (m, body frame), exact when the coefficients equal it (identify
    // iterates to that fixed point).
    Eigen::Vector3d com_anchor = Eigen::Vector3d::Zero();
    bool shifts_com() const;
    // sensor_offset: its column is the secant through this offset, exact to
    // second order when the coefficient equals it (identify iterates).
    double offset_anchor = 0;
    // Sets com_anchor to the shift of coefficients theta and the columns' directions with it.
    void anchor_com_shift(const Eigen::VectorXd& theta);
    std::vector<std::string> parameters;  // names of the regression coefficients
    const CauseKind& kind() const;        // its table entry (an mbx::Error if the name has none)
    double scale = 0;    // a fixed nonlinear setting (Stribeck velocity, the Coulomb law's smoothing speed)
    // The Stribeck law's smoothing speed of sign(q̇) (0: sign_speed's); refined with `scale`.
    double smoothing = 0;
    // Columns over `rows` (stacked as RegressionRows::y), one per parameter.
    Eigen::MatrixXd columns(const RegressionRows& rows) const;
    // Coefficients a physical effect can have (friction is dissipative, a
    // delay positive, a gain positive); false rules the candidate out.
    bool physical(const Eigen::VectorXd& theta) const;
    // mass_error: the body correction of coefficients theta.
    BodyCorrection body_correction(const Eigen::VectorXd& theta) const;
    // The same over any scalar: mass scale, shift (3) and change (6).
    template <class S> void body_correction(const S* theta, S& mass_scale, S* com_shift, S* inertia_change) const {
        mass_scale = S(1);
        for (int k = 0; k < 3; ++k) com_shift[k] = S(0);
        for (int k = 0; k < 6; ++k) inertia_change[k] = S(0);
        for (size_t i = 0; i < parameters.size(); ++i) {
            const std::string& p = parameters[i];
            if (p == "mass_change") mass_scale = S(1) + theta[i];
            for (int k = 0; k < 3; ++k)
                if (p == kComShiftNames[k]) com_shift[k] = theta[i];
            for (int k = 0; k < 6; ++k)
                if (p == kInertiaChangeNames[k]) inertia_change[k] = theta[i];
        }
    }
    static constexpr const char* kComShiftNames[3] = {"com_shift_x", "com_shift_y", "com_shift_z"};
    static constexpr const char* kInertiaChangeNames[6] = {"inertia_change_xx", "inertia_change_yy",
                                                           "inertia_change_zz", "inertia_change_xy",
                                                           "inertia_change_xz", "inertia_change_yz"};
};

// mass_error variants of one body: its mass (and inertia alike), a centre
// of mass shifted along each axis the records see or along all of them,
// and each inertia entry they see changed, or all of them.
std::vector<Candidate> body_candidates(const RegressionRows& fit, int body, const sim::Inertia<double>& inertia);

// "joint 'name'", "body 'name'" or "the mounting": a candidate's subject in messages.
std::string subject_text(const sim::Model& m, const Candidate& c);

// Every candidate for the actuated joints, the measured coordinates, the
// moving bodies of `m` and its mounting.
std::vector<Candidate> catalogue(const sim::Model& m, const RegressionRows& fit);

// The smoothing speed of sign(q̇) for a coordinate: a small fraction of
// its typical speed, so that the law is a sign away from reversals.
double sign_speed(const RegressionRows& rows, int dof);

}  // namespace mbx::calibration
