#include "calibration/simulation/contact_fit.h"
#include "calibration/simulation/quiet_solve.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <sstream>
#include <thread>

#include "core/finding.h"
#include "core/heartbeat.h"
#include "sim/dynamics.h"
#include "sim/joint_motion.h"

namespace mbx::calibration {

namespace {

using sim::contact::ContactWorld;
using sim::contact::Shape;
using sim::contact::ShapeKind;

[[noreturn]] void fail(const std::string& message) {
    throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::model("contact calibration"), message);
}

// Runs f(i) for i in [0, n) on up to `threads` threads; the first exception
// is rethrown here. The workers share the run's heartbeat: a cancel reaches
// their rollouts too.
template <class F> void parallel_for(size_t n, int threads, F&& f) {
    size_t workers = threads > 0 ? size_t(threads) : std::max(1u, std::thread::hardware_concurrency());
    workers = std::min(workers, n);
    if (workers <= 1) {
        for (size_t i = 0; i < n; ++i) f(i);
        return;
    }
    std::atomic<size_t> next{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    Heartbeat* const heartbeat = current_heartbeat();
    auto work = [&] {
        const HeartbeatScope beating(heartbeat);
        for (size_t i; (i = next++) < n;) {
            try {
                f(i);
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!error) error = std::current_exception();
                next = n;
            }
        }
    };
    std::vector<std::thread> pool;
    for (size_t k = 1; k < workers; ++k) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

// The shapes with the model's ground offset applied.
std::vector<Shape> placed_shapes(const ContactScene& scene, const ContactModel& model) {
    std::vector<Shape> shapes = scene.shapes;
    for (Shape& s : shapes)
        if (s.body == 0 && s.kind == ShapeKind::HalfSpace) s.position += model.ground_offset * s.rotation.col(2);
    return shapes;
}

const sim::JointT<double>& free_joint(const ContactScene& scene) {
    const sim::Model& m = *scene.model;
    if (scene.body < 1 || scene.body >= m.body_count()) fail("the measured body " + std::to_string(scene.body) + " is not in the model");
    const sim::JointT<double>& j = m.joint_of_body(scene.body);
    if (j.kind != sim::JointKind::Free || m.bodies[size_t(scene.body)].parent != 0)
        fail("the measured body '" + m.bodies[size_t(scene.body)].name + "' is not a free body on the world");
    return j;
}

double angle_deg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
    return 2 * std::acos(std::min(1.0, std::abs(a.dot(b)))) * 180 / M_PI;
}

// Rotation error as a vector (axis times angle, degrees): the fit's residual,
// whose norm is the scored angle.
Eigen::Vector3d rotation_residual(const Eigen::Quaterniond& simulated, const Eigen::Quaterniond& measured) {
    Eigen::Quaterniond e = simulated * measured.conjugate();
    if (e.w() < 0) e.coeffs() = -e.coeffs();
    const Eigen::AngleAxisd aa(e);
    return aa.axis() * aa.angle() * 180 / M_PI;
}

}  // namespace

