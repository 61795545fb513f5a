#include "calibration/excitation/excitation.h"

#include <algorithm>
#include <complex>
#include <memory>
#include <random>
#include <sstream>

#include "calibration/cause_table.h"
#include "calibration/identification/closed_chain.h"
#include "core/finding.h"
#include "core/heartbeat.h"
#include "core/text_format.h"
#include "sim/dynamics.h"
#include "sim/joint_forces.h"

namespace mbx::calibration {

void FourierReference::at(double t, double period, double& q, double& qd, double& qdd) const {
    const double w = 2 * M_PI / period;
    q = q0, qd = 0, qdd = 0;
    for (size_t l = 0; l < a.size(); ++l) {
        const double lw = double(l + 1) * w, s = std::sin(lw * t), c = std::cos(lw * t);
        q += a[l] * s + b[l] * (c - 1);
        qd += lw * (a[l] * c - b[l] * s);
        qdd -= lw * lw * (a[l] * s + b[l] * c);
    }
}

FourierReference followed(const FourierReference& r, double period, const ExcitationServo& servo, double inertia) {
    if (!(servo.stiffness > 0)) return r;
    // a sin + b cos = Re[(b - i a) e^{i theta}]: the closed loop multiplies
    // (b - i a) by H(i l w) = (k + i l w d_e) / (k - J (l w)^2 + i l w d).
    FourierReference q = r;
    const double w = 2 * M_PI / period;
    double shift = 0;
    for (size_t l = 0; l < r.a.size(); ++l) {
        const double lw = double(l + 1) * w;
        const std::complex<double> H(servo.stiffness, servo.damping_on_error ? lw * servo.damping : 0.0);
        const std::complex<double> c = H / std::complex<double>(servo.stiffness - inertia * lw * lw, lw * servo.damping) *
                                       std::complex<double>(r.b[l], -r.a[l]);
        q.b[l] = c.real(), q.a[l] = -c.imag();
        shift += q.b[l] - r.b[l];
    }
    q.q0 = r.q0 + shift;  // the same mean: q0 - sum b unchanged
    return q;
}

namespace {

ClosedChain chain_of(const sim::Model& m, const std::vector<int>& dofs) {
    std::vector<char> measured(size_t(m.nv), 0);
    for (int dof : dofs) measured[size_t(dof)] = 1;
    return closed_chain(m, measured);
}

// motion_rows with the chain of `dofs` already made (the search makes it once).
RegressionRows rows_along(const sim::Model& m, ClosedChain& chain, const std::vector<int>& dofs, const SampledMotion& motion,
                          unsigned parts = kAllRowParts) {
    RegressionRows rows;
    rows.actuated = dofs;
    const Eigen::Index na = Eigen::Index(dofs.size());
    RowSamples samples(m.nq, m.nv, na, Eigen::Index(motion.t.size()));
    for (Eigen::Index k = 0; k < samples.size(); ++k) {
        samples.start_row(k, m.q_reference, k == 0);
        for (size_t i = 0; i < dofs.size(); ++i) {
            samples.q(m.joints[size_t(m.dof_joint[size_t(dofs[i])])].q_index, k) = motion.q(k, Eigen::Index(i));
            samples.qd(dofs[i], k) = motion.qd(k, Eigen::Index(i));
            samples.qdd(dofs[i], k) = motion.qdd(k, Eigen::Index(i));
        }
    }
    fill_rows(m, chain, samples, rows, parts);
    // The model's own efforts stand for the measured ones (an actuator
    // gain's column is the effort the actuator gives).
    rows.effort = rows.model_effort;
    rows.weight = effort_weights(rows);
    return rows;
}

}  // namespace

RegressionRows motion_rows(const sim::Model& m, const std::vector<int>& dofs, const SampledMotion& motion) {
    ClosedChain chain = chain_of(m, dofs);
    return rows_along(m, chain, dofs, motion);
}

namespace {

// The causes' columns side by side, rows weighted as `rows` says.
Eigen::MatrixXd design_matrix(const RegressionRows& rows, const std::vector<Candidate>& causes) {
    Eigen::Index np = 0;
    for (const Candidate& c : causes) np += Eigen::Index(c.parameters.size());
    Eigen::MatrixXd X(rows.samples * Eigen::Index(rows.actuated.size()), np);
    Eigen::Index at = 0;
    for (const Candidate& c : causes) {
        const Eigen::MatrixXd cols = c.columns(rows);
        X.middleCols(at, cols.cols()) = cols;
        at += cols.cols();
    }
    return X;
}

}  // namespace

std::vector<Candidate> separable_causes(const RegressionRows& rows, const std::vector<Candidate>& causes,
                                        const sim::Model& m, std::vector<std::string>& dropped) {
    const Eigen::MatrixXd X = design_matrix(rows, causes);
    if (X.cols() == 0 || !X.allFinite()) return causes;
    // Unit columns, then a rank-revealing QR: the pivots are the most
    // independent columns first, and those past the rank are combinations
    // of them (or zero).
    Eigen::VectorXd norms = X.colwise().norm().transpose();
    const double top = norms.maxCoeff();
    Eigen::MatrixXd Xn = X;
    for (Eigen::Index j = 0; j < X.cols(); ++j) Xn.col(j) = norms[j] > 1e-12 * top ? Eigen::VectorXd(X.col(j) / norms[j]) : Eigen::VectorXd::Zero(X.rows());
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xn);
    qr.setThreshold(1e-6);
    std::vector<char> independent(size_t(X.cols()), 0);
    for (Eigen::Index k = 0; k < qr.rank(); ++k) independent[size_t(qr.colsPermutation().indices()[k])] = 1;
    std::vector<Candidate> out;
    Eigen::Index at = 0;
    for (const Candidate& c : causes) {
        bool all = true;
        for (size_t p = 0; p < c.parameters.size(); ++p) all = all && independent[size_t(at + Eigen::Index(p))];
        at += Eigen::Index(c.parameters.size());
        if (all) out.push_back(c);
        else dropped.push_back(c.cause + " on " + subject_text(m, c));
    }
    return out;
}

