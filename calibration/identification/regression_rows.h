// The rows of the inverse-dynamics regression: along the measured motion
// (filtered, differentiated, decimated) the model's inverse dynamics
// predicts each actuated joint's effort; the measured effort minus that is
// what the causes (calibration/causes.h) must explain.
#pragma once
#include <cmath>
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "calibration/records/records.h"

namespace mbx::calibration {

// A body's inertial parameters at its frame's origin, in this order: mass,
// first moment m c (3), inertia about the origin (xx yy zz xy xz yz).
constexpr int kInertialParameters = 10;
Eigen::Matrix<double, kInertialParameters, 1> inertial_parameters(const sim::Inertia<double>& inertia);
sim::Inertia<double> inertia_of_parameters(const Eigen::Matrix<double, kInertialParameters, 1>& p);

// The regression data of one set of records (fit or validation): rows are
// (decimated sample, actuated joint) pairs.
struct RegressionRows {
    std::vector<int> actuated;  // velocity coordinates with a measured effort
    std::vector<double> weight; // per actuated coordinate: 1 / RMS of its fit-record effort
    int samples = 0;
    // Per sample and coordinate (samples x nv), filtered and differentiated.
    Eigen::MatrixXd q, qd, qdd;
    // Per sample and actuated coordinate (samples x actuated).
    Eigen::MatrixXd effort, effort_rate, model_effort;
    // d model_effort / d q_j and d^2 model_effort / d q_j^2, per coordinate
    // j: (samples x actuated) each.
    std::vector<Eigen::MatrixXd> effort_by_position, effort_by_position2;
    // Per body, the actuated efforts' derivative with respect to the body's
    // ten inertial parameters (inverse dynamics is linear in them, gravity
    // included): (samples * actuated) x 10, rows sample-major as y(), columns
    // kInertialParameters. Times the body's own parameters it is the body's
    // share of the effort; times their change, what a mass, centre-of-mass or
    // inertia error changes.
    std::vector<Eigen::MatrixXd> inertial_regressor;
    // The model's gravity, and per world axis k the actuated efforts that
    // hold the bodies still at each row's position under a unit gravity
    // along e_k ((samples x actuated) each): inverse dynamics is linear in
    // gravity, so a gravity turned by a small angle about axis a changes
    // the effort by the angle times the sum over k of (a x gravity)_k times these.
    Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
    std::vector<Eigen::MatrixXd> effort_by_gravity;
    // The filtered signals between the rows, per record: columns that are
    // nonlinear in the motion are evaluated at the full rate and filtered
    // like the effort (a friction law's step at a reversal reaches the
    // filtered effort smoothed), and an exact delay reads the effort between
    // samples. Per record: full-rate effort (samples x actuated) and speeds
    // (samples x nv, measured coordinates; zero for a loop's others), its
    // sample period and filter cutoff; per row: its record and sample.
    std::vector<Eigen::MatrixXd> record_effort, record_velocity;
    std::vector<double> record_period, record_cutoff;
    std::vector<int> row_record, row_sample;
    Eigen::VectorXd y() const;        // weighted residual, stacked sample-major
    Eigen::VectorXd measured() const; // weighted measured effort, same order
};

// The records' own effort noise in the rows' measure (docs/calibration.md,
// "Noise floor"): what a model that explained everything else would still
// leave, as % of the weighted measured effort, like the errors; from each
// record's white effort noise (records/noise.h) after its low-pass, on
// `rows` built from `records`. NaN when no record holds an effort.
// The measured positions' own noise (an encoder's counts) adds what the
// model's mass matrix makes of it, differentiated twice and filtered (for a
// model whose coordinates are all hinges and slides; in a closed chain the
// mass matrix of the motions the loops allow, G^T M G on the independent
// coordinates).
double noise_floor(const sim::Model& m, const RegressionRows& rows, const std::vector<const Record*>& records);

struct IdentifyOptions {
    double cutoff = 0;         // Hz; 0: each record's filter_cutoff()
    double min_t_ratio = 5;    // a cause's parameters must exceed this many standard errors
    // and cut the validation error by this fraction of itself (a tenth: a
    // cause worth naming removes a visible part of what is left)
    double min_relative_gain = 0.1;
    double bic_margin = 10;    // and lower the validation BIC by this much (strong evidence)
    int max_causes = 6;
    // Two causes whose columns (beyond those named) correlate above this
    // cannot be told apart by the data: neither is named (a warning says so);
    // above the second they are one parameter, named once.
    double max_rival_correlation = 0.99;
    double same_column_correlation = 0.999;
    // A cause named over another whose column (beyond those named) still
    // correlates above this, and whose validation error is within this
    // factor of the named one's, gets a warning that the records hardly
    // tell the two apart. Near the noise floor (the named one's error within
    // twice it) the difference is weighed against the noise instead: the
    // other leaving at least this share of the noise's variance more on
    // validation is told apart (near the noise a ratio of errors says
    // little: 0.98 % against 1.15 % over a floor of 0.75 % is a clear call).
    double ambiguous_correlation = 0.99;
    double ambiguous_error_ratio = 1.5;
    double ambiguous_noise_share = 0.25;
    // The validation records' noise floor (noise_floor(), % of the weighted
    // effort; NaN: not measured): the selection stops once the error left is
    // no more than it.
    double noise_level = NAN;
};

// Whether an inverse-dynamics error (%) is the noise floor's (%): within a
// quarter above it, the scatter of the floor's own estimate and of the
// error's over a few thousand filtered rows. False when the floor is not
// measured.
inline bool explained_to_noise(double error, double noise_level) {
    return std::isfinite(noise_level) && noise_level > 0 && error <= 1.25 * noise_level;
}

// The rows' motion before the model sees it, a column per row: the
// independent coordinates' positions (in a full q, the others a start),
// speeds and accelerations, and the measured efforts and their rates per
// actuated coordinate. (Columns of a few matrices rather than a vector each:
// a million rows of small vectors took 600 MB and a 100 ms pause to free.)
struct RowSamples {
    Eigen::MatrixXd q, qd, qdd, effort, rate;
    std::vector<char> first;  // of its record: the loops are closed from the assembly pose
    // Room for `rows` rows, left unset: each is set by start_row and the
    // caller (a long record's rows are touched as they are made).
    RowSamples(Eigen::Index nq, Eigen::Index nv, Eigen::Index actuated, Eigen::Index rows)
        : q(nq, rows), qd(nv, rows), qdd(nv, rows), effort(actuated, rows), rate(actuated, rows), first(size_t(rows), 0) {}
    Eigen::Index size() const { return q.cols(); }
    // Row `at` at the reference pose, at rest, no effort.
    void start_row(Eigen::Index at, const Eigen::VectorXd& q_reference, bool first_of_record) {
        q.col(at) = q_reference, qd.col(at).setZero(), qdd.col(at).setZero();
        effort.col(at).setZero(), rate.col(at).setZero();
        first[size_t(at)] = first_of_record;
    }
};

struct ClosedChain;

// The parts of the rows beyond the model's efforts, each costing passes of
// inverse dynamics per sample (a cause's kind says which its columns read:
// CauseKind::row_parts); a part left out stays empty.
enum RowPart : unsigned {
    kPositionSensitivity = 1,  // effort_by_position(2): two passes per measured coordinate
    kGravityShares = 2,        // effort_by_gravity: three passes
    kInertialRegressor = 4,    // inertial_regressor: one pass and each body's depth
    kAllRowParts = 7,
};

// The rows at `samples` (rows.actuated set): the loops closed, the model's
// efforts and the `parts` asked for; rows.weight is left as it is.
void fill_rows(const sim::Model& m, ClosedChain& chain, const RowSamples& samples, RegressionRows& rows,
               unsigned parts = kAllRowParts);

// Per actuated coordinate 1 / RMS of rows.effort: each joint weighs by its
// own effort level, so a joint in N and one in N m count alike.
std::vector<double> effort_weights(const RegressionRows& rows);

// Rows from records. Trees: the position of every coordinate must be
// measured. Closed chains: exactly the loops' independent coordinates
// (every actuated one among them); the others are solved from the
// closures, and the efforts are the tree's inverse dynamics projected onto
// the independent coordinates (docs/calibration.md). Throws mbx::Error.
RegressionRows regression_rows(const sim::Model& m, const std::vector<const Record*>& records,
                               const IdentifyOptions& options, const std::vector<double>* weights = nullptr);

}  // namespace mbx::calibration