Rollout roll_out(const ContactScene& scene, const ContactModel& model, const PoseRecord& record, double rest_time) {
    const sim::Model& m = *scene.model;
    const sim::JointT<double>& joint = free_joint(scene);
    Rollout out;
    if (record.samples.empty()) return out;
    ContactWorld world(m, placed_shapes(scene, model), model.settings);
    sim::Data d(m);
    const PoseSample& s0 = record.samples.front();
    const int qi = joint.q_index, vi = joint.v_index;
    d.q.segment<3>(qi) = s0.p;
    d.q[qi + 3] = s0.q.w(), d.q[qi + 4] = s0.q.x(), d.q[qi + 5] = s0.q.y(), d.q[qi + 6] = s0.q.z();
    d.v.segment<3>(vi) = s0.v;
    d.v.segment<3>(vi + 3) = s0.w;
    d.time = s0.t;
    // A penalty contact that blows up sends the body far away or to NaN;
    // either ends the rollout as diverged rather than running on.
    const double far = 1e3 * std::max(scene.length_scale, 1e-3);
    auto healthy = [&] { return d.q.allFinite() && d.v.allFinite() && (d.q.segment<3>(qi) - s0.p).norm() < far; };
    auto pose = [&](Eigen::Vector3d& p, Eigen::Quaterniond& q) {
        p = d.q.segment<3>(qi);
        q = Eigen::Quaterniond(d.q[qi + 3], d.q[qi + 4], d.q[qi + 5], d.q[qi + 6]).normalized();
    };
    out.positions.reserve(record.samples.size());
    out.orientations.reserve(record.samples.size());
    for (const PoseSample& s : record.samples) {
        while (d.time < s.t - 1e-9 && !out.diverged) {
            heartbeat();
            world.step(m, d, scene.integrator);
            out.diverged = !healthy();
        }
        if (out.diverged) break;
        Eigen::Vector3d p;
        Eigen::Quaterniond q;
        pose(p, q);
        out.positions.push_back(p), out.orientations.push_back(q);
        out.error.position += (p - s.p).norm() / scene.length_scale * 100;
        out.error.rotation += angle_deg(q, s.q);
        ++out.error.samples;
    }
    if (out.diverged) {
        out.error.diverged = 1;
        return out;
    }
    out.error.position /= double(out.error.samples), out.error.rotation /= double(out.error.samples);
    if (rest_time > 0) {
        const double end = record.samples.back().t;
        const double watch = std::min(0.5, rest_time);
        while (d.time < end + rest_time - watch - 1e-9 && healthy()) world.step(m, d, scene.integrator);
        const Eigen::Vector3d before = d.q.segment<3>(qi);
        while (d.time < end + rest_time - 1e-9 && healthy()) world.step(m, d, scene.integrator);
        out.diverged = !healthy();
        out.error.diverged = out.diverged;
        out.rest_drift = (d.q.segment<3>(qi) - before).norm();
        out.rest_speed = d.v.segment<6>(vi).norm();
    }
    return out;
}

PoseError pose_error(const ContactScene& scene, const ContactModel& model, const std::vector<PoseRecord>& records,
                     int threads) {
    std::vector<Rollout> rollouts(records.size());
    parallel_for(records.size(), threads, [&](size_t i) { rollouts[i] = roll_out(scene, model, records[i]); });
    PoseError sum;
    for (const Rollout& r : rollouts) {
        sum.diverged += r.error.diverged;
        if (r.diverged) continue;
        sum.position += r.error.position * double(r.error.samples);
        sum.rotation += r.error.rotation * double(r.error.samples);
        sum.samples += r.error.samples;
    }
    if (sum.samples) sum.position /= double(sum.samples), sum.rotation /= double(sum.samples);
    return sum;
}

namespace {

// A contact cause's parameter in the fit's coordinates: logarithms for the
// positive, scale-free quantities, millimetres for the ground offset, so
// that one finite-difference step and one trust region suit them all.
struct Knob {
    std::string cause;
    double lower, upper;  // bounds in fit coordinates
    double step;          // central-difference step in fit coordinates
    // The screening grid: a start far from the truth (restitution 0.5 where
    // the board gives 0.1) lies in another basin than the optimum, which a
    // local fit from there never reaches.
    double grid_from, grid_to, grid_step;
};
// Keeps -Wmissing-field-initializers quiet for the least-squares values.
FittedValue value(std::string name, std::string unit, double v, double se) { return {std::move(name), std::move(unit), v, se, {}}; }

const std::vector<Knob>& knobs() {
    static const std::vector<Knob> all = {
        // Grids coarse enough to be cheap, fine enough that the least-squares
        // refit from the best point stays in its basin.
        {"contact_stiffness", -7, 7, 0.1, -6, 6, 1.5},        // ln(k / k0): 1/400 to 400 times
        {"contact_damping", -5, 5, 0.1, -3.75, 3.75, 0.75},   // ln(c / c0)
        {"contact_friction", -3, 2, 0.05, -2.5, 1.5, 0.5},    // ln(mu / mu0): 0.08 to 4.5 times
        {"ground_offset", -20, 20, 0.2, 0, 0, 1},             // mm (screened by its rest signature)
    };
    return all;
}

const Knob& knob(const std::string& cause) {
    for (const Knob& k : knobs())
        if (k.cause == cause) return k;
    fail("'" + cause + "' is not a contact cause (contact_stiffness, contact_damping, contact_friction, ground_offset)");
}

// `base` with the fit coordinates x of `causes` applied.
ContactModel apply(const ContactModel& base, const std::vector<std::string>& causes, const double* x) {
    ContactModel m = base;
    for (size_t k = 0; k < causes.size(); ++k) {
        const std::string& c = causes[k];
        if (c == "contact_stiffness") m.settings.normal.stiffness = base.settings.normal.stiffness * std::exp(x[k]);
        if (c == "contact_damping") m.settings.normal.damping = base.settings.normal.damping * std::exp(x[k]);
        if (c == "contact_friction") {
            m.settings.friction.mu_static = base.settings.friction.mu_static * std::exp(x[k]);
            m.settings.friction.mu_kinetic = base.settings.friction.mu_kinetic * std::exp(x[k]);
        }
        if (c == "ground_offset") m.ground_offset = base.ground_offset + x[k] * 1e-3;
    }
    return m;
}

// Residuals of every sample of every fit trial: position error in % of the
// size and rotation error in weighted degrees, each scaled by
// 1/sqrt(samples) so that the sum of squares is a mean square.
class RolloutResiduals : public ceres::CostFunction {
public:
    RolloutResiduals(const ContactScene& scene, const ContactModel& base, std::vector<std::string> causes,
                     const std::vector<PoseRecord>& records, const ContactFitOptions& options, int& rollouts)
        : scene_(scene), base_(base), causes_(std::move(causes)), records_(records), options_(options),
          rollouts_(rollouts) {
        for (const PoseRecord& r : records_) samples_ += r.samples.size();
        set_num_residuals(int(samples_ * 6));
        mutable_parameter_block_sizes()->push_back(int(causes_.size()));
    }