PredictedErrors predict_errors(const RegressionRows& motion, const std::vector<Candidate>& causes,
                               const std::vector<double>& noise, double rows_per_second, double seconds,
                               const sim::Model& m) {
    PredictedErrors out;
    // Each row weighed by its joint's noise: the columns are then in units of it.
    RegressionRows rows = motion;
    rows.weight.assign(rows.actuated.size(), 1.0);
    for (size_t a = 0; a < rows.actuated.size() && a < noise.size(); ++a) rows.weight[a] = 1 / noise[a];
    const Eigen::MatrixXd X = design_matrix(rows, causes);
    const Eigen::Index np = X.cols();
    for (const Candidate& c : causes)
        for (const std::string& p : c.parameters) out.names.push_back(c.cause + "." + p + " on " + subject_text(m, c));
    out.std_error = Eigen::VectorXd::Constant(np, INFINITY);
    if (np == 0 || !X.allFinite()) return out;
    // The rows stand for rows_per_second * seconds of identification rows:
    // X^T X grows with their number.
    const double scale = rows_per_second * seconds / double(rows.samples);
    // Scaled to unit columns, so that the test of rank is about alike columns, not units.
    const Eigen::VectorXd norms = X.colwise().norm().transpose();
    if (!(norms.minCoeff() > 0)) return out;
    const Eigen::MatrixXd Xn = X * norms.cwiseInverse().asDiagonal();
    // Xn P = Q R: (Xn^T Xn)^-1 = P R^-1 R^-T P^T, whose diagonal is the
    // squared rows of R^-1. (A Jacobi SVD, the same numbers, was a fifth of
    // the design's time on the 7-DoF chain.) Columns too alike to tell
    // apart leave R's last pivots below 1e-8 of its first.
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xn);
    const Eigen::MatrixXd R = qr.matrixR().topLeftCorner(np, np).triangularView<Eigen::Upper>();
    const double first = std::abs(R(0, 0));
    for (Eigen::Index k = 0; k < np; ++k)
        if (!(std::abs(R(k, k)) > 1e-8 * first)) return out;
    const Eigen::MatrixXd Rinv =
        R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(np, np));
    for (Eigen::Index k = 0; k < np; ++k) {
        const Eigen::Index j = qr.colsPermutation().indices()[k];
        out.std_error[j] = std::sqrt(Rinv.row(k).squaredNorm() / scale) / norms[j];
    }
    out.criterion = out.std_error.array().log10().mean();
    return out;
}

