// Excitation design (docs/calibration.md, "Excitation design"): periodic
// references for the actuated joints, a finite Fourier series each, that
// keep every joint inside its position, speed, acceleration and effort
// limits, start and end at rest, and along which the causes asked for are
// identifiable together. The criterion is the one the identification's
// verdict depends on: the mean log of the parameters' predicted standard
// errors in the joint inverse-dynamics fit (identify's weighted rows, the
// records' effort noise a fixed share of each joint's effort RMS), which
// rewards large, distinct columns and punishes columns alike (two causes
// whose columns correlate at r have standard errors 1/sqrt(1 - r^2) times
// those of unrelated ones).
#pragma once
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "calibration/identification/causes.h"
#include "calibration/identification/regression_rows.h"

namespace mbx::calibration {

// One actuated coordinate's limits (SI; infinite: none).
struct ExcitationLimits {
    double lower = -INFINITY, upper = INFINITY;
    double velocity = INFINITY, acceleration = INFINITY, effort = INFINITY;
};

// q(t) = q0 + sum_l a_l sin(l w t) + b_l (cos(l w t) - 1), w = 2 pi / period:
// q(0) = q0, and the speed and acceleration vanish at t = 0 and every whole
// period (sum l a_l = 0, sum l^2 b_l = 0), so a record of whole periods
// starts and ends at rest.
struct FourierReference {
    double q0 = 0;
    std::vector<double> a, b;  // harmonics 1..N
    void at(double t, double period, double& q, double& qd, double& qdd) const;
};

// The controller that will follow a joint's reference, as a servo at the
// joint: effort = stiffness (r - q) + damping (rate - q'), rate = r' when
// the damping acts on the error, 0 when it acts on the measured speed alone
// (a drive's kd and velocity loop, mechatronics' ServoEquivalent).
struct ExcitationServo {
    double stiffness = 0;  // N m/rad or N/m; 0: the joint follows its reference exactly
    double damping = 0;    // N m s/rad or N s/m
    bool damping_on_error = false;
};

struct ExcitationOptions {
    double period = 10;     // s
    int harmonics = 6;
    int periods = 2;        // the record's length in periods
    // The share of each limit (of the position range) left free, for the
    // controller's tracking error and the model's.
    double margin = 0.1;
    // Causes to make identifiable: catalogue names, each on every subject
    // the catalogue offers it, or "cause on subject" (subject as
    // subject_text writes it, e.g. "armature on joint 'elbow'") on one
    // (empty names the default set: viscous and
    // Coulomb friction, armature and effort offset on every actuated joint,
    // and every moving body's mass).
    std::vector<std::string> causes;
    // Only these subjects ("joint 'name'", "body 'name'", "the mounting"
    // as subject_text writes them; empty: all).
    std::vector<std::string> subjects;
    int samples_per_period = 200;  // the grid the limits and the criterion are evaluated on
    int evaluations = 2400;        // of the criterion, by the search
    // Independent searches the evaluations are shared among (at most one
    // per 300 evaluations): the best of several is surer than one as long.
    int searches = 4;
    unsigned seed = 1;
    // Per actuated coordinate the records' effort noise (sigma, N m or N),
    // or empty: noise_share times each joint's effort limit (times the
    // first motion's effort RMS where it has none).
    std::vector<double> effort_noise;
    double noise_share = 0.01;
    double sample_rate = 1000;     // Hz of the records, for the predicted errors (rows as identify decimates them)
    double cutoff = 0;             // Hz of the records' filter; 0: sample_rate / 40 (identify's default)
    // Per actuated coordinate the servo that follows the reference (empty:
    // each follows it exactly). The design then keeps the limits and
    // predicts the errors along the motion the servo makes of the
    // reference (each harmonic through the closed loop of the servo and the
    // joint's inertia at the start pose), as well as along the reference:
    // a servo near its bandwidth overshoots what it is asked.
    std::vector<ExcitationServo> servo;
    // Called after every evaluation with the share done; false cancels
    // (mbx::Error MBX_ERROR_CANCELLED).
    std::function<bool(double)> progress;
};

// The predicted standard errors of `candidates`' parameters along a motion,
// in the joint fit of all of them.
struct PredictedErrors {
    std::vector<std::string> names;  // "cause.parameter on subject"
    Eigen::VectorXd std_error;       // in the parameters' units; infinite: not identifiable together
    double criterion = INFINITY;     // mean log10 of std_error
};

struct ExcitationDesign {
    std::vector<int> dofs;  // actuated coordinates, the references' order
    double period = 0;
    int periods = 0;
    std::vector<FourierReference> references;
    std::vector<Candidate> causes;  // whose parameters the design makes identifiable
    PredictedErrors predicted;
    // The same along the search's first motion, a random multi-sine scaled
    // to the same limits (what a record made without a design would give).
    PredictedErrors reference;
    std::vector<double> effort_noise;  // the noise the prediction assumed, per coordinate
    // Per coordinate the inertia its servo moves (options.servo given; empty otherwise).
    std::vector<double> servo_inertia;
    // Causes of the default set left out: no motion shows them in the
    // efforts apart from the others ("cause on subject").
    std::vector<std::string> dropped;
    // Along the motion the joints will make (the references through the
    // servos, or the references themselves without): the lowest and highest
    // position, the largest speed, acceleration and effort per coordinate,
    // for the report; within the limits less the margins, as are the
    // references.
    std::vector<double> peak_velocity, peak_acceleration, peak_effort, lowest, highest;
    int evaluations = 0;
};

// The independent coordinates' motion sampled: times and per coordinate of
// `dofs` position, speed, acceleration (samples x dofs.size() each).
struct SampledMotion {
    std::vector<double> t;
    Eigen::MatrixXd q, qd, qdd;
};

// Rows of the inverse-dynamics regression along `motion` (the model's own
// efforts as the measured ones, weighted as identify weighs records).
RegressionRows motion_rows(const sim::Model& m, const std::vector<int>& dofs, const SampledMotion& motion);

PredictedErrors predict_errors(const RegressionRows& rows, const std::vector<Candidate>& causes,
                               const std::vector<double>& effort_noise, double rows_per_second, double seconds,
                               const sim::Model& m);

// `causes` less those whose columns along `rows` are zero or combinations of
// the others' (named in `dropped` as "cause on subject").
std::vector<Candidate> separable_causes(const RegressionRows& rows, const std::vector<Candidate>& causes,
                                        const sim::Model& m, std::vector<std::string>& dropped);

// The candidates the options name, one per cause and subject (its first variant).
std::vector<Candidate> excitation_causes(const sim::Model& m, const RegressionRows& rows, const ExcitationOptions& options);

// Throws mbx::Error for options or limits no design can meet (a position
// range that excludes the start, a period too short for the harmonics).
ExcitationDesign design_excitation(const sim::Model& m, const std::vector<int>& dofs,
                                   const std::vector<ExcitationLimits>& limits, const ExcitationOptions& options);

// The design's references at `rate` samples per second over its periods.
SampledMotion sample_design(const ExcitationDesign& design, double rate);

// The periodic motion a servo with the joint's inertia `inertia` makes of
// reference `r` (each harmonic through the closed loop; the mean passes
// unchanged).
FourierReference followed(const FourierReference& r, double period, const ExcitationServo& servo, double inertia);

}  // namespace mbx::calibration