    // A cancel ends the evaluation as a failed one: no exception may cross
    // Ceres, and solve_quietly then ends the solve and throws it.
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
        try {
            return evaluate(parameters, residuals, jacobians);
        } catch (const Error& e) {
            if (e.status() == MBX_ERROR_CANCELLED) return false;
            throw;
        }
    }

    size_t samples() const { return samples_; }

private:
    bool evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
        const size_t p = causes_.size();
        const double* x = parameters[0];
        // Centre, then +/- each coordinate: every trial of every setting in one parallel batch.
        std::vector<std::vector<double>> settings(1, std::vector<double>(x, x + p));
        if (jacobians && jacobians[0])
            for (size_t j = 0; j < p; ++j)
                for (double sign : {1.0, -1.0}) {
                    std::vector<double> y(x, x + p);
                    y[j] += sign * knob(causes_[j]).step;
                    settings.push_back(y);
                }
        std::vector<Eigen::VectorXd> r(settings.size(), Eigen::VectorXd(num_residuals()));
        std::vector<char> ok(settings.size(), 1);
        std::vector<ContactModel> models;
        for (const auto& y : settings) models.push_back(apply(base_, causes_, y.data()));
        std::vector<size_t> offset(records_.size() + 1, 0);
        for (size_t i = 0; i < records_.size(); ++i) offset[i + 1] = offset[i] + records_[i].samples.size() * 6;
        const double w = 1 / std::sqrt(double(samples_));
        parallel_for(settings.size() * records_.size(), options_.threads, [&](size_t job) {
            const size_t s = job / records_.size(), i = job % records_.size();
            const Rollout roll = roll_out(scene_, models[s], records_[i]);
            if (roll.diverged) {
                ok[s] = 0;
                return;
            }
            double* out = r[s].data() + offset[i];
            for (size_t k = 0; k < records_[i].samples.size(); ++k) {
                const PoseSample& m = records_[i].samples[k];
                const Eigen::Vector3d dp = (roll.positions[k] - m.p) / scene_.length_scale * 100 * w;
                const Eigen::Vector3d dq = rotation_residual(roll.orientations[k], m.q) * options_.rotation_weight * w;
                for (int c = 0; c < 3; ++c) out[6 * k + size_t(c)] = dp[c], out[6 * k + 3 + size_t(c)] = dq[c];
            }
        });
        rollouts_ += int(settings.size() * records_.size());
        if (!ok[0]) return false;
        Eigen::Map<Eigen::VectorXd>(residuals, num_residuals()) = r[0];
        if (jacobians && jacobians[0]) {
            Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
                jacobians[0], num_residuals(), int(p));
            for (size_t j = 0; j < p; ++j) {
                const size_t plus = 1 + 2 * j, minus = 2 + 2 * j;
                const double h = knob(causes_[j]).step;
                // A side that diverged falls back to the one-sided difference.
                if (ok[plus] && ok[minus]) J.col(int(j)) = (r[plus] - r[minus]) / (2 * h);
                else if (ok[plus]) J.col(int(j)) = (r[plus] - r[0]) / h;
                else if (ok[minus]) J.col(int(j)) = (r[0] - r[minus]) / h;
                else return false;
            }
        }
        return true;
    }

    const ContactScene& scene_;
    const ContactModel& base_;
    std::vector<std::string> causes_;
    const std::vector<PoseRecord>& records_;
    const ContactFitOptions& options_;
    int& rollouts_;
    size_t samples_ = 0;
};