std::vector<Candidate> excitation_causes(const sim::Model& m, const RegressionRows& rows, const ExcitationOptions& options) {
    static const std::vector<std::string> kDefault = {"viscous_friction", "coulomb_friction", "armature", "effort_offset",
                                                      "mass_error"};
    // Each entry a cause on every subject, or "cause on subject" on one.
    struct Wanted {
        std::string cause, subject;  // subject "": any
    };
    std::vector<Wanted> wanted;
    for (const std::string& n : options.causes.empty() ? kDefault : options.causes) {
        const size_t on = n.find(" on ");
        Wanted w{on == std::string::npos ? n : n.substr(0, on), on == std::string::npos ? "" : n.substr(on + 4)};
        cause_kind(w.cause);  // an unknown name is an error naming it
        wanted.push_back(w);
    }
    auto asked = [&](const Candidate& c) {
        const std::string subject = subject_text(m, c);
        if (!options.subjects.empty() &&
            std::find(options.subjects.begin(), options.subjects.end(), subject) == options.subjects.end())
            return false;
        for (const Wanted& w : wanted)
            if (w.cause == c.cause && (w.subject.empty() || w.subject == subject)) return true;
        return false;
    };
    std::vector<Candidate> out;
    for (const Candidate& c : catalogue(m, rows)) {
        if (!asked(c)) continue;
        bool seen = false;
        for (const Candidate& o : out) seen = seen || (o.cause == c.cause && o.joint == c.joint && o.body == c.body);
        if (!seen) out.push_back(c);
    }
    for (const Wanted& w : wanted) {
        if (w.subject.empty()) continue;
        bool offered = false;
        for (const Candidate& c : out) offered = offered || (c.cause == w.cause && subject_text(m, c) == w.subject);
        if (!offered)
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name),
                        "the excitation design cannot make " + w.cause + " on " + w.subject +
                            " identifiable: the model offers no such cause there");
    }
    if (out.empty())
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name), "the excitation design names no cause the model offers");
    return out;
}

namespace {

// Gaussian draws from mt19937_64's bits: the same design on every standard library.
struct Draw {
    std::mt19937_64 engine;
    explicit Draw(uint64_t seed) : engine(seed) {}
    double uniform() { return double(engine() >> 11) * (1.0 / 9007199254740992.0); }
    double normal() {
        double u = uniform();
        while (u <= 0) u = uniform();
        return std::sqrt(-2 * std::log(u)) * std::cos(2 * M_PI * uniform());
    }
};

struct Problem {
    const sim::Model& m;
    const std::vector<int>& dofs;
    const std::vector<ExcitationLimits>& limits;
    const ExcitationOptions& o;
    std::vector<double> q0;
    std::vector<double> times;  // one period
    std::shared_ptr<ClosedChain> chain;
    std::vector<Eigen::Index> actuated_at;  // each dof's place among the chain's independent coordinates
    std::shared_ptr<sim::Data> data;
    // What the rows hold beyond the efforts: all of it until the causes are
    // known, then only what their columns read.
    unsigned parts = kAllRowParts;
    int free_per_dof() const { return 2 * o.harmonics; }

    // References of coefficients x (per coordinate a_1..a_N, b_1..b_N) times
    // s, projected onto the rest conditions (sum l a_l = 0, sum l^2 b_l = 0)
    // along their normals: the least change to the spectrum. (Solving the
    // conditions for the first harmonic instead put most of a random
    // shape's size into the slow fundamental, which then used up the
    // position range.)
    std::vector<FourierReference> references(const Eigen::VectorXd& x, double s) const {
        std::vector<FourierReference> r(dofs.size());
        const int N = o.harmonics, F = free_per_dof();
        double l2 = 0, l4 = 0;
        for (int l = 1; l <= N; ++l) l2 += double(l) * l, l4 += double(l) * l * l * l;
        for (size_t i = 0; i < dofs.size(); ++i) {
            r[i].q0 = q0[i];
            r[i].a.assign(size_t(N), 0.0), r[i].b.assign(size_t(N), 0.0);
            double sa = 0, sb = 0;
            for (int l = 1; l <= N; ++l) {
                const double a = s * x[Eigen::Index(i) * F + (l - 1)], b = s * x[Eigen::Index(i) * F + N + (l - 1)];
                r[i].a[size_t(l - 1)] = a, r[i].b[size_t(l - 1)] = b;
                sa += l * a, sb += double(l) * l * b;
            }
            for (int l = 1; l <= N; ++l) {
                r[i].a[size_t(l - 1)] -= sa / l2 * l;
                r[i].b[size_t(l - 1)] -= sb / l4 * l * l;
            }
        }
        return r;
    }

    // Per coordinate the inertia its servo moves (empty without servos).
    std::vector<double> servo_inertia;
    bool servoed() const { return !servo_inertia.empty(); }
    // The motion the servos make of references r.
    std::vector<FourierReference> joints_of(const std::vector<FourierReference>& r) const {
        if (!servoed()) return r;
        std::vector<FourierReference> q(r.size());
        for (size_t i = 0; i < r.size(); ++i) q[i] = followed(r[i], o.period, o.servo[i], servo_inertia[i]);
        return q;
    }

