#include "calibration/identification/identify.h"

#include <cmath>
#include <map>
#include <sstream>

#include "calibration/cause_table.h"
#include "calibration/identification/tall_qr.h"
#include "core/finding.h"
#include "core/heartbeat.h"

namespace mbx::calibration {

namespace {

struct Fit {
    Eigen::VectorXd theta;
    Eigen::MatrixXd covariance;
    Eigen::MatrixXd R;  // of the regressors [X xk], by tall_r
    double sse_fit = 0, sse_validation = 0;
    bool ok = false;
};

// The residual in the recorded effort's units. An actuator gain g = 1 - d
// (its column the recorded effort on its joint's rows, `gain` marking it)
// says the joint needs g times what was recorded, so there the linear
// residual g E - tau is g times E - tau / g, what the model misses of the
// recorded effort. Every cause's residual is compared in those units: taken
// as it comes, a gain shrinks the residual's scale with itself, and where
// the measured motion's own noise dominates (an encoder's counts twice
// differentiated, through the inertia) it beats the cause that is there (the
// four-bar's coupler mass, docs/calibration.md).
void to_recorded_units(Eigen::VectorXd& r, const Eigen::MatrixXd& X, const Eigen::VectorXd& theta,
                       const std::vector<char>& gain) {
    for (Eigen::Index j = 0; j < X.cols() && size_t(j) < gain.size(); ++j) {
        const double g = 1 - theta[j];
        if (!gain[size_t(j)] || !(g > 0)) continue;
        for (Eigen::Index i = 0; i < r.size(); ++i)
            if (X(i, j) != 0) r[i] /= g;
    }
}

using Part = Eigen::Ref<const Eigen::MatrixXd>;

// Least squares of y on [X xk] (the causes named so far and a candidate's
// columns; column-pivoted QR of their R, computed by blocks of rows:
// collinear columns give a rank-deficient fit, which is reported as not
// ok); the errors' sums of squares in the recorded effort's units (`gain`:
// the actuator-gain columns among [X xk]).
// The covariance takes each joint's residual variance from its own rows
// (rows stacked sample-major, `joints` per sample): (X^T X)^-1 (sum_a
// sigma_a^2 X_a^T X_a) (X^T X)^-1. The rows are weighted by each joint's
// effort RMS, not its noise, so the joints' weighted noise differs as soon
// as a record moves one joint harder than another; one pooled variance then
// lends a quiet joint's parameters the noise of a loud one (an elbow's
// armature along a motion that drives the shoulder hard came out 1.3x too
// uncertain, the shoulder's damping as much too sure). With equal
// variances this is sigma^2 (X^T X)^-1.
Fit least_squares(Part X, Part xk, const Eigen::VectorXd& y, Part Xv, Part xvk, const Eigen::VectorXd& yv,
                  Eigen::Index joints, const std::vector<char>& gain = {}) {
    Fit f;
    const Eigen::Index p = X.cols() + xk.cols(), n = y.size();
    if (p == 0) {
        f.theta.resize(0);
        f.sse_fit = y.squaredNorm(), f.sse_validation = yv.squaredNorm(), f.ok = true;
        return f;
    }
    const Eigen::MatrixXd Ry = tall_r({X, xk, y});
    f.R = Ry.topLeftCorner(p, p);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(f.R);
    qr.setThreshold(1e-10);
    if (qr.rank() < p) return f;
    f.theta = qr.solve(Eigen::VectorXd(Ry.col(p).head(p)));
    const Eigen::Index A = std::max<Eigen::Index>(1, joints);
    const bool per_joint = A > 1 && n % A == 0;
    const Eigen::Index block = tall_block_rows(A);
    std::vector<Eigen::MatrixXd> gram(per_joint ? size_t(A) : 0, Eigen::MatrixXd::Zero(p, p));
    Eigen::VectorXd joint_sse = Eigen::VectorXd::Zero(A);
    Eigen::MatrixXd B;
    Eigen::VectorXd r;
    // The residual of rows [from, from + rows) of (Xp, yp) in recorded units,
    // its linear sum of squares per joint added to `joint_sse`.
    auto residual = [&](Part Xp, Part xp, const Eigen::VectorXd& yp, Eigen::Index from, Eigen::Index rows, bool fit_rows) {
        B.resize(rows, p);
        B.leftCols(X.cols()) = Xp.middleRows(from, rows), B.rightCols(xk.cols()) = xp.middleRows(from, rows);
        r = yp.segment(from, rows) - B * f.theta;
        if (fit_rows)
            for (Eigen::Index i = 0; i < rows; ++i) joint_sse[(from + i) % A] += r[i] * r[i];
        to_recorded_units(r, B, f.theta, gain);
        return r.squaredNorm();
    };
    for (Eigen::Index from = 0; from < n; from += block) {
        heartbeat();
        const Eigen::Index rows = std::min(block, n - from);
        f.sse_fit += residual(X, xk, y, from, rows, true);
        using Rows = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>>;
        for (size_t a = 0; a < gram.size(); ++a) {
            const Rows Ba(B.data() + a, rows / A, p, Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>(rows, A));
            gram[a].noalias() += Ba.transpose() * Ba;
        }
    }
    for (Eigen::Index from = 0; from < yv.size(); from += block) {
        heartbeat();
        f.sse_validation += residual(Xv, xvk, yv, from, std::min(block, yv.size() - from), false);
    }
    // (X^T X)^-1 = R^-1 R^-T: X^T X itself would square the condition number.
    const Eigen::MatrixXd R_inverse = f.R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
    const Eigen::MatrixXd inverse = R_inverse * R_inverse.transpose();
    // Each joint's rows keep their share of the degrees of freedom.
    const double keep = std::max(1.0, double(n - p)) / double(n);
    Eigen::MatrixXd spread = Eigen::MatrixXd::Zero(p, p);
    if (!per_joint) {
        spread = (joint_sse.sum() / (keep * double(n))) * (f.R.transpose() * f.R);
    } else {
        const double samples = double(n / A);
        for (size_t a = 0; a < gram.size(); ++a) spread.noalias() += (joint_sse[Eigen::Index(a)] / (keep * samples)) * gram[a];
    }
    f.covariance = inverse * spread * inverse;
    f.ok = f.theta.allFinite();
    return f;
}

// Whether a candidate's columns (the last of a fit's R, after `named`) add
// nothing the named causes' columns do not already span, to the
// same-column correlation: the smallest singular value of an orthonormal
// basis of them, less what the named columns explain, below `least_new`.
// From R alone: with [X xk] = Q R, that part of the basis xk Rk^-1 is
// Q2 R22 Rk^-1, where Rk^T Rk = xk^T xk = R12^T R12 + R22^T R22.
bool spanned(const Eigen::MatrixXd& R, Eigen::Index named, double least_new) {
    const Eigen::Index c = R.cols() - named;
    if (named == 0 || c == 0) return false;
    const Eigen::HouseholderQR<Eigen::MatrixXd> own(R.rightCols(c));
    const Eigen::MatrixXd Rk = own.matrixQR().topRows(c).triangularView<Eigen::Upper>();
    const Eigen::MatrixXd R22 = R.bottomRightCorner(c, c).triangularView<Eigen::Upper>();
    const Eigen::MatrixXd basis_left = Rk.transpose().triangularView<Eigen::Lower>().solve(R22.transpose()).transpose();
    return Eigen::JacobiSVD<Eigen::MatrixXd>(basis_left).singularValues().minCoeff() < least_new;
}

// |cos| of the angle between what X's columns leave of a and of b (0 where
// they leave nothing of one): from R of [X a b], what is left of a is
// q_a r_aa, of b q_a r_ab + q_b r_bb.
double unexplained_correlation(Part X, Part a, Part b) {
    const Eigen::MatrixXd R = tall_r({X, a, b});
    const Eigen::Index p = X.cols();
    const double raa = R(p, p), rab = R(p, p + 1), rbb = R(p + 1, p + 1);
    const double left_b = std::hypot(rab, rbb);
    return raa != 0 && left_b > 0 ? std::abs(rab) / left_b : 0;
}

double percent(double sse, const Eigen::VectorXd& measured) {
    const double n = measured.squaredNorm();
    return n > 0 ? 100 * std::sqrt(sse / n) : 0;
}

double bic(double sse, Eigen::Index n, Eigen::Index k) {
    return double(n) * std::log(std::max(sse, 1e-300) / double(n)) + double(k) * std::log(double(n));
}

// Takes what cause `c` explains at its values out of residual `left` of `rows`.
void remove_cause(const SelectedCause& c, const RegressionRows& rows, Eigen::VectorXd& left) {
    const Eigen::MatrixXd cols = c.candidate.columns(rows);
    for (Eigen::Index p = 0; p < cols.cols() && p < Eigen::Index(c.parameters.size()); ++p)
        left -= c.parameters[size_t(p)].value * cols.col(p);
}

double correlation(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    const double na = a.norm(), nb = b.norm();
    return na > 0 && nb > 0 ? a.dot(b) / (na * nb) : 0;
}

}  // namespace

Identification identify(const sim::Model& m, const RegressionRows& fit, const RegressionRows& validation,
                        const IdentifyOptions& options) {
    Identification out;
    const Eigen::VectorXd y = fit.y(), yv = validation.y();
    const Eigen::Index joints = Eigen::Index(fit.actuated.size());
    const Eigen::VectorXd meas = fit.measured(), meas_v = validation.measured();
    out.baseline_fit_error = percent(y.squaredNorm(), meas);
    out.baseline_validation_error = percent(yv.squaredNorm(), meas_v);
    out.noise_level = options.noise_level;

    std::vector<Candidate> candidates = catalogue(m, fit);
    std::vector<Eigen::MatrixXd> cols, cols_v;
    for (const Candidate& c : candidates) {
        heartbeat();
        cols.push_back(c.columns(fit)), cols_v.push_back(c.columns(validation));
    }

    std::vector<size_t> chosen;
    Eigen::MatrixXd X(y.size(), 0), Xv(yv.size(), 0);
    std::vector<char> X_gain;  // per column of X: an actuator gain's (to_recorded_units)
    auto with_gain = [&](size_t k) {
        std::vector<char> g = X_gain;
        g.resize(X_gain.size() + size_t(cols[k].cols()), candidates[k].kind().id == CauseId::ActuatorGain);
        return g;
    };
    Fit current = least_squares(X, Eigen::MatrixXd(X.rows(), 0), y, Xv, Eigen::MatrixXd(Xv.rows(), 0), yv, joints);
    std::vector<size_t> refused;  // candidates the data could not tell from a named one
    std::map<size_t, std::string> carried_with;  // a named candidate: the group's others, in words
    auto taken = [&](const Candidate& c) {
        for (size_t k : refused)
            if (candidates[k].cause == c.cause && candidates[k].joint == c.joint && candidates[k].body == c.body)
                return true;
        for (size_t k : chosen) {
            const Candidate& o = candidates[k];
            // One law per cause and subject (a single Stribeck speed per joint).
            if (o.cause == c.cause && o.joint == c.joint && o.body == c.body) return true;
        }
        return false;
    };
    for (int round = 0; round < options.max_causes; ++round) {
        heartbeat(double(round) / double(std::max(1, options.max_causes)));
        // Nothing stands above the records' noise: any cause named now would
        // be named for fitting it. (Not the verdict's margin: an effect
        // beside the noise adds in quadrature, one of 75 % of the noise stays
        // within 1.25 times the floor, and validation with its BIC margin
        // still judges it.)
        if (std::isfinite(options.noise_level) && percent(current.sse_validation, meas_v) <= options.noise_level) break;
        std::vector<double> gain_of(candidates.size(), -INFINITY);
        int best = -1;
        Fit best_fit;
        double best_gain = 0;
        // One grid setting (a Stribeck speed) per joint goes on to be
        // refined: the one that fits best (the refinement spans the grid's spacing).
        std::vector<char> grid_best(candidates.size(), 0);
        {
            std::vector<double> best_sse(size_t(m.nv), INFINITY);
            std::vector<int> best_at(size_t(m.nv), -1);
            for (size_t k = 0; k < candidates.size(); ++k) {
                heartbeat();
                const Candidate& c = candidates[k];
                if (c.kind().refinement != Refinement::GridAndSpeeds || taken(c)) continue;
                const Fit f = least_squares(X, cols[k], y, Eigen::MatrixXd(0, X.cols()), Eigen::MatrixXd(0, cols[k].cols()),
                                            Eigen::VectorXd(0), joints, with_gain(k));
                if (f.ok && f.sse_fit < best_sse[size_t(c.dof)]) best_sse[size_t(c.dof)] = f.sse_fit, best_at[size_t(c.dof)] = int(k);
            }
            for (int k : best_at)
                if (k >= 0) grid_best[size_t(k)] = 1;
        }
        // A candidate whose columns the named causes already span (to the
        // same-column correlation) adds nothing but a fit to the noise, with
        // huge opposite coefficients: a centre of mass moved across the last
        // link after that joint's sensor offset, say.
        const double least_new = std::sqrt(std::max(0.0, 1 - options.same_column_correlation * options.same_column_correlation));
        for (size_t k = 0; k < candidates.size(); ++k) {
            heartbeat();
            if (taken(candidates[k])) continue;
            const Refinement refinement = candidates[k].kind().refinement;
            if (refinement == Refinement::GridAndSpeeds && !grid_best[k]) continue;
            auto fit_with = [&](const Eigen::MatrixXd& ck, const Eigen::MatrixXd& cvk) {
                return least_squares(X, ck, y, Xv, cvk, yv, joints, with_gain(k));
            };
            Fit f = fit_with(cols[k], cols_v[k]);
            if (!f.ok || spanned(f.R, X.cols(), least_new)) continue;
            // Nonlinear settings, refined on the fit records along with the causes named so far.
            if (refinement == Refinement::ExactLag) {
                // The exact lag: the column at setting d has the delay as its
                // coefficient, so d = coefficient is a fixed point (a few
                // steps from the first-order estimate; the second-order part
                // of a lag would otherwise pass for an actuator gain).
                Candidate c = candidates[k];
                for (int it = 0; it < 8; ++it) {
                    const double d = f.theta[X.cols()];
                    if (!(d > 0) || d > 0.5) break;
                    const bool settled = c.scale > 0 && std::abs(d - c.scale) < 1e-4 * c.scale;
                    c.scale = d;
                    const Eigen::MatrixXd ck = c.columns(fit), cvk = c.columns(validation);
                    const Fit g = fit_with(ck, cvk);
                    if (!g.ok) break;
                    candidates[k] = c, cols[k] = ck, cols_v[k] = cvk, f = g;
                    if (settled) break;
                }
            } else if (refinement == Refinement::OffsetAnchor) {
                // Its column's second-order part at the offset found: a fixed point, as for a shift.
                Candidate c = candidates[k];
                for (int it = 0; it < 8; ++it) {
                    const double o = f.theta[X.cols()];
                    const double before = c.offset_anchor;
                    c.offset_anchor = o;
                    const Eigen::MatrixXd ck = c.columns(fit), cvk = c.columns(validation);
                    const Fit g = fit_with(ck, cvk);
                    if (!g.ok) break;
                    candidates[k] = c, cols[k] = ck, cols_v[k] = cvk, f = g;
                    if (std::abs(o - before) <= 1e-6 * std::abs(o)) break;
                }
            } else if (refinement == Refinement::ComAnchor && candidates[k].shifts_com()) {
                // The shift's columns through the shift found: a fixed point
                // a few steps from the first-order estimate (the quadratic
                // part of a shift would otherwise pass for an armature).
                Candidate c = candidates[k];
                const double size = largest_com_shift(c.body_inertia);
                for (int it = 0; it < 8; ++it) {
                    const Eigen::VectorXd th = f.theta.segment(X.cols(), cols[k].cols());
                    if (!(th.norm() <= size)) break;  // no shift of this body: another cause's signature
                    const Eigen::Vector3d before = c.com_anchor;
                    c.anchor_com_shift(th);
                    const Eigen::MatrixXd ck = c.columns(fit), cvk = c.columns(validation);
                    const Fit g = fit_with(ck, cvk);
                    if (!g.ok) break;
                    candidates[k] = c, cols[k] = ck, cols_v[k] = cvk, f = g;
                    if ((c.com_anchor - before).norm() <= 1e-6 * c.com_anchor.norm()) break;
                }
            } else if (refinement == Refinement::GridAndSpeeds) {
                // The Stribeck speed and the sign's smoothing speed (the
                // breadth of the law's step at zero speed, which trades
                // against its amplitude): golden-section searches on the fit
                // error in log speed, alternated, within a factor of the
                // grid's spacing and of the default smoothing.
                Candidate c = candidates[k];
                const double s0 = c.scale, v0 = sign_speed(fit, c.dof);
                c.smoothing = v0;
                auto sse = [&](double* setting, double log_speed) {
                    *setting = std::exp(log_speed);
                    // A Stribeck dip narrower than a few smoothing speeds is
                    // the Coulomb law's shape at reversals, not a dip.
                    if (c.smoothing > c.scale / 3) return double(INFINITY);
                    const Fit g = fit_with(c.columns(fit), Eigen::MatrixXd::Zero(Xv.rows(), 1));
                    return g.ok ? g.sse_fit : INFINITY;
                };
                auto golden = [&](double* setting, double lo, double hi) {
                    const double phi = 0.5 * (std::sqrt(5.0) - 1);
                    double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo), f1 = sse(setting, x1),
                           f2 = sse(setting, x2);
                    for (int it = 0; it < 12; ++it) {
                        if (f1 < f2)
                            hi = x2, x2 = x1, f2 = f1, x1 = hi - phi * (hi - lo), f1 = sse(setting, x1);
                        else
                            lo = x1, x1 = x2, f1 = f2, x2 = lo + phi * (hi - lo), f2 = sse(setting, x2);
                    }
                    *setting = std::exp(0.5 * (lo + hi));
                };
                // (Speeds within the grid's span: beyond its top the dip spans
                // the motion and passes for Coulomb and viscous friction.)
                const double top = 100 * 0.5 * v0, bottom = 100 * 0.02 * v0;
                for (int pass = 0; pass < 2; ++pass) {
                    golden(&c.scale, std::log(std::max(bottom, s0 / 2.5)), std::log(std::min(top, s0 * 2.5)));
                    golden(&c.smoothing, std::log(v0 / 4), std::log(v0 * 4));
                }
                const Eigen::MatrixXd ck = c.columns(fit), cvk = c.columns(validation);
                const Fit g = fit_with(ck, cvk);
                if (g.ok && g.sse_fit < f.sse_fit) candidates[k] = c, cols[k] = ck, cols_v[k] = cvk, f = g;
            }
            const Candidate& c = candidates[k];
            const Eigen::Index p0 = X.cols(), np = cols[k].cols();
            const Eigen::VectorXd th = f.theta.segment(p0, np);
            bool significant = true;
            for (Eigen::Index i = 0; i < np; ++i) {
                const double se = std::sqrt(std::max(0.0, f.covariance(p0 + i, p0 + i)));
                significant = significant && std::abs(th[i]) > options.min_t_ratio * se;
            }
            const double gain = current.sse_validation - f.sse_validation;
            if (round == 0) {
                std::ostringstream s;
                s << c.cause << " on " << subject_text(m, c) << ": validation "
                  << percent(f.sse_validation, meas_v) << " %";
                out.considered.push_back(s.str());
            }
            if (!significant || !c.physical(th)) continue;
            // Nor may it make a cause named before unphysical in the joint
            // fit (a gain deficit pushed to all of the effort by a shift that
            // takes over its part).
            bool named_physical = true;
            for (size_t i = 0, at = 0; i < chosen.size(); ++i) {
                const Eigen::Index n = cols[chosen[i]].cols();
                named_physical = named_physical && candidates[chosen[i]].physical(f.theta.segment(Eigen::Index(at), n));
                at += size_t(n);
            }
            if (!named_physical) continue;
            // Nor one whose parameters the joint fit cannot tell from a named
            // cause's (a loop's coupler shifted against the crank's gain):
            // what it adds is the noise the pair can fit, not evidence.
            bool apart = true;
            for (Eigen::Index i = p0; i < p0 + np && apart; ++i)
                for (Eigen::Index j = 0; j < p0; ++j) {
                    const double r = f.covariance(i, j) / std::sqrt(f.covariance(i, i) * f.covariance(j, j));
                    if (std::abs(r) > options.max_rival_correlation) apart = false;
                }
            if (!apart) continue;
            gain_of[k] = gain;
            if (gain > best_gain) best = int(k), best_gain = gain, best_fit = f;
        }
        if (best < 0) break;
        // Named only when validation, not the fit, says it helps, by more
        // than a small share and beyond what noise and the added parameters explain.
        const double err_now = percent(current.sse_validation, meas_v);
        const double err_new = percent(best_fit.sse_validation, meas_v);
        const Eigen::Index nv = yv.size();
        const bool relative = err_new < (1 - options.min_relative_gain) * err_now;
        // (A Stribeck law's two refined speeds count as parameters too.)
        const Eigen::Index settings = candidates[size_t(best)].kind().settings;
        const bool evidence = bic(best_fit.sse_validation, nv, X.cols() + cols[size_t(best)].cols() + settings) <
                              bic(current.sse_validation, nv, X.cols()) - options.bic_margin;
        if (!relative || !evidence) break;
        // A rival of another cause or subject that explains about as much
        // (validation does not prefer the best one beyond the BIC margin)
        // with a column nearly the same as the best one's (once the named
        // causes are accounted for): the data cannot tell the two apart.
        // Exactly the same column (a crank turning about the actuated axis:
        // its inertia and the armature) is one base parameter, named once
        // as the first in the catalogue with a warning; merely close ones
        // are not named at all.
        {
            const Candidate& cb = candidates[size_t(best)];
            int close = -1;
            double close_r = 0, rival_r = 0;
            std::vector<size_t> rivals;  // of other causes, validation not preferring the best beyond the margin
            for (size_t k = 0; k < candidates.size(); ++k) {
                const Candidate& o = candidates[k];
                if (int(k) == best || !(gain_of[k] > 0.5 * best_gain) || o.cause == cb.cause) continue;
                const double r = unexplained_correlation(X, cols[size_t(best)].col(0), cols[k].col(0));
                const double e_rival = percent(current.sse_validation - gain_of[k], meas_v),
                             e_best = percent(current.sse_validation - best_gain, meas_v), floor = options.noise_level;
                const bool near_noise = std::isfinite(floor) && floor > 0 && e_best <= 2 * floor;
                const bool alike = near_noise ? e_rival * e_rival - e_best * e_best < options.ambiguous_noise_share * floor * floor
                                              : e_rival < options.ambiguous_error_ratio * e_best;
                if (r > options.ambiguous_correlation && r > close_r && alike) close = int(k), close_r = r;
                // Told apart when validation prefers the best one strongly (the BIC margin).
                const double sse_rival = current.sse_validation - gain_of[k];
                if (bic(sse_rival, nv, 1) - bic(best_fit.sse_validation, nv, 1) > options.bic_margin) continue;
                if (r > options.max_rival_correlation) {
                    // One per cause and subject (a Stribeck law's grid, a friction's variants).
                    bool seen = false;
                    for (size_t& q : rivals)
                        if (candidates[q].cause == o.cause && candidates[q].joint == o.joint && candidates[q].body == o.body) {
                            if (gain_of[k] > gain_of[q]) q = k;
                            seen = true;
                        }
                    if (!seen) rivals.push_back(k);
                    rival_r = std::max(rival_r, r);
                }
            }
            // Validation prefers the best one, but not by much, and another
            // cause's column is nearly the same: named, with a warning that
            // these records can hardly tell the two apart (a mass that
            // carries nearly all the inertia against an actuator gain, say).
            if (rivals.empty() && close >= 0) {
                const Candidate& o = candidates[size_t(close)];
                std::ostringstream s;
                s.precision(4);
                s << cb.cause << " on " << subject_text(m, cb) << " is named, but " << o.cause << " on "
                  << subject_text(m, o) << " explains nearly as much with a nearly equal column (r = " << close_r
                  << ", validation " << percent(current.sse_validation - best_gain, meas_v) << " % against "
                  << percent(current.sse_validation - gain_of[size_t(close)], meas_v)
                  << " %): these records hardly tell them apart; a record with another load or motion would";
                out.warnings.push_back(s.str());
                out.ambiguous.push_back({cb.cause + " on " + subject_text(m, cb), o.cause + " on " + subject_text(m, o)});
            }
            if (!rivals.empty()) {
                // A group the records cannot tell apart still explains the
                // data: the model carries one of it, the catalogue's simplest
                // (the same fit, within the correlation), the others are not
                // offered again, and the search goes on with the other causes.
                std::vector<size_t> group = rivals;
                group.push_back(size_t(best));
                size_t carried = size_t(best);
                for (size_t k : group) {
                    const auto rank = [&](size_t i) { return std::pair{int(candidates[i].kind().id), i}; };
                    if (rank(k) < rank(carried)) carried = k;
                }
                std::ostringstream s, others;
                s.precision(5);
                for (size_t k : group) {
                    s << (k == group.front() ? "" : k == group.back() ? " and " : ", ") << candidates[k].cause << " on "
                      << subject_text(m, candidates[k]) << " (validation "
                      << percent(current.sse_validation - (int(k) == best ? best_gain : gain_of[k]), meas_v) << " %)";
                    if (k != carried) {
                        others << (others.tellp() > 0 ? ", " : "") << candidates[k].cause << " on "
                               << subject_text(m, candidates[k]);
                        refused.push_back(k);
                    }
                }
                s << " have the same signature in these data (r up to " << rival_r << "): the model carries "
                  << candidates[carried].cause << " on " << subject_text(m, candidates[carried]);
                if (rival_r > options.same_column_correlation)
                    s << " (one parameter; the catalogue's simpler cause)";
                else
                    s << " (the catalogue's simpler cause); a record with another load or motion would tell which";
                out.warnings.push_back(s.str());
                out.ambiguous.emplace_back();
                for (size_t k : group) out.ambiguous.back().push_back(candidates[k].cause + " on " + subject_text(m, candidates[k]));
                carried_with[carried] = others.str();
                if (int(carried) != best) {
                    best = int(carried);
                    best_fit = least_squares(X, cols[size_t(best)], y, Xv, cols_v[size_t(best)], yv, joints, with_gain(size_t(best)));
                    if (!best_fit.ok) break;
                }
            }
        }
        const Candidate& c = candidates[size_t(best)];
        SelectedCause sc;
        sc.candidate = c;
        {
            // The signature: how the residual before this step lines up with the cause's column.
            const Eigen::VectorXd residual = y - X * current.theta;
            std::ostringstream s;
            s.precision(3);
            s << "residual correlates with the " << c.cause << " column on " << subject_text(m, c)
              << " (r = " << correlation(residual, cols[size_t(best)].col(0)) << ")";
            if (const auto w = carried_with.find(size_t(best)); w != carried_with.end())
                s << "; carried for a group these records cannot tell apart, with " << w->second;
            sc.evidence = s.str();
        }
        chosen.push_back(size_t(best));
        Eigen::MatrixXd X2(X.rows(), X.cols() + cols[size_t(best)].cols()), Xv2(Xv.rows(), Xv.cols() + cols_v[size_t(best)].cols());
        X2 << X, cols[size_t(best)];
        Xv2 << Xv, cols_v[size_t(best)];
        X_gain = with_gain(size_t(best));
        X = std::move(X2), Xv = std::move(Xv2);
        current = best_fit;
        sc.fit_error = percent(current.sse_fit, meas);
        // (the fit that is named: the catalogue's first of two alike may have replaced the best)
        sc.validation_error = percent(best_fit.sse_validation, meas_v);
        sc.validation_gain = err_now - sc.validation_error;
        out.causes.push_back(std::move(sc));
    }
    // Parameters from the final joint fit, with standard errors; a warning
    // where two of them cannot be told apart.
    Eigen::Index at = 0;
    std::vector<std::string> names;
    for (SelectedCause& sc : out.causes) {
        for (const std::string& p : sc.candidate.parameters) {
            Estimate e;
            e.name = p;
            e.value = current.theta[at];
            e.std_error = std::sqrt(std::max(0.0, current.covariance(at, at)));
            sc.parameters.push_back(e);
            names.push_back(sc.candidate.cause + "." + p + " on " + subject_text(m, sc.candidate));
            ++at;
        }
    }
    for (Eigen::Index i = 0; i < at; ++i)
        for (Eigen::Index k = i + 1; k < at; ++k) {
            const double r = current.covariance(i, k) / std::sqrt(current.covariance(i, i) * current.covariance(k, k));
            if (std::abs(r) > 0.95) {
                std::ostringstream s;
                s.precision(3);
                s << names[size_t(i)] << " and " << names[size_t(k)] << " are correlated (r = " << r
                  << "): the data can hardly tell them apart";
                out.warnings.push_back(s.str());
            }
        }
    out.final_fit_error = percent(current.sse_fit, meas);
    out.final_validation_error = percent(current.sse_validation, meas_v);
    return out;
}