struct JointFit {
    std::vector<double> x;      // fit coordinates
    std::vector<double> se;     // their standard errors
    ContactModel model;
    PoseError fit;
};

// Levenberg-Marquardt over the causes' coordinates from x0 (empty: the
// base model), then standard errors from the Jacobian at the optimum. They treat
// the samples as independent, which consecutive samples of one trial are
// not: read them as a lower bound.
JointFit fit_jointly(const ContactScene& scene, const ContactModel& base, const std::vector<std::string>& causes,
                     const std::vector<PoseRecord>& records, const ContactFitOptions& options, int& rollouts,
                     std::vector<double> x0 = {}) {
    JointFit out;
    out.x = x0.size() == causes.size() ? std::move(x0) : std::vector<double>(causes.size(), 0.0);
    auto* cost = new RolloutResiduals(scene, base, causes, records, options, rollouts);
    ceres::Problem problem;
    problem.AddResidualBlock(cost, nullptr, out.x.data());
    for (size_t k = 0; k < causes.size(); ++k) {
        problem.SetParameterLowerBound(out.x.data(), int(k), knob(causes[k]).lower);
        problem.SetParameterUpperBound(out.x.data(), int(k), knob(causes[k]).upper);
    }
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_QR;
    solver.max_num_iterations = options.max_iterations;
    // Rollout noise (a tipping cube) sits near 1e-3 of the cost; tighter
    // tolerances only chase it.
    solver.function_tolerance = 1e-3;
    solver.parameter_tolerance = 1e-3;
    solver.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    solve_quietly(solver, &problem, &summary);

    const int n = cost->num_residuals(), p = int(causes.size());
    Eigen::VectorXd r(n);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(n, p);
    const double* params[] = {out.x.data()};
    double* jac[] = {J.data()};
    out.se.assign(causes.size(), std::numeric_limits<double>::quiet_NaN());
    if (cost->Evaluate(params, r.data(), jac)) {
        // Residuals are pre-scaled by 1/sqrt(N): r.squaredNorm() is the mean square.
        const double N = double(cost->samples()) * 6;
        const double sigma2 = r.squaredNorm() * N / std::max(1.0, N - p);
        const Eigen::MatrixXd JtJ = J.transpose() * J * N;
        Eigen::FullPivLU<Eigen::MatrixXd> lu(JtJ);
        if (lu.isInvertible()) {
            const Eigen::MatrixXd cov = lu.inverse() * sigma2;
            for (int k = 0; k < p; ++k) out.se[size_t(k)] = std::sqrt(std::max(0.0, cov(k, k)));
        }
    }
    out.model = apply(base, causes, out.x.data());
    return out;
}

std::vector<FittedValue> fitted_values(const ContactModel& base, const std::vector<std::string>& causes,
                                       const JointFit& f) {
    std::vector<FittedValue> out;
    for (size_t k = 0; k < causes.size(); ++k) {
        const double x = f.x[k], se = f.se[k];
        const std::string& c = causes[k];
        // Logarithmic coordinates: the value's standard error is value * se(x).
        if (c == "contact_stiffness") {
            const double v = base.settings.normal.stiffness * std::exp(x);
            out.push_back(value("stiffness", "N/m^" + std::to_string(base.settings.normal.exponent).substr(0, 4), v, v * se));
        } else if (c == "contact_damping") {
            const double v = base.settings.normal.damping * std::exp(x);
            const bool hunt_crossley = base.settings.normal.model == sim::contact::NormalModel::HuntCrossley;
            out.push_back(value("damping", hunt_crossley ? "s/m" : "N s/m", v, v * se));
        } else if (c == "contact_friction") {
            const double mu_s = base.settings.friction.mu_static * std::exp(x);
            const double mu_k = base.settings.friction.mu_kinetic * std::exp(x);
            out.push_back(value("mu_static", "", mu_s, mu_s * se));
            out.push_back(value("mu_kinetic", "", mu_k, mu_k * se));
        }
    }
    return out;
}