    // sin(l w t) and cos(l w t) at `times` (samples x harmonics): every
    // motion the search tries is sampled at the same times, so the motions
    // are products with these (the sines were a seventh of the design's time).
    Eigen::MatrixXd sines, cosines;
    void set_times(std::vector<double> t) {
        times = std::move(t);
        const Eigen::Index n = Eigen::Index(times.size()), N = o.harmonics;
        // (the final check's grid can be long: there each sample is evaluated
        // as it goes rather than held, 2 x 8 bytes per sample and harmonic)
        if (double(n) * double(N) > 1e6) {
            sines.resize(0, 0), cosines.resize(0, 0);
            return;
        }
        sines.resize(n, N), cosines.resize(n, N);
        for (Eigen::Index k = 0; k < n; ++k)
            for (Eigen::Index l = 0; l < N; ++l) {
                const double phase = double(l + 1) * 2 * M_PI / o.period * times[size_t(k)];
                sines(k, l) = std::sin(phase), cosines(k, l) = std::cos(phase);
            }
    }

    SampledMotion motion(const std::vector<FourierReference>& r) const {
        SampledMotion mo;
        mo.t = times;
        const Eigen::Index n = Eigen::Index(times.size()), d = Eigen::Index(dofs.size()), N = o.harmonics;
        mo.q.resize(n, d), mo.qd.resize(n, d), mo.qdd.resize(n, d);
        if (sines.rows() != n) {
            for (Eigen::Index k = 0; k < n; ++k)
                for (Eigen::Index i = 0; i < d; ++i)
                    r[size_t(i)].at(times[size_t(k)], o.period, mo.q(k, i), mo.qd(k, i), mo.qdd(k, i));
            return mo;
        }
        Eigen::VectorXd lw(N);
        for (Eigen::Index l = 0; l < N; ++l) lw[l] = double(l + 1) * 2 * M_PI / o.period;
        for (Eigen::Index i = 0; i < d; ++i) {
            const Eigen::Map<const Eigen::VectorXd> a(r[size_t(i)].a.data(), N), b(r[size_t(i)].b.data(), N);
            mo.q.col(i) = (sines * a + cosines * b).array() + (r[size_t(i)].q0 - b.sum());
            mo.qd.col(i) = cosines * lw.cwiseProduct(a) - sines * lw.cwiseProduct(b);
            mo.qdd.col(i) = -(sines * lw.cwiseAbs2().cwiseProduct(a) + cosines * lw.cwiseAbs2().cwiseProduct(b));
        }
        return mo;
    }

    // Per coordinate, the largest scale of its motion in x that keeps its
    // kinematic limits.
    std::vector<double> joint_scales(const Eigen::VectorXd& x) const {
        const std::vector<FourierReference> r = references(x, 1);
        std::vector<double> scales = kinematic_scales(motion(r));
        if (servoed()) {
            const std::vector<double> joint = kinematic_scales(motion(joints_of(r)));
            for (size_t i = 0; i < scales.size(); ++i) scales[i] = std::min(scales[i], joint[i]);
        }
        return scales;
    }
    std::vector<double> kinematic_scales(const SampledMotion& unit) const {
        std::vector<double> scales(dofs.size(), INFINITY);
        const double keep = 1 - o.margin;
        for (size_t i = 0; i < dofs.size(); ++i) {
            const ExcitationLimits& L = limits[i];
            const Eigen::Index c = Eigen::Index(i);
            double& s = scales[i];
            const double up = (unit.q.col(c).array() - q0[i]).maxCoeff(), down = (q0[i] - unit.q.col(c).array()).maxCoeff();
            const double range = L.upper - L.lower, room = o.margin * (std::isfinite(range) ? range : 0);
            if (up > 0 && std::isfinite(L.upper)) s = std::min(s, (L.upper - room - q0[i]) / up);
            if (down > 0 && std::isfinite(L.lower)) s = std::min(s, (q0[i] - L.lower - room) / down);
            const double v = unit.qd.col(c).cwiseAbs().maxCoeff(), a = unit.qdd.col(c).cwiseAbs().maxCoeff();
            if (v > 0 && std::isfinite(L.velocity)) s = std::min(s, keep * L.velocity / v);
            if (a > 0 && std::isfinite(L.acceleration)) s = std::min(s, keep * L.acceleration / a);
        }
        return scales;
    }
    double kinematic_scale(const Eigen::VectorXd& x) const {
        const std::vector<double> s = joint_scales(x);
        return *std::min_element(s.begin(), s.end());
    }
    // x with every coordinate's motion at its own kinematic limits: the
    // search then need not find the joints' relative sizes, a narrow ridge
    // for a random search (a joint that stops short of its limits while
    // another reaches them wastes its share of the record).
    Eigen::VectorXd at_own_limits(Eigen::VectorXd x) const {
        const std::vector<double> s = joint_scales(x);
        const int F = free_per_dof();
        for (size_t i = 0; i < dofs.size(); ++i)
            if (s[i] > 0 && std::isfinite(s[i])) x.segment(Eigen::Index(i) * F, F) *= s[i];
        return x;
    }