void locate_residual(const sim::Model& m, Identification& id, const RegressionRows& validation) {
    id.residual_concentration.clear();
    if (explained_to_noise(id.final_validation_error, id.noise_level)) return;
    Eigen::VectorXd left = validation.y();
    for (const SelectedCause& c : id.causes) remove_cause(c, validation, left);
    const Eigen::Index A = Eigen::Index(validation.actuated.size()), S = validation.samples;
    const double total = left.squaredNorm();
    if (!(total > 0) || S < 20) return;
    for (Eigen::Index a = 0; a < A; ++a) {
        const int dof = validation.actuated[size_t(a)];
        const sim::JointT<double>& joint = m.joints[size_t(m.dof_joint[size_t(dof)])];
        double own = 0;
        for (Eigen::Index s = 0; s < S; ++s) own += left[s * A + a] * left[s * A + a];
        if (own < 0.25 * total) continue;
        const double speed = std::sqrt(validation.qd.col(dof).squaredNorm() / double(S));
        const double accel = std::sqrt(validation.qdd.col(dof).squaredNorm() / double(S));
        const Eigen::VectorXd q = validation.q.col(joint.q_index);
        const double lo = q.minCoeff(), hi = q.maxCoeff();
        struct Region {
            std::string words;
            double energy = 0;
            int rows = 0;
        };
        std::vector<Region> regions = {{"at velocity reversals (speeds below a tenth of their RMS)"},
                                       {"at high accelerations (above 1.5 times their RMS)"}};
        const int bins = hi > lo ? 5 : 0;
        const bool linear = joint.kind == sim::JointKind::Prismatic;
        for (int b = 0; b < bins; ++b) {
            std::ostringstream w;
            w.precision(3);
            const double from = lo + (hi - lo) * b / bins, to = lo + (hi - lo) * (b + 1) / bins;
            w << "between positions " << (linear ? from : from * 180 / M_PI) << " and " << (linear ? to : to * 180 / M_PI)
              << (linear ? " m" : " deg");
            regions.push_back({w.str()});
        }
        for (Eigen::Index s = 0; s < S; ++s) {
            const double e = left[s * A + a] * left[s * A + a];
            auto add = [&](Region& r) { r.energy += e, ++r.rows; };
            if (std::abs(validation.qd(s, dof)) < 0.1 * speed) add(regions[0]);
            if (std::abs(validation.qdd(s, dof)) > 1.5 * accel) add(regions[1]);
            if (bins > 0) add(regions[size_t(2 + std::min(bins - 1, int(bins * (q[s] - lo) / (hi - lo))))]);
        }
        const Region* worst = nullptr;
        double worst_ratio = 0;
        for (const Region& r : regions) {
            if (r.rows == 0) continue;
            const double energy_share = r.energy / own, row_share = double(r.rows) / double(S);
            const double ratio = energy_share / row_share;
            if (energy_share >= 0.2 && ratio >= 2 && ratio > worst_ratio) worst = &r, worst_ratio = ratio;
        }
        if (!worst) continue;
        std::ostringstream s;
        s << "joint '" << joint.name << "': " << std::lround(100 * worst->energy / own) << " % of its residual lies "
          << worst->words << ", " << std::lround(100 * double(worst->rows) / double(S)) << " % of its samples";
        id.residual_concentration.push_back(s.str());
    }
}