// The ground offset's signature: where a trial ends at rest, the measured
// body lies higher or lower than the simulated one by the offset, whatever
// the contact did before. The median over such trials (robust to a trial
// that settled on another face), its standard error from the spread.
FittedValue rest_offset(const ContactScene& scene, const ContactModel& model, const std::vector<PoseRecord>& records,
                        int threads) {
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
    for (const Shape& s : scene.shapes)
        if (s.body == 0 && s.kind == ShapeKind::HalfSpace) {
            normal = s.rotation.col(2);
            break;
        }
    std::vector<double> offsets(records.size(), std::numeric_limits<double>::quiet_NaN());
    // At rest: moving slower than 5 % of the size per second over the last
    // sample (a tracker's noise alone moves a resting cube's estimate by a
    // few millimetres per second).
    const double still = 0.05 * scene.length_scale;
    parallel_for(records.size(), threads, [&](size_t i) {
        const PoseRecord& r = records[i];
        const size_t n = r.samples.size();
        const double dt = r.samples[n - 1].t - r.samples[n - 2].t;
        if ((r.samples[n - 1].p - r.samples[n - 2].p).norm() > still * dt) return;
        const Rollout roll = roll_out(scene, model, r);
        if (roll.diverged || (roll.positions[n - 1] - roll.positions[n - 2]).norm() > still * dt) return;
        offsets[i] = (r.samples[n - 1].p - roll.positions[n - 1]).dot(normal);
    });
    offsets.erase(std::remove_if(offsets.begin(), offsets.end(), [](double x) { return std::isnan(x); }), offsets.end());
    FittedValue v{"ground_offset", "m", std::numeric_limits<double>::quiet_NaN(), 0, {}};
    if (offsets.size() < 2) return v;
    auto median = [](std::vector<double> x) {
        std::nth_element(x.begin(), x.begin() + long(x.size() / 2), x.end());
        return x[x.size() / 2];
    };
    const double m = median(offsets);
    std::vector<double> deviation;
    for (double x : offsets) deviation.push_back(std::abs(x - m));
    v.value = model.ground_offset + m;
    v.standard_error = 1.4826 * median(deviation) * std::sqrt(M_PI / 2 / double(offsets.size()));
    std::ostringstream note;
    note.precision(3);
    note << "resting height off by " << m * 1e3 << " mm (median of " << offsets.size() << " trials ending at rest)";
    v.method = note.str();
    return v;
}

std::string describe(const PoseError& e) {
    std::ostringstream s;
    s.precision(3);
    s << e.position << " % / " << e.rotation << " deg";
    return s.str();
}

}  // namespace