    bool effort_limited() const {
        for (const ExcitationLimits& L : limits)
            if (std::isfinite(L.effort)) return true;
        return false;
    }

    // The largest share of an effort limit (less the margin) the motion
    // uses: the actuators' efforts by inverse dynamics less the model's
    // passive forces, projected onto the actuated coordinates in a loop.
    double effort_use(const SampledMotion& mo) const {
        sim::Data& d = *data;
        Eigen::VectorXd qd, qdd, tau;
        Eigen::MatrixXd G;
        double use = 0;
        d.q = m.q_reference;
        for (size_t k = 0; k < mo.t.size(); ++k) {
            qd = Eigen::VectorXd::Zero(m.nv), qdd = Eigen::VectorXd::Zero(m.nv);
            if (k == 0) d.q = m.q_reference;  // the loops closed from the assembly pose, then from the last sample
            for (size_t i = 0; i < dofs.size(); ++i) {
                d.q[m.joints[size_t(m.dof_joint[size_t(dofs[i])])].q_index] = mo.q(Eigen::Index(k), Eigen::Index(i));
                qd[dofs[i]] = mo.qd(Eigen::Index(k), Eigen::Index(i)), qdd[dofs[i]] = mo.qdd(Eigen::Index(k), Eigen::Index(i));
            }
            if (chain->active()) chain->close(m, d, qd, qdd, G);
            d.v = qd;
            sim::update_kinematics(m, d);
            sim::inverse_dynamics(m, d, qdd, tau);
            sim::passive_forces(m, d, sim::FrictionLaw::Regularised);
            tau -= d.qfrc_passive;
            const Eigen::VectorXd actuated = chain->active() ? Eigen::VectorXd(G.transpose() * tau) : tau;
            for (size_t i = 0; i < dofs.size(); ++i)
                if (std::isfinite(limits[i].effort))
                    use = std::max(use, std::abs(actuated[chain->active() ? actuated_at[i] : dofs[i]]) /
                                            ((1 - o.margin) * limits[i].effort));
        }
        return use;
    }

    struct Evaluated {
        double s = 0;
        RegressionRows rows;
        bool ok = false;
    };

    // x at the largest scale within every limit. The efforts' use grows with
    // the scale (if not strictly): its crossing of 1 is found by the Illinois
    // method to a relative 1e-9, so the criterion stays continuous in the
    // shape (a coarse bisection made it a staircase the search stalled on).
    Evaluated at_limits(const Eigen::VectorXd& x) const {
        Evaluated e;
        double s = kinematic_scale(x);
        if (!(s > 0) || !std::isfinite(s)) return e;
        if (effort_limited()) {
            auto excess = [&](double scale) { return effort_use(motion(joints_of(references(x, scale)))) - 1; };
            double hi = s, f_hi = excess(hi);
            if (f_hi > 0) {
                double lo = 0, f_lo = excess(0);
                if (f_lo >= 0) return e;  // holding still at the start pose already needs too much
                int side = 0;
                for (int it = 0; it < 60 && hi - lo > 1e-9 * s; ++it) {
                    const double mid = (lo * f_hi - hi * f_lo) / (f_hi - f_lo), f = excess(mid);
                    if (f > 0) {
                        hi = mid, f_hi = f;
                        if (side == -1) f_lo *= 0.5;
                        side = -1;
                    } else {
                        lo = mid, f_lo = f;
                        if (side == 1) f_hi *= 0.5;
                        side = 1;
                    }
                }
                s = lo;
            }
        }
        if (!(s > 0)) return e;
        e.rows = rows_along(m, *chain, dofs, motion(joints_of(references(x, s))), parts);
        e.s = s, e.ok = true;
        return e;
    }
};

}  // namespace