void recompute_errors(Identification& id, const RegressionRows& fit, const RegressionRows& validation) {
    Eigen::VectorXd left_fit = fit.y(), left_validation = validation.y();
    const Eigen::VectorXd meas = fit.measured(), meas_v = validation.measured();
    double before = id.baseline_validation_error;
    // The actuator gains named so far, for the errors in recorded units.
    Eigen::MatrixXd gains_fit(left_fit.size(), 0), gains_validation(left_validation.size(), 0);
    Eigen::VectorXd deficits(0);
    auto sse = [&](const Eigen::VectorXd& left, const Eigen::MatrixXd& gains) {
        Eigen::VectorXd r = left;
        to_recorded_units(r, gains, deficits, std::vector<char>(size_t(gains.cols()), 1));
        return r.squaredNorm();
    };
    for (SelectedCause& c : id.causes) {
        remove_cause(c, fit, left_fit);
        remove_cause(c, validation, left_validation);
        if (c.candidate.kind().id == CauseId::ActuatorGain && !c.parameters.empty()) {
            auto append = [](Eigen::MatrixXd& to, const Eigen::MatrixXd& col) {
                to.conservativeResize(Eigen::NoChange, to.cols() + 1);
                to.col(to.cols() - 1) = col.col(0);
            };
            append(gains_fit, c.candidate.columns(fit));
            append(gains_validation, c.candidate.columns(validation));
            deficits.conservativeResize(deficits.size() + 1);
            deficits[deficits.size() - 1] = c.parameters[0].value;
        }
        c.fit_error = percent(sse(left_fit, gains_fit), meas);
        c.validation_error = percent(sse(left_validation, gains_validation), meas_v);
        c.validation_gain = before - c.validation_error;
        before = c.validation_error;
    }
    id.final_fit_error = percent(sse(left_fit, gains_fit), meas);
    id.final_validation_error = percent(sse(left_validation, gains_validation), meas_v);
}

}  // namespace mbx::calibration
