#include "calibration/identify.h"

#include <cmath>
#include <sstream>

#include "core/finding.h"

namespace mbx::calibration {

namespace {

struct Fit {
    Eigen::VectorXd theta;
    Eigen::MatrixXd covariance;
    double sse_fit = 0, sse_validation = 0;
    bool ok = false;
};

// Least squares of y on X (column-pivoted QR: collinear columns give a
// rank-deficient fit, which is reported as not ok), residual variance from
// the fit rows, covariance sigma^2 (X^T X)^-1.
Fit least_squares(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, const Eigen::MatrixXd& Xv,
                  const Eigen::VectorXd& yv) {
    Fit f;
    if (X.cols() == 0) {
        f.theta.resize(0);
        f.sse_fit = y.squaredNorm(), f.sse_validation = yv.squaredNorm(), f.ok = true;
        return f;
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
    qr.setThreshold(1e-10);
    if (qr.rank() < X.cols()) return f;
    f.theta = qr.solve(y);
    f.sse_fit = (y - X * f.theta).squaredNorm();
    f.sse_validation = (yv - Xv * f.theta).squaredNorm();
    const double dof = std::max(1.0, double(X.rows() - X.cols()));
    const Eigen::MatrixXd XtX = X.transpose() * X;
    f.covariance = (f.sse_fit / dof) * XtX.ldlt().solve(Eigen::MatrixXd::Identity(X.cols(), X.cols()));
    f.ok = f.theta.allFinite();
    return f;
}

double percent(double sse, const Eigen::VectorXd& measured) {
    const double n = measured.squaredNorm();
    return n > 0 ? 100 * std::sqrt(sse / n) : 0;
}

double bic(double sse, Eigen::Index n, Eigen::Index k) {
    return double(n) * std::log(std::max(sse, 1e-300) / double(n)) + double(k) * std::log(double(n));
}

std::string subject_text(const sim::Model& m, const Candidate& c) {
    if (c.body >= 0) return "body '" + m.bodies[size_t(c.body)].name + "'";
    return "joint '" + m.joints[size_t(c.joint)].name + "'";
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
    const Eigen::VectorXd meas = fit.measured(), meas_v = validation.measured();
    out.baseline_fit_error = percent(y.squaredNorm(), meas);
    out.baseline_validation_error = percent(yv.squaredNorm(), meas_v);

    const std::vector<Candidate> candidates = catalogue(m, fit);
    std::vector<Eigen::MatrixXd> cols, cols_v;
    for (const Candidate& c : candidates) cols.push_back(c.columns(fit)), cols_v.push_back(c.columns(validation));

    std::vector<size_t> chosen;
    Eigen::MatrixXd X(y.size(), 0), Xv(yv.size(), 0);
    Fit current = least_squares(X, y, Xv, yv);
    auto taken = [&](const Candidate& c) {
        for (size_t k : chosen) {
            const Candidate& o = candidates[k];
            // One law per cause and subject (a single Stribeck speed per joint).
            if (o.cause == c.cause && o.joint == c.joint && o.body == c.body) return true;
        }
        return false;
    };
    for (int round = 0; round < options.max_causes; ++round) {
        int best = -1;
        Fit best_fit;
        double best_gain = 0;
        for (size_t k = 0; k < candidates.size(); ++k) {
            const Candidate& c = candidates[k];
            if (taken(c)) continue;
            Eigen::MatrixXd X2(X.rows(), X.cols() + cols[k].cols()), Xv2(Xv.rows(), Xv.cols() + cols_v[k].cols());
            X2 << X, cols[k];
            Xv2 << Xv, cols_v[k];
            Fit f = least_squares(X2, y, Xv2, yv);
            if (!f.ok) continue;
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
            if (gain > best_gain) best = int(k), best_gain = gain, best_fit = f;
        }
        if (best < 0) break;
        // Named only when validation, not the fit, says it helps, by more
        // than a small share and beyond what noise and the added parameters explain.
        const double err_now = percent(current.sse_validation, meas_v);
        const double err_new = percent(best_fit.sse_validation, meas_v);
        const Eigen::Index nv = yv.size();
        const bool relative = err_new < (1 - options.min_relative_gain) * err_now;
        const bool evidence = bic(best_fit.sse_validation, nv, X.cols() + cols[size_t(best)].cols()) <
                              bic(current.sse_validation, nv, X.cols()) - options.bic_margin;
        if (!relative || !evidence) break;
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
            sc.evidence = s.str();
        }
        chosen.push_back(size_t(best));
        Eigen::MatrixXd X2(X.rows(), X.cols() + cols[size_t(best)].cols()), Xv2(Xv.rows(), Xv.cols() + cols_v[size_t(best)].cols());
        X2 << X, cols[size_t(best)];
        Xv2 << Xv, cols_v[size_t(best)];
        X = std::move(X2), Xv = std::move(Xv2);
        current = best_fit;
        sc.fit_error = percent(current.sse_fit, meas);
        sc.validation_error = err_new;
        sc.validation_gain = err_now - err_new;
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

}  // namespace mbx::calibration