ExcitationDesign design_excitation(const sim::Model& m, const std::vector<int>& dofs,
                                   const std::vector<ExcitationLimits>& limits, const ExcitationOptions& o) {
    const Subject model = Subject::model(m.name);
    auto refuse = [&](const std::string& why) { throw Error(MBX_ERROR_INVALID_INPUT, model, "excitation design: " + why); };
    if (!(std::isfinite(o.period) && o.period > 0 && o.period <= 3600)) refuse("the period must be in (0, 3600] s");
    if (o.harmonics < 2 || o.harmonics > 50) refuse("harmonics must be 2 to 50 (one cannot start and end at rest)");
    if (o.periods < 1 || o.periods > 1000) refuse("periods must be 1 to 1000");
    if (!(o.margin >= 0 && o.margin < 0.5)) refuse("the margin must be in [0, 0.5)");
    if (o.samples_per_period < 8 * o.harmonics || o.samples_per_period > 100000)
        refuse("samples per period must be at least 8 per harmonic and at most 100000");
    if (o.evaluations < 1 || o.evaluations > 1000000) refuse("evaluations must be 1 to 1000000");
    if (!(o.sample_rate > 0) || !(o.noise_share > 0)) refuse("the sample rate and the noise share must be positive");
    if (!o.effort_noise.empty() && o.effort_noise.size() != dofs.size()) refuse("one effort noise per actuated coordinate is needed");
    for (double v : o.effort_noise)
        if (!(v > 0 && std::isfinite(v))) refuse("an effort noise must be positive");
    if (dofs.empty() || dofs.size() != limits.size()) refuse("one limit per actuated coordinate is needed");
    for (int dof : dofs)
        if (dof < 0 || dof >= m.nv) refuse("a coordinate is not the model's");

    Problem p{m, dofs, limits, o, {}, {}, nullptr, {}, std::make_shared<sim::Data>(m), kAllRowParts, {}, {}, {}};
    {
        p.chain = std::make_shared<ClosedChain>(chain_of(m, dofs));
        for (int dof : dofs)
            p.actuated_at.push_back(Eigen::Index(std::find(p.chain->independent.begin(), p.chain->independent.end(), dof) -
                                                 p.chain->independent.begin()));
    }
    for (size_t i = 0; i < dofs.size(); ++i) {
        const ExcitationLimits& L = limits[i];
        const sim::JointT<double>& j = m.joints[size_t(m.dof_joint[size_t(dofs[i])])];
        const std::string who = "joint '" + j.name + "'";
        for (double v : {L.velocity, L.acceleration, L.effort})
            if (!(v > 0)) refuse(who + ": a speed, acceleration or effort limit must be positive");
        if (!(L.upper > L.lower)) refuse(who + ": its position range is empty");
        if (!std::isfinite(L.upper - L.lower) && !std::isfinite(L.velocity) && !std::isfinite(L.acceleration))
            refuse(who + " has no position range, speed or acceleration limit: the motion would have no size");
        // The motion swings about the middle of the range, or about the
        // assembly pose where the range is open.
        const double pose = m.q_reference[j.q_index];
        p.q0.push_back(std::isfinite(L.upper - L.lower) ? 0.5 * (L.lower + L.upper)
                                                         : std::clamp(pose, L.lower, L.upper));
    }
    if (!o.servo.empty()) {
        if (o.servo.size() != dofs.size()) refuse("one servo per actuated coordinate is needed");
        for (const ExcitationServo& sv : o.servo)
            if (!(sv.stiffness >= 0 && std::isfinite(sv.stiffness) && sv.damping >= 0 && std::isfinite(sv.damping)))
                refuse("a servo's stiffness and damping must be finite and not negative");
        // Each servo moves the joint's inertia at the start pose: the mass
        // matrix's diagonal (armature included), in a loop that of the
        // motions the loop allows (G^T M G on the independent coordinates).
        sim::Data& d = *p.data;
        d.q = m.q_reference, d.v.setZero();
        for (size_t i = 0; i < dofs.size(); ++i) d.q[m.joints[size_t(m.dof_joint[size_t(dofs[i])])].q_index] = p.q0[i];
        Eigen::VectorXd qd = Eigen::VectorXd::Zero(m.nv), qdd = qd;
        Eigen::MatrixXd G;
        if (p.chain->active()) p.chain->close(m, d, qd, qdd, G);
        sim::update_kinematics(m, d);
        sim::mass_matrix(m, d);
        const Eigen::MatrixXd M = p.chain->active() ? Eigen::MatrixXd(G.transpose() * d.M * G) : Eigen::MatrixXd(d.M);
        for (size_t i = 0; i < dofs.size(); ++i) {
            const Eigen::Index at = p.chain->active() ? p.actuated_at[i] : dofs[i];
            p.servo_inertia.push_back(M(at, at));
        }
    }
    const double fc = o.cutoff > 0 ? o.cutoff : o.sample_rate / 40;
    // Identify's rows: about four per cutoff period.
    const double rows_per_second = o.sample_rate / std::max(1.0, std::floor(o.sample_rate / (4 * fc)));
    if (o.harmonics / o.period > fc / 2)
        refuse("the highest harmonic (" + readable(o.harmonics / o.period) + " Hz) is above half the records' filter cutoff");
    {
        std::vector<double> times;
        for (int k = 0; k < o.samples_per_period; ++k) times.push_back(o.period * k / o.samples_per_period);
        p.set_times(std::move(times));
    }

    // The rows of a first motion only to find the candidates (their columns
    // do not depend on it).
    Draw draw(o.seed);
    const Eigen::Index nx = Eigen::Index(dofs.size()) * p.free_per_dof();
    auto random_x = [&] {
        Eigen::VectorXd x(nx);
        const int F = p.free_per_dof();
        for (Eigen::Index k = 0; k < nx; ++k) x[k] = draw.normal() / double(1 + (k % F) % o.harmonics);
        return x;
    };
    std::vector<Candidate> causes;
    const double seconds = o.period * o.periods;
    ExcitationDesign out;
    Eigen::VectorXd best_x;
    Problem::Evaluated best;
    double best_f = INFINITY;
    // The effort noise the records will carry: given, or a share of each
    // joint's effort limit, or of the first motion's effort RMS where there
    // is none. It must not follow the motion: a motion that kept a joint's
    // effort small would otherwise be credited with a small noise.
    std::vector<double> noise = o.effort_noise;
    // The search: independent searches, each from its own random shapes
    // and tones scaled to the limits, its best start going on to a (1+1)
    // evolution strategy with the one-fifth success rule on the shape, one
    // joint's coefficients at a time (a step of every joint at once lets one
    // joint's loss hide another's gain), every tenth step a leap to a fresh
    // shape for that joint, each shape scaled to the largest motion within
    // the limits. The shapes' landscape has many local optima (the harmonic
    // a joint's motion settles on): on the two-link arm over eight seeds one
    // search of 3000 evaluations without leaps ended between -4.22 and -4.15
    // (mean log10 standard error), four of 600 with leaps between -4.23 and
    // -4.21. (Measured and not better: the same search on the coefficients
    // with the limits a penalty; random spectral tilts; peaks smoothed as a
    // 64-norm; eight searches halved in turn; the largest error ratio
    // against the first motion as the criterion, which traded one
    // parameter's gain for another's less evenly than the mean.)
    auto criterion = [&](const RegressionRows& rows) {
        if (causes.empty()) {
            causes = excitation_causes(m, rows, o);
            // The default set leaves out what this machine cannot show in
            // its efforts (a body whose mass no joint carries against
            // gravity or acceleration) or shows only as another cause;
            // causes asked for by name are kept, and refused if they are.
            if (o.causes.empty()) causes = separable_causes(rows, causes, m, out.dropped);
            p.parts = 0;
            for (const Candidate& c : causes) p.parts |= cause_kind(c.cause).row_parts;
        }
        if (noise.empty())
            for (size_t i = 0; i < dofs.size(); ++i) {
                const double rms = std::sqrt(rows.model_effort.col(Eigen::Index(i)).squaredNorm() / double(rows.samples));
                noise.push_back(o.noise_share * (std::isfinite(limits[i].effort) ? limits[i].effort : std::max(rms, 1e-12)));
            }
        return predict_errors(rows, causes, noise, rows_per_second, seconds, m);
    };
    // The criterion at x scaled to the limits (infinite: no motion of that
    // shape keeps them); `shape` is x at its joints' own kinematic limits.
    Heartbeat beat(o.progress ? Heartbeat::Callback([&](const char*, double f) { return o.progress(f); }) : Heartbeat::Callback(),
                   "the excitation design");
    const HeartbeatScope beating(&beat);
    beat.stage("excite", 0);
    auto evaluate = [&](const Eigen::VectorXd& given, Eigen::VectorXd& shape) -> double {
        shape = p.at_own_limits(given);
        Problem::Evaluated e = p.at_limits(shape);
        ++out.evaluations;
        beat.beat(double(out.evaluations) / o.evaluations);
        if (!e.ok) return INFINITY;
        const PredictedErrors predicted = criterion(e.rows);
        // The first motion is a random multi-sine within the same limits:
        // what a record made without a design would give, for the report.
        if (out.reference.names.empty()) out.reference = predicted;
        if (predicted.criterion < best_f) best_f = predicted.criterion, best_x = shape;
        return predicted.criterion;
    };
    // Tones: each joint at one harmonic drawn at random (with a little of
    // the rest). A cause seen in one joint's speed or acceleration alone is
    // best measured by a motion near a pure tone (the lowest peak for its
    // RMS), which sums of many harmonics seldom come near.
    auto tone_x = [&] {
        Eigen::VectorXd x = 0.05 * random_x();
        const int F = p.free_per_dof();
        for (size_t i = 0; i < dofs.size(); ++i) {
            const int l = int(draw.uniform() * o.harmonics) % o.harmonics;
            const double phase = 2 * M_PI * draw.uniform();
            x[Eigen::Index(i) * F + l] += std::cos(phase), x[Eigen::Index(i) * F + o.harmonics + l] += std::sin(phase);
        }
        return x;
    };
    const int F = p.free_per_dof();
    const int searches = std::clamp(o.evaluations / 300, 1, std::max(1, o.searches));
    for (int search = 0; search < searches; ++search) {
        const int budget = o.evaluations * (search + 1) / searches;  // its last evaluation's count
        const int starts = std::max(1, std::min(20, (budget - out.evaluations) / 5));
        Eigen::VectorXd x, shape, tried;
        double f = INFINITY;
        for (int k = 0; k < starts; ++k) {
            const double fk = evaluate(k % 2 ? tone_x() : random_x(), tried);
            if (fk < f) f = fk, x = tried;
        }
        if (!std::isfinite(f)) continue;
        std::vector<double> steps(dofs.size(), 0.3);
        for (size_t turn = 0; out.evaluations < budget; ++turn) {
            const size_t i = turn % dofs.size();
            const Eigen::Index at = Eigen::Index(i) * F;
            Eigen::VectorXd y = x;
            const double scale = x.segment(at, F).cwiseAbs().maxCoeff();
            // Every tenth step a leap: the joint's coefficients replaced by
            // a fresh random shape or tone of the same size, which reaches
            // another basin where small steps cannot.
            const bool leap = turn % 10 == 9;
            if (leap) {
                const Eigen::VectorXd fresh = (turn / 10) % 2 ? tone_x() : random_x();
                const double size = fresh.segment(at, F).cwiseAbs().maxCoeff();
                if (size > 0) y.segment(at, F) = fresh.segment(at, F) * (scale / size);
            } else {
                for (Eigen::Index k = at; k < at + F; ++k)
                    y[k] += steps[i] * scale * draw.normal() / double(1 + (k % F) % o.harmonics);
            }
            const double fy = evaluate(y, shape);
            const bool better = fy < f;
            if (better) f = fy, x = shape;
            if (!leap) steps[i] = std::clamp(steps[i] * (better ? 1.5 : std::pow(1.5, -0.25)), 1e-4, 2.0);
        }
    }
    if (!std::isfinite(best_f)) {
        if (causes.empty()) refuse("no motion within the limits moves the joints (check the limits)");
        refuse("the causes asked for are not identifiable together along any motion tried (two of them are one "
               "parameter for this machine)");
    }

    // Scaled to the limits exactly, on the records' own samples (or a grid
    // twenty times finer than the search's, if that is finer): the motion
    // may reach a little further between the search's points.
    {
        Problem fine = p;
        std::vector<double> times;
        const int n = int(std::min(2e6, std::max(20.0 * o.samples_per_period, std::ceil(o.sample_rate * o.period))));
        for (int k = 0; k <= n; ++k) times.push_back(o.period * k / n);
        fine.set_times(std::move(times));
        Problem::Evaluated e = fine.at_limits(best_x);
        if (!e.ok) refuse("the designed motion cannot be scaled within the limits");
        best.s = e.s * (1 - 1e-9);  // (a motion that touches a limit stays on its side when rounded)
        best.rows = rows_along(m, *p.chain, dofs, p.motion(p.joints_of(p.references(best_x, e.s))), p.parts);
    }
    out.dofs = dofs, out.period = o.period, out.periods = o.periods;
    out.references = p.references(best_x, best.s);
    out.causes = causes;
    out.predicted = predict_errors(best.rows, causes, noise, rows_per_second, seconds, m);
    out.effort_noise = noise;
    out.servo_inertia = p.servo_inertia;
    const SampledMotion mo = p.motion(p.joints_of(out.references));
    for (size_t i = 0; i < dofs.size(); ++i) {
        const Eigen::Index c = Eigen::Index(i);
        out.lowest.push_back(mo.q.col(c).minCoeff()), out.highest.push_back(mo.q.col(c).maxCoeff());
        out.peak_velocity.push_back(mo.qd.col(c).cwiseAbs().maxCoeff());
        out.peak_acceleration.push_back(mo.qdd.col(c).cwiseAbs().maxCoeff());
        out.peak_effort.push_back(best.rows.model_effort.col(c).cwiseAbs().maxCoeff());
    }
    beat.report_now(1);
    return out;
}

SampledMotion sample_design(const ExcitationDesign& design, double rate) {
    SampledMotion mo;
    const double seconds = design.period * design.periods;
    const size_t n = size_t(std::llround(seconds * rate)) + 1;
    const Eigen::Index d = Eigen::Index(design.dofs.size());
    mo.q.resize(Eigen::Index(n), d), mo.qd.resize(Eigen::Index(n), d), mo.qdd.resize(Eigen::Index(n), d);
    for (size_t k = 0; k < n; ++k) {
        const double t = double(k) / rate;
        mo.t.push_back(t);
        for (Eigen::Index i = 0; i < d; ++i)
            design.references[size_t(i)].at(t, design.period, mo.q(Eigen::Index(k), i), mo.qd(Eigen::Index(k), i),
                                            mo.qdd(Eigen::Index(k), i));
    }
    return mo;
}

}  // namespace mbx::calibration