ContactFit fit_contact(const ContactScene& scene, const ContactModel& start, const std::vector<PoseRecord>& fit,
                       const std::vector<PoseRecord>& validation, const ContactFitOptions& options) {
    if (!scene.model) fail("no model");
    free_joint(scene);
    if (fit.empty() || validation.empty()) fail("contact calibration needs fit and validation trials");
    if (std::none_of(scene.shapes.begin(), scene.shapes.end(), [&](const Shape& s) { return s.body == scene.body; }))
        fail("the measured body '" + scene.model->bodies[size_t(scene.body)].name + "' has no collision shape");
    for (const std::string& c : options.causes) knob(c);
    if (std::find(options.causes.begin(), options.causes.end(), "contact_damping") != options.causes.end() &&
        !(start.settings.normal.damping > 0))
        fail("contact_damping scales the start model's damping, which is zero: give it a first value");

    auto say = [&](const std::string& m) {
        if (options.progress) options.progress(m);
    };
    ContactFit out;
    out.model = start;
    out.baseline_fit = pose_error(scene, start, fit, options.threads);
    out.baseline_validation = pose_error(scene, start, validation, options.threads);
    out.rollouts = int(fit.size() + validation.size());
    if (out.baseline_fit.diverged || out.baseline_validation.diverged)
        fail("the start model's rollouts diverge (" +
             std::to_string(out.baseline_fit.diverged + out.baseline_validation.diverged) +
             " trials): a smaller step or a softer contact first");
    say("contact baseline: fit " + describe(out.baseline_fit) + ", validation " + describe(out.baseline_validation));

    const double w = options.rotation_weight;
    // Causes refitted by least squares at every step, their coordinates
    // against `base`; the ground offset, measured by its own signature, is
    // folded into `base` instead.
    std::vector<std::string> named, remaining = options.causes;
    std::vector<double> named_x;
    ContactModel base = start;
    FittedValue offset_value;
    PoseError current_fit = out.baseline_fit, current_validation = out.baseline_validation;
    while (!remaining.empty()) {
        // Screen each candidate alone on top of what is named, then refit
        // the winner jointly with the named ones.
        std::string best;
        double best_score = current_fit.score(w), best_x = 0;
        FittedValue best_offset;
        for (const std::string& c : remaining) {
            double candidate_score = std::numeric_limits<double>::infinity(), candidate_x = 0;
            PoseError candidate_error;
            FittedValue offset;
            auto consider = [&](double x) {
                const PoseError e = pose_error(scene, apply(out.model, {c}, &x), fit, options.threads);
                out.rollouts += int(fit.size());
                if (!e.diverged && e.score(w) < candidate_score) candidate_score = e.score(w), candidate_x = x, candidate_error = e;
            };
            if (c == "ground_offset") {
                offset = rest_offset(scene, out.model, fit, options.threads);
                out.rollouts += int(fit.size());
                if (std::isfinite(offset.value)) consider((offset.value - out.model.ground_offset) * 1e3);
            } else {
                const Knob& k = knob(c);
                for (double x = k.grid_from; x <= k.grid_to + 1e-9; x += k.grid_step) consider(x);
            }
            say("  candidate " + c + ": fit " + describe(candidate_error));
            if (candidate_score < best_score) best_score = candidate_score, best = c, best_x = candidate_x, best_offset = offset;
        }
        if (best.empty()) {
            out.notes.push_back("no remaining candidate lowers the fit error");
            break;
        }
        ContactModel next_base = base;
        std::vector<std::string> causes = named;
        std::vector<double> x0 = named_x;
        if (best == "ground_offset") {
            next_base = apply(base, {best}, &best_x);
        } else {
            // The candidate's coordinate is the same against `base` (it
            // changes a quantity no named cause touches).
            causes.push_back(best);
            x0.push_back(best_x);
        }
        JointFit joint = fit_jointly(scene, next_base, causes, fit, options, out.rollouts, x0);
        PoseError e_fit = pose_error(scene, joint.model, fit, options.threads);
        // Least squares weighs large errors more than the mean scored here:
        // keep the screened point when the refit scores worse by the mean.
        if (e_fit.diverged || e_fit.score(w) > best_score) {
            joint.x = x0;
            joint.model = apply(next_base, causes, x0.data());
            e_fit = pose_error(scene, joint.model, fit, options.threads);
        }
        const PoseError e_val = pose_error(scene, joint.model, validation, options.threads);
        out.rollouts += int(fit.size() + validation.size());
        if (e_val.diverged || !(e_val.score(w) < current_validation.score(w) * (1 - options.min_validation_gain))) {
            std::ostringstream note;
            note << best << " lowers the fit error (" << describe(current_fit) << " -> " << describe(e_fit)
                 << ") but not the validation error enough (" << describe(current_validation) << " -> "
                 << describe(e_val) << ", needs " << options.min_validation_gain * 100 << " %): not named";
            out.notes.push_back(note.str());
            say(note.str());
            break;
        }
        if (best == "ground_offset") offset_value = best_offset;
        ContactStep step;
        step.cause = best;
        step.parameters = fitted_values(next_base, causes, joint);
        if (!offset_value.name.empty()) step.parameters.push_back(offset_value);
        step.fit = e_fit, step.validation = e_val;
        step.evidence = "fit " + describe(current_fit) + " -> " + describe(e_fit) + "; validation " +
                        describe(current_validation) + " -> " + describe(e_val);
        if (best == "ground_offset") step.evidence += "; " + best_offset.method;
        say("named " + best + ": " + step.evidence);
        out.steps.push_back(step);
        base = next_base;
        named = causes;
        named_x = joint.x;
        out.model = joint.model;
        current_fit = e_fit, current_validation = e_val;
        remaining.erase(std::find(remaining.begin(), remaining.end(), best));
    }
    return out;
}

}  // namespace mbx::calibration
