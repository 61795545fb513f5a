#include "calibration/simulation/nonlinear_fit.h"
#include "calibration/simulation/quiet_solve.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <sstream>

#include "calibration/cause_table.h"
#include "calibration/identification/closed_chain.h"
#include "calibration/simulation/fit_scalar.h"
#include "calibration/records/filters.h"
#include "calibration/simulation/replay.h"
#include "core/finding.h"
#include "core/heartbeat.h"
#include "core/text_format.h"
#include "sim/forward_dynamics.h"
#include "sim/joint_forces.h"

namespace mbx::calibration {

namespace {

[[noreturn]] void refuse(const std::string& what) {
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("calibration"), what);
}

double scalar_of(double x) { return x; }
template <class T, int N> double scalar_of(const ceres::Jet<T, N>& x) { return x.a; }

std::vector<std::string> parameters_of(const Candidate& c) {
    const CauseKind& k = c.kind();
    return k.subject == CauseSubject::Transmission ? k.parameters : c.parameters;
}

}  // namespace

bool simulation_supports(const std::string& cause) {
    for (const CauseKind& k : cause_table())
        if (cause == k.name) return k.simulated;
    return false;
}

// One window: a stretch of a record simulated from its measured start.
struct Window {
    const Record* record = nullptr;
    size_t k0 = 0, n = 0;           // first sample and samples (outputs at k0+1 .. k0+n-1)
    Eigen::VectorXd q0, v0;          // measured start (loops closed)
    // How the start moves with the fitted corrections of the measured
    // coordinates' positions and rates (nv x outputs: the selection on a
    // tree, the loop's velocity map on a closed chain).
    Eigen::MatrixXd G;
    std::vector<std::vector<double>> target;  // per output: measured positions at k0+1..
    // Per elastic cause: the filtered effort, its rate and the filtered
    // acceleration at k0 (the spring's load at the start).
    std::vector<double> effort0, effort_rate0, acc0;
};

struct SimulationProblem::Impl {
    sim::Model model;
    SimulationFitOptions options;
    std::vector<CauseStart> causes;
    std::vector<CauseId> causes_id;  // each cause's table entry
    std::vector<int> offset;  // first parameter of each cause
    int parameters = 0;
    std::vector<int> out_dof;       // measured coordinates (outputs), in order
    std::vector<double> out_scale;  // their weights' inverse
    std::vector<int> actuated;      // coordinates with a recorded effort
    std::vector<double> sign_speed; // per coordinate, Coulomb's smoothing speed
    std::vector<Window> windows;
    double dt = 0;
    double reference_norm = 0;
    int residuals = 0;

    int residuals_of(const Window& w) const { return int(out_dof.size()) * int(w.n - 1); }

    // The recorded effort on coordinate `dof` at sample position `at` of the record (linear).
    template <class S> S effort_at(const Window& w, int dof, double at, const S& delay_samples) const {
        const Signal* s = w.record->find(Quantity::Effort, dof);
        if (!s) return S(0);
        const std::vector<double>& v = s->values;
        const S pos = S(at) - delay_samples;
        double base = std::floor(scalar_of(pos));
        base = std::clamp(base, 0.0, double(v.size() - 2));
        const size_t i = size_t(base);
        S frac = pos - S(base);
        if (scalar_of(frac) > 1) frac = S(1);
        if (scalar_of(frac) < 0) frac = S(0);
        return (S(1) - frac) * v[i] + frac * v[i + 1];
    }

    // Simulates window w at parameters theta; residuals (simulated - measured) / scale.
    // `start`: the window's start corrections (outputs' positions, then rates), or null.
    template <class S> bool simulate(const Window& w, const S* theta, const S* start, S* out) const;
    int start_size() const { return options.fit_start ? 2 * int(out_dof.size()) : 0; }

    // The first evaluation that could not be completed, in words: what became
    // non-finite, or the error that ended it, and where. A solve that fails
    // on it says this rather than Ceres' "evaluation failed".
    mutable std::mutex failure_mutex;
    mutable std::string first_failure;
    void note_failure(const std::string& what) const {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (first_failure.empty()) first_failure = what;
    }
};

// An elastic transmission in a simulated window.
struct Elastic {
    int dof = -1, q_index = -1, cause = -1;
    bool dead_band = false;
    // Backlash: the stops' stiffness and damping (a 1 ms time constant,
    // critically damped, on the motor and link inertias in series).
    double stop_stiffness = 0, stop_damping = 0;
};

// The stops' rate (rad/s): stiff against the motion, followable by RK4 at half a millisecond.
constexpr double kStopRate = 1000;

template <class S>
bool SimulationProblem::Impl::simulate(const Window& w, const S* theta, const S* start, S* out) const {
    using std::isfinite;
    sim::ModelT<S> m = model.template cast<S>();
    const int nv = m.nv, nq = m.nq;
    std::vector<S> gain(size_t(nv), S(1)), delay(size_t(nv), S(0)), spring(size_t(nv), S(0));
    std::vector<Elastic> elastic;
    std::vector<std::array<S, 3>> elastic_p;  // k, c, motor inertia
    for (size_t c = 0; c < causes.size(); ++c) {
        const Candidate& k = causes[c].candidate;
        const S* p = theta + offset[c];
        const CauseId id = causes_id[c];
        if (id == CauseId::MassError) {
            S scale, shift[3], change[6];
            k.body_correction(p, scale, shift, change);
            sim::Inertia<S>& I = m.bodies[size_t(k.body)].inertia;
            I = corrected_inertia(I, scale, shift, change);
            continue;
        }
        sim::JointDynamicsT<S>& jd = m.joints[size_t(k.joint)].dynamics;
        const size_t dof = size_t(k.dof);
        // (What each cause adds to the model; the table's `simulated` says which are here.)
        if (id == CauseId::ViscousFriction) {
            jd.damping += p[0];
            if (jd.asymmetric) jd.damping_negative += p[0];
        } else if (id == CauseId::CoulombFriction) {
            if (!(scalar_of(jd.coulomb_velocity) > 0)) jd.coulomb_velocity = S(sign_speed[dof]);
            jd.coulomb += p[0];
            if (jd.asymmetric) jd.coulomb_negative += p[0];
        } else if (id == CauseId::EffortOffset) {
            jd.offset += p[0];
        } else if (id == CauseId::Armature) {
            jd.armature += p[0];
        } else if (id == CauseId::PositionDependentEffort) {
            spring[dof] += p[0];
        } else if (id == CauseId::ActuatorGain) {
            gain[dof] *= S(1) - p[0];
        } else if (id == CauseId::Delay) {
            delay[dof] += p[0] / dt;
        } else if (id == CauseId::Compliance) {
            elastic.push_back({k.dof, k.q_index, int(c)});
            elastic_p.push_back({p[0], p[1], p[2]});
        } else if (id == CauseId::Backlash) {
            Elastic e{k.dof, k.q_index, int(c), true};
            // From the starting motor inertia: the stops are a fixed part of the law, not fitted.
            const double link = model.joints[size_t(k.joint)].reference_inertia, motor = causes[c].values[1];
            const double reduced = motor > 0 && link > 0 ? motor * link / (motor + link) : std::max(motor, link);
            e.stop_stiffness = reduced * kStopRate * kStopRate;
            e.stop_damping = 2 * reduced * kStopRate;
            elastic.push_back(e);
            elastic_p.push_back({p[0], S(0), p[1]});
        }
    }
    const size_t ne = elastic.size();
    for (size_t e = 0; e < ne; ++e)
        if (!(scalar_of(elastic_p[e][0]) > 0) || !(scalar_of(elastic_p[e][2]) > 0)) return false;
    // The torque through a transmission at deflection dq and its rate.
    auto transmitted = [&](size_t e, const S& dq, const S& dqd) -> S {
        if (!elastic[e].dead_band) return elastic_p[e][0] * dq + elastic_p[e][1] * dqd;
        const S half = elastic_p[e][0] / S(2);
        // In the band nothing passes; against a stop, a stiff spring-damper that never pulls.
        if (dq > half) {
            const S f = elastic[e].stop_stiffness * (dq - half) + elastic[e].stop_damping * dqd;
            return f > S(0) ? f : S(0);
        }
        if (dq < -half) {
            const S f = elastic[e].stop_stiffness * (dq + half) + elastic[e].stop_damping * dqd;
            return f < S(0) ? f : S(0);
        }
        return S(0);
    };

    // State: q (nq), v (nv), then each elastic transmission's motor angle and rate.
    const int n = nq + nv + 2 * int(ne);
    using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
    Vec x(n);
    std::vector<int> q_of_v(static_cast<size_t>(nv), 0);
    for (const sim::JointT<S>& j : m.joints) q_of_v[size_t(j.v_index)] = j.q_index;
    for (int i = 0; i < nq; ++i) x[i] = S(w.q0[i]);
    for (int i = 0; i < nv; ++i) x[nq + i] = S(w.v0[i]);
    if (start) {
        const Eigen::Index no = w.G.cols();
        for (int i = 0; i < nv; ++i)
            for (Eigen::Index o = 0; o < no; ++o) {
                if (w.G(i, o) == 0) continue;
                x[q_of_v[size_t(i)]] += w.G(i, o) * start[o];
                x[nq + i] += w.G(i, o) * start[no + o];
            }
    }
    for (size_t e = 0; e < ne; ++e) {
        const S& k = elastic_p[e][0];
        const S& jm = elastic_p[e][2];
        // The encoder and the drive are on the motor side: the measured start
        // is the motor's; the link lags by the spring's deflection under its load.
        const int d = elastic[e].dof, qi = elastic[e].q_index;
        x[nq + nv + 2 * int(e)] = x[qi];
        x[nq + nv + 2 * int(e) + 1] = x[nq + d];
        if (elastic[e].dead_band) {
            // Against the stop the load pushes it to (the band's middle at no load).
            const S load = S(w.effort0[e]) - jm * w.acc0[e];
            const double side = scalar_of(load) > 0 ? 1 : scalar_of(load) < 0 ? -1 : 0;
            x[qi] = x[qi] - S(side) * (k / S(2)) - load / elastic[e].stop_stiffness;
            continue;
        }
        x[qi] = x[qi] - (S(w.effort0[e]) - jm * w.acc0[e]) / k;
        x[nq + d] = x[nq + d] - S(w.effort_rate0[e]) / k;
    }
    sim::DataT<S> data(m);
    const double h = 1.0 / options.substeps;  // in samples
    const double step_seconds = dt * h;

    auto derivative = [&](double at, const Vec& s, Vec& ds) {
        for (int i = 0; i < nq; ++i) data.q[i] = s[i];
        for (int i = 0; i < nv; ++i) data.v[i] = s[nq + i];
        sim::passive_forces(m, data, sim::FrictionLaw::Regularised, nullptr, step_seconds);
        data.qfrc_total = data.qfrc_passive;
        for (int dof : actuated)
            data.qfrc_total[dof] += gain[size_t(dof)] * effort_at<S>(w, dof, at, delay[size_t(dof)]);
        for (int i = 0; i < nv; ++i)
            if (scalar_of(spring[size_t(i)]) != 0) data.qfrc_total[i] -= spring[size_t(i)] * s[q_of_v[size_t(i)]];
        ds.resize(n);
        for (size_t e = 0; e < ne; ++e) {
            const int d = elastic[e].dof, qi = elastic[e].q_index;
            const S th = s[nq + nv + 2 * int(e)], om = s[nq + nv + 2 * int(e) + 1];
            // The drive's effort goes to the motor; the link feels the spring and its damper.
            const S drive = data.qfrc_total[d] - data.qfrc_passive[d];
            const S link = transmitted(e, th - s[qi], om - s[nq + d]);
            data.qfrc_total[d] = data.qfrc_passive[d] + link;
            ds[nq + nv + 2 * int(e)] = om;
            ds[nq + nv + 2 * int(e) + 1] = (drive - link) / elastic_p[e][2];
        }
        sim::forward_dynamics(m, data);
        for (int i = 0; i < nv; ++i) ds[q_of_v[size_t(i)]] = s[nq + i];
        for (int i = 0; i < nv; ++i) ds[nq + i] = data.qacc[i];
    };

    Vec k1, k2, k3, k4, tmp;
    double at = double(w.k0);
    S* r = out;
    size_t sample = 1;
    // (where in the record, for a message)
    auto when = [&] { return " at t = " + readable(w.record->t[std::min(w.k0 + sample, w.record->t.size() - 1)]) + " s of " + w.record->path; };
    try {
        for (; sample < w.n; ++sample) {
            heartbeat();  // a cancel throws, and ends this evaluation as a failed one
            for (int sub = 0; sub < options.substeps; ++sub) {
                const S half(step_seconds / 2), full(step_seconds), sixth(step_seconds / 6);
                derivative(at, x, k1);
                tmp = x + half * k1;
                derivative(at + h / 2, tmp, k2);
                tmp = x + half * k2;
                derivative(at + h / 2, tmp, k3);
                tmp = x + full * k3;
                derivative(at + h, tmp, k4);
                x += sixth * (k1 + S(2) * k2 + S(2) * k3 + k4);
                at += h;
            }
            for (size_t o = 0; o < out_dof.size(); ++o) {
                const int d = out_dof[o];
                S y = x[q_of_v[size_t(d)]];
                for (size_t e = 0; e < ne; ++e)
                    if (elastic[e].dof == d) y = x[nq + nv + 2 * int(e)];
                const S res = (y - S(w.target[o][sample - 1])) / S(out_scale[o]);
                if (!isfinite(scalar_of(res))) {
                    const sim::JointT<double>& j = model.joints[size_t(model.dof_joint[size_t(d)])];
                    note_failure("joint '" + j.name + "''s simulated position became " + readable(scalar_of(y)) + when());
                    return false;
                }
                *r++ = res;
            }
        }
    } catch (const Error& e) {
        if (e.status() != MBX_ERROR_CANCELLED) note_failure(e.what() + when());
        return false;
    }
    return true;
}

namespace {

// Ceres' view of one window.
struct WindowCost {
    const SimulationProblem::Impl* problem;
    const Window* window;
    const Heartbeat* heartbeat;  // the run's; Ceres' worker threads have none of their own
    template <class T> bool operator()(T const* const* parameters, T* residuals) const {
        if (heartbeat && heartbeat->cancelled()) return false;
        return problem->simulate<T>(*window, parameters[0], problem->options.fit_start ? parameters[1] : nullptr,
                                    residuals);
    }
};

ceres::CostFunction* cost_of(const SimulationProblem::Impl* p, const Window* w) {
    auto* f = new ceres::DynamicAutoDiffCostFunction<WindowCost, kFitStride>(new WindowCost{p, w, current_heartbeat()});
    f->AddParameterBlock(p->parameters);
    if (p->options.fit_start) f->AddParameterBlock(p->start_size());
    f->SetNumResiduals(p->residuals_of(*w));
    return f;
}

// The `want` windows (first samples, `len` long) holding the most reversals
// of `dof`'s filtered effort in their middle (from 30 to 70 % of the window:
// a clear load at the start, whose deflection the start takes, and time after
// the reversal for the simulation to show it), in record order; windows without one
// fill up evenly. A reversal counts when the effort passes from beyond -5 %
// of its RMS to beyond +5 % or back, so noise about zero is not one.
std::vector<std::pair<const Record*, size_t>> windows_at_reversals(const std::vector<std::pair<const Record*, size_t>>& all,
                                                                   size_t len, int dof, double dt, double cutoff,
                                                                   size_t want) {
    struct Load {
        std::vector<double> effort;  // filtered
        double band = 0;             // 5 % of its RMS
    };
    std::map<const Record*, Load> loads;
    for (const auto& [r, k0] : all) {
        if (loads.count(r)) continue;
        Load& l = loads[r];
        if (const Signal* e = r->find(Quantity::Effort, dof)) l.effort = low_pass(e->values, dt, cutoff);
        double sum = 0;
        for (double x : l.effort) sum += x * x;
        if (!l.effort.empty()) l.band = 0.05 * std::sqrt(sum / double(l.effort.size()));
    }
    std::vector<int> score(all.size(), 0);
    for (size_t i = 0; i < all.size(); ++i) {
        const Load& l = loads[all[i].first];
        const std::vector<double>& f = l.effort;
        const size_t k0 = all[i].second;
        // The start's deflection is the load's: a clear one.
        if (f.empty() || std::fabs(f[k0]) < l.band) continue;
        int side = f[k0] > 0 ? 1 : -1;
        for (size_t k = k0 + (3 * len) / 10, end = std::min(f.size(), k0 + (7 * len) / 10); k < end; ++k) {
            const int now = f[k] > l.band ? 1 : f[k] < -l.band ? -1 : 0;
            if (now != 0 && now != side) ++score[i];
            if (now != 0) side = now;
        }
    }
    std::vector<size_t> order(all.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return score[a] > score[b]; });
    std::vector<char> take(all.size(), 0);
    size_t taken = 0;
    for (size_t i : order)
        if (taken < want && score[i] > 0) take[i] = 1, ++taken;
    // Too few reversals: the rest spread evenly over the windows not taken.
    std::vector<size_t> rest;
    for (size_t i = 0; i < all.size(); ++i)
        if (!take[i]) rest.push_back(i);
    const size_t more = want - taken;
    for (size_t i = 0; i < more && !rest.empty(); ++i) take[rest[i * rest.size() / more]] = 1;
    std::vector<std::pair<const Record*, size_t>> chosen;
    for (size_t i = 0; i < all.size(); ++i)
        if (take[i]) chosen.push_back(all[i]);
    return chosen;
}

}  // namespace

SimulationProblem::SimulationProblem(const sim::Model& m, const std::vector<const Record*>& records,
                                     const std::vector<CauseStart>& causes, const SimulationFitOptions& options)
    : impl_(std::make_unique<Impl>()) {
    Impl& P = *impl_;
    P.model = m;
    P.options = options;
    P.causes = causes;
    if (options.horizon <= 0 || options.max_windows < 1 || options.substeps < 1)
        refuse("the simulation fit needs a positive horizon, at least one window and one step per sample");
    for (const sim::JointT<double>& j : m.joints)
        if (j.nv() != 1) refuse("the simulation fit handles 1-dof joints only; joint '" + j.name + "' has " + std::to_string(j.nv()));
    if (records.empty()) refuse("the simulation fit needs at least one record");
    for (const CauseStart& c : causes) {
        if (!simulation_supports(c.candidate.cause))
            refuse("the simulation fit cannot carry " + c.candidate.cause + " yet");
        const CauseKind& kind = c.candidate.kind();
        const size_t np = parameters_of(c.candidate).size();
        if (c.values.size() != np)
            refuse(c.candidate.cause + " needs " + std::to_string(np) + " starting values, got " + std::to_string(c.values.size()));
        if (kind.subject == CauseSubject::Body ? (c.candidate.body <= 0 || c.candidate.body >= m.body_count())
                                               : (c.candidate.dof < 0 || c.candidate.dof >= m.nv))
            refuse(c.candidate.cause + " has no subject in the model");
        if (kind.elastic && !m.closures.empty())
            refuse(c.candidate.cause + " in a closed loop is not carried by the simulation fit (joint '" +
                   m.joints[size_t(c.candidate.joint)].name + "')");
        P.causes_id.push_back(kind.id);
        P.offset.push_back(P.parameters);
        P.parameters += int(np);
    }
    if (P.parameters == 0) refuse("the simulation fit has no parameter to refine");

    const Record& first = *records.front();
    P.dt = first.sample_period();
    for (const Record* r : records)
        if (std::fabs(r->sample_period() - P.dt) > 1e-6 * P.dt) refuse("the simulation fit needs one sample period in all records");
    for (const Signal& s : first.signals) {
        if (s.quantity == Quantity::Position) P.out_dof.push_back(s.dof);
        if (s.quantity == Quantity::Effort) P.actuated.push_back(s.dof);
    }
    if (P.out_dof.empty()) refuse(first.path + ": no measured position to compare the simulation with");
    for (const CauseStart& c : causes)
        if (c.candidate.kind().needs_effort &&
            std::find(P.actuated.begin(), P.actuated.end(), c.candidate.dof) == P.actuated.end())
            refuse(c.candidate.cause + " on joint '" + m.joints[size_t(c.candidate.joint)].name + "', which has no recorded effort");

    // Coulomb's smoothing speed: 1 % of each coordinate's RMS speed, as the linear fit's column.
    const double cutoff = first.filter_cutoff();
    P.sign_speed.assign(size_t(m.nv), 1e-3);
    std::vector<double> sum(size_t(m.nv), 0.0);
    size_t count = 0;
    for (const Record* r : records) {
        for (const Signal& s : r->signals) {
            if (s.quantity != Quantity::Position) continue;
            const std::vector<double> v = derivative(low_pass(s.values, P.dt, cutoff), P.dt);
            for (double x : v) sum[size_t(s.dof)] += x * x;
        }
        count += r->t.size();
    }
    for (int d = 0; d < m.nv; ++d)
        if (sum[size_t(d)] > 0) P.sign_speed[size_t(d)] = std::max(1e-9, 0.01 * std::sqrt(sum[size_t(d)] / double(count)));

    // Windows: as many whole ones as the records hold, thinned evenly to max_windows.
    const size_t len = std::max<size_t>(3, size_t(std::llround(options.horizon / P.dt)) + 1);
    const size_t margin = size_t(std::ceil(0.02 / P.dt));  // the start's local fit reaches 10 ms
    std::vector<std::pair<const Record*, size_t>> all;
    for (const Record* r : records)
        for (size_t k0 = margin; k0 + len + margin <= r->t.size(); k0 += len - 1) all.push_back({r, k0});
    if (all.empty()) refuse("records too short for one simulation window of " + std::to_string(options.horizon) + " s");
    std::vector<std::pair<const Record*, size_t>> chosen;
    const size_t want = std::min(all.size(), size_t(options.max_windows));
    if (options.reversal_dof >= 0) {
        chosen = windows_at_reversals(all, len, options.reversal_dof, P.dt, cutoff, want);
    } else {
        for (size_t i = 0; i < want; ++i) chosen.push_back(all[i * all.size() / want]);
    }

    std::vector<int> elastic_dofs;
    for (const CauseStart& c : causes)
        if (c.candidate.kind().elastic) elastic_dofs.push_back(c.candidate.dof);
    struct Filtered {
        std::vector<double> effort, effort_rate, acc;
    };
    std::vector<std::vector<Filtered>> filtered(records.size());
    for (size_t ri = 0; ri < records.size(); ++ri)
        for (int d : elastic_dofs) {
            const Record& r = *records[ri];
            Filtered f;
            const Signal* e = r.find(Quantity::Effort, d);
            const Signal* q = r.find(Quantity::Position, d);
            if (!e || !q) refuse(r.path + ": compliance needs the joint's measured position and effort");
            f.effort = low_pass(e->values, P.dt, cutoff);
            f.effort_rate = derivative(f.effort, P.dt);
            f.acc = derivative(derivative(low_pass(q->values, P.dt, cutoff), P.dt), P.dt);
            filtered[ri].push_back(std::move(f));
        }

    std::vector<char> measured(size_t(m.nv), 0);
    for (int od : P.out_dof) measured[size_t(od)] = 1;
    ClosedChain chain = closed_chain(m, measured);
    sim::Data d(m);
    const ReplayAdjustments none(m.nv);
    P.out_scale.assign(P.out_dof.size(), 0.0);
    std::vector<double> motion(P.out_dof.size(), 0.0);
    size_t motion_n = 0;
    for (const auto& [r, k0] : chosen) {
        Window w;
        w.record = r, w.k0 = k0, w.n = len;
        measured_start_state(m, d, *r, k0, none);
        w.q0 = d.q, w.v0 = d.v;
        w.G = Eigen::MatrixXd::Zero(m.nv, Eigen::Index(P.out_dof.size()));
        if (chain.active()) {
            Eigen::VectorXd qd = d.v, qdd = Eigen::VectorXd::Zero(m.nv);
            Eigen::MatrixXd G;
            chain.close(m, d, qd, qdd, G);
            for (size_t o = 0; o < P.out_dof.size(); ++o) {
                const size_t col = size_t(std::find(chain.independent.begin(), chain.independent.end(), P.out_dof[o]) -
                                          chain.independent.begin());
                w.G.col(Eigen::Index(o)) = G.col(Eigen::Index(col));
            }
        } else {
            for (size_t o = 0; o < P.out_dof.size(); ++o) w.G(P.out_dof[o], Eigen::Index(o)) = 1;
        }
        for (size_t o = 0; o < P.out_dof.size(); ++o) {
            const Signal* s = r->find(Quantity::Position, P.out_dof[o]);
            if (!s) refuse(r->path + ": every record needs the same measured positions");
            w.target.emplace_back(s->values.begin() + std::ptrdiff_t(k0 + 1), s->values.begin() + std::ptrdiff_t(k0 + len));
            for (size_t k = k0 + 1; k < k0 + len; ++k) motion[o] += std::pow(s->values[k] - s->values[k0], 2);
        }
        motion_n += len - 1;
        const size_t ri = size_t(std::find(records.begin(), records.end(), r) - records.begin());
        for (const Filtered& f : filtered[ri]) {
            w.effort0.push_back(f.effort[k0]);
            w.effort_rate0.push_back(f.effort_rate[k0]);
            w.acc0.push_back(f.acc[k0]);
        }
        P.windows.push_back(std::move(w));
    }
    for (size_t o = 0; o < P.out_dof.size(); ++o) {
        P.out_scale[o] = std::sqrt(motion[o] / double(std::max<size_t>(1, motion_n)));
        if (!(P.out_scale[o] > 0)) P.out_scale[o] = 1;
    }
    // ||motion since each start|| in the residuals' weights: every output's weighted RMS is 1.
    P.reference_norm = std::sqrt(double(motion_n * P.out_dof.size()));
    for (const Window& w : P.windows) P.residuals += P.residuals_of(w);
}

SimulationProblem::~SimulationProblem() = default;

int SimulationProblem::parameter_count() const { return impl_->parameters; }
int SimulationProblem::residual_count() const { return impl_->residuals; }
int SimulationProblem::window_count() const { return int(impl_->windows.size()); }

std::vector<double> SimulationProblem::start() const {
    std::vector<double> theta;
    for (const CauseStart& c : impl_->causes) theta.insert(theta.end(), c.values.begin(), c.values.end());
    return theta;
}

double SimulationProblem::error_percent(const Eigen::VectorXd& r) const { return 100 * r.norm() / impl_->reference_norm; }

bool SimulationProblem::evaluate(const std::vector<double>& theta, Eigen::VectorXd& residuals, Eigen::MatrixXd* jacobian) const {
    const Impl& P = *impl_;
    if (int(theta.size()) != P.parameters) refuse("evaluate: wrong number of parameters");
    residuals.resize(P.residuals);
    if (jacobian) jacobian->resize(P.residuals, P.parameters);
    int row = 0;
    for (const Window& w : P.windows) {
        std::unique_ptr<ceres::CostFunction> f(cost_of(&P, &w));
        const int nr = P.residuals_of(w);
        const std::vector<double> zero(size_t(P.start_size()), 0.0);
        const double* params[] = {theta.data(), zero.data()};
        // Ceres writes Jacobians row-major.
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(nr, P.parameters);
        double* jacs[] = {J.data(), nullptr};
        if (!f->Evaluate(params, residuals.data() + row, jacobian ? jacs : nullptr)) return false;
        if (jacobian) jacobian->middleRows(row, nr) = J;
        row += nr;
    }
    return true;
}

SimulationFit SimulationProblem::solve(std::vector<double> theta) const {
    const Impl& P = *impl_;
    const auto t0 = std::chrono::steady_clock::now();
    if (theta.empty()) theta = start();
    if (int(theta.size()) != P.parameters) refuse("solve: wrong number of parameters");
    {
        // (what failed in an earlier evaluate() or solve() is not this solve's)
        const std::lock_guard<std::mutex> lock(P.failure_mutex);
        P.first_failure.clear();
    }
    SimulationFit out;
    out.windows = int(P.windows.size());
    out.residuals = P.residuals;
    Eigen::VectorXd r;
    if (!evaluate(theta, r))
        refuse("the simulation diverges at the starting parameters" +
               (P.first_failure.empty() ? std::string() : ": " + P.first_failure));
    out.initial_error = error_percent(r);

    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    const int ns = P.start_size();
    std::vector<std::vector<double>> starts(P.windows.size(), std::vector<double>(size_t(ns), 0.0));
    for (size_t i = 0; i < P.windows.size(); ++i) {
        if (ns > 0)
            problem.AddResidualBlock(cost_of(&P, &P.windows[i]), nullptr, theta.data(), starts[i].data());
        else
            problem.AddResidualBlock(cost_of(&P, &P.windows[i]), nullptr, theta.data());
    }
    // Physical bounds (the table's, calibration/cause_table.cpp): dissipation,
    // inertia and stiffness stay positive, a gain and a mass stay above a tenth.
    for (size_t c = 0; c < P.causes.size(); ++c) {
        const Candidate& k = P.causes[c].candidate;
        const auto bounds = k.kind().simulation_bounds;
        if (!bounds) continue;
        const size_t np = parameters_of(k).size();
        for (size_t i = 0; i < np; ++i) {
            const int at = P.offset[c] + int(i);
            double lower = -INFINITY, upper = INFINITY;
            bounds(k, i, theta[size_t(at)], lower, upper);
            if (std::isfinite(lower)) problem.SetParameterLowerBound(theta.data(), at, lower);
            if (std::isfinite(upper)) problem.SetParameterUpperBound(theta.data(), at, upper);
        }
    }
    if (P.options.hold_parameters) {
        problem.SetParameterBlockConstant(theta.data());
    } else if (!P.options.held.empty()) {
        problem.SetManifold(theta.data(), new ceres::SubsetManifold(P.parameters, P.options.held));
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = P.options.max_iterations;
    so.num_threads = std::max(1, P.options.threads);
    so.function_tolerance = 1e-10;
    so.parameter_tolerance = 1e-10;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    solve_quietly(so, &problem, &summary);
    out.iterations = int(summary.iterations.size());
    out.converged = summary.termination_type == ceres::CONVERGENCE;
    out.report = summary.BriefReport();
    out.note = solver_note(summary, "the simulation fit");
    if (summary.termination_type == ceres::FAILURE && !P.first_failure.empty())
        out.note = "the simulation fit failed: " + P.first_failure;

    // Standard errors from the Jacobian at the optimum. A window's residuals
    // are one simulated trajectory, strongly correlated along it (an error in
    // its start drifts through all of them), so (J^T J)^-1 s^2, which takes
    // them as independent, would be several times too small; the windows are
    // independent of each other, so the covariance is the cluster-robust
    // (J^T J)^-1 (sum_w J_w^T r_w r_w^T J_w) (J^T J)^-1 over windows.
    // The fitted starts are parameters too: the columns of the full Jacobian.
    const Eigen::Index nw = Eigen::Index(P.windows.size()), np = P.parameters, nt = np + nw * ns;
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(P.residuals, nt);
    r.resize(P.residuals);
    bool ok = true;
    int row = 0;
    for (Eigen::Index i = 0; i < nw && ok; ++i) {
        const Window& w = P.windows[size_t(i)];
        std::unique_ptr<ceres::CostFunction> f(cost_of(&P, &w));
        const int nr = P.residuals_of(w);
        using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
        RowMajor Jt(nr, np), Js(nr, std::max(ns, 1));
        const double* params[] = {theta.data(), starts[size_t(i)].data()};
        double* jacs[] = {Jt.data(), Js.data()};
        ok = f->Evaluate(params, r.data() + row, jacs);
        J.block(row, 0, nr, np) = Jt;
        if (ns > 0) J.block(row, np + i * ns, nr, ns) = Js;
        row += nr;
    }
    std::vector<double> se(size_t(P.parameters), NAN);
    if (ok) {
        out.final_error = error_percent(r);
        // Columns scaled to unit norm first: a stiffness, an inertia and a
        // start's rate differ by eight orders, which would pass for rank loss.
        Eigen::VectorXd scale = J.colwise().norm().transpose();
        for (Eigen::Index i = 0; i < nt; ++i) scale[i] = scale[i] > 0 ? 1 / scale[i] : 1;
        J = J * scale.asDiagonal();
        const Eigen::MatrixXd JtJ = J.transpose() * J;
        Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(JtJ);
        if (cod.rank() == nt) {
            Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(nt, nt);
            row = 0;
            for (const Window& w : P.windows) {
                const int nr = P.residuals_of(w);
                const Eigen::VectorXd g = J.middleRows(row, nr).transpose() * r.segment(row, nr);
                meat += g * g.transpose();
                row += nr;
            }
            const double dof_ratio = double(nw) > double(np + ns) ? double(nw) / double(nw - np - ns) : 1.0;
            const Eigen::MatrixXd inv = cod.pseudoInverse();
            const Eigen::MatrixXd cov = dof_ratio * scale.asDiagonal() * (inv * meat * inv) * scale.asDiagonal();
            for (int i = 0; i < P.parameters; ++i) se[size_t(i)] = std::sqrt(std::max(0.0, cov(i, i)));
        }
    } else {
        out.final_error = NAN;
    }
    for (size_t c = 0; c < P.causes.size(); ++c) {
        std::vector<Estimate> est;
        const std::vector<std::string> names = parameters_of(P.causes[c].candidate);
        for (size_t i = 0; i < names.size(); ++i)
            est.push_back({names[i], theta[size_t(P.offset[c]) + i], se[size_t(P.offset[c]) + i]});
        out.parameters.push_back(std::move(est));
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

namespace {

std::string percent(double x) {
    std::ostringstream s;
    s.precision(3);
    s << x << " %";
    return s.str();
}

// The validation error of the causes as they are: only the windows' starts fitted.
double validation_error(const sim::Model& m, const std::vector<const Record*>& validation,
                        const std::vector<CauseStart>& causes, SimulationFitOptions o) {
    o.hold_parameters = true;
    if (causes.empty()) {
        // Nothing to hold: a viscous friction of zero stands for the model as it is.
        return NAN;
    }
    return SimulationProblem(m, validation, causes, o).solve().final_error;
}

}  // namespace

Identification add_transmissions(const sim::Model& m, const std::vector<const Record*>& fit,
                                 const std::vector<const Record*>& validation, const Identification& linear,
                                 const TransmissionOptions& options) {
    Identification out = linear;
    if (!m.closures.empty()) return out;
    for (const SelectedCause& c : linear.causes)
        if (!simulation_supports(c.candidate.cause)) return out;
    for (size_t a = 0; a < linear.causes.size(); ++a) {
        const SelectedCause& arm = linear.causes[a];
        // The motor's inertia is an armature to the rigid model, or an
        // actuator gain where the joint's effort is all inertia (a slide).
        if (!arm.candidate.kind().rigid_motor) continue;
        const bool from_armature = arm.candidate.kind().id == CauseId::Armature;
        const Candidate& where = arm.candidate;
        const std::string& name = m.joints[size_t(where.joint)].name;
        // The model with the linear causes, and with compliance in place of the armature.
        std::vector<CauseStart> base, with;
        for (const SelectedCause& c : out.causes) {
            std::vector<double> v;
            for (const Estimate& e : c.parameters) v.push_back(e.value);
            base.push_back({c.candidate, v});
            if (!(c.candidate.cause == arm.candidate.cause && c.candidate.joint == where.joint)) with.push_back({c.candidate, v});
        }
        Candidate k = where;
        k.cause = cause_name(CauseId::Compliance);
        k.parameters = cause_table()[size_t(CauseId::Compliance)].parameters;
        const double link = m.joints[size_t(where.joint)].reference_inertia;
        if (!(link > 0)) continue;
        const double motor = from_armature ? std::max(arm.parameters[0].value, 1e-3 * link) : 0.3 * link;
        const double reduced = link * motor / (link + motor);
        // Grid of link resonances (Hz), up to what the records resolve.
        const double fs = 1.0 / fit.front()->sample_period();
        double best = INFINITY;
        std::vector<double> start;
        SimulationFitOptions probe = options.fit;
        probe.max_windows = std::max(4, options.fit.max_windows / 3);
        for (double f = 2; f <= std::min(64.0, 0.05 * fs); f *= 2) {
            const double stiffness = link * std::pow(2 * M_PI * f, 2);
            std::vector<CauseStart> trial = with;
            trial.push_back({k, {stiffness, 0.2 * std::sqrt(stiffness * reduced), motor}});
            SimulationProblem p(m, fit, trial, probe);
            Eigen::VectorXd r;
            if (!p.evaluate(p.start(), r)) continue;
            const double e = r.squaredNorm();
            if (e < best) best = e, start = p.start();
        }
        std::ostringstream line;
        line << "compliance on joint '" << name << "': ";
        if (start.empty()) {
            line << "no grid start simulates";
            out.considered.push_back(line.str());
            continue;
        }
        std::vector<CauseStart> trial = with;
        trial.push_back({k, {start.end()[-3], start.end()[-2], start.end()[-1]}});
        SimulationFit sf;
        double before = NAN, after = NAN;
        try {
            // The damping held first: from a grid start, a free damper would
            // rather grow (a stiff link through a heavy damper) than move the
            // spring to the resonance.
            SimulationFitOptions first = options.fit;
            int at = 0;
            for (const CauseStart& c : trial) at += int(c.values.size());
            first.held = {at - 2};
            first.max_iterations = std::min(first.max_iterations, 10);
            sf = refine_by_simulation(m, fit, trial, first);
            for (size_t c = 0; c < trial.size(); ++c)
                for (size_t i = 0; i < trial[c].values.size(); ++i) trial[c].values[i] = sf.parameters[c][i].value;
            sf = refine_by_simulation(m, fit, trial, options.fit);
            for (size_t c = 0; c < trial.size(); ++c)
                for (size_t i = 0; i < trial[c].values.size(); ++i) trial[c].values[i] = sf.parameters[c][i].value;

            before = validation_error(m, validation, base, options.fit);
            after = validation_error(m, validation, trial, options.fit);
        } catch (const Error& e) {
            line << e.what();
            out.considered.push_back(line.str());
            continue;
        }
        const Estimate& stiffness = sf.parameters.back()[0];
        const double t = stiffness.value / stiffness.std_error;
        line << "from " << start.end()[-3] << " (grid), stiffness " << stiffness.value << " +- " << stiffness.std_error
             << ", simulated validation error " << percent(before) << " with the " << arm.candidate.cause << ", "
             << percent(after) << " with compliance";
        if (!sf.note.empty()) line << " (" << sf.note << ")";
        out.considered.push_back(line.str());
        if (!(t > options.min_t_ratio) || !(after < (1 - options.min_relative_gain) * before)) continue;

        // Named: the linear causes the joint fit keeps, then the compliance.
        std::vector<SelectedCause> kept;
        for (size_t c = 0; c + 1 < trial.size(); ++c) {
            const std::vector<Estimate>& est = sf.parameters[c];
            bool significant = true;
            for (const Estimate& e : est) significant = significant && std::fabs(e.value) > options.min_t_ratio * e.std_error;
            const SelectedCause* from = nullptr;
            for (const SelectedCause& sc : out.causes)
                if (sc.candidate.cause == trial[c].candidate.cause && sc.candidate.joint == trial[c].candidate.joint &&
                    sc.candidate.body == trial[c].candidate.body)
                    from = &sc;
            if (!significant) {
                out.warnings.push_back(trial[c].candidate.cause + " dropped: with compliance on joint '" + name +
                                       "' the simulation fit finds it insignificant");
                continue;
            }
            SelectedCause s = *from;
            s.parameters = est;
            kept.push_back(s);
        }
        SelectedCause sc;
        sc.candidate = k;
        sc.parameters = sf.parameters.back();
        std::ostringstream ev;
        ev << "in place of the " << arm.candidate.cause << " on joint '" << name
           << "' (the motor's inertia the rigid model saw), the "
           << "elastic transmission cuts the simulated position error on validation from " << percent(before) << " to "
           << percent(after) << " (link resonance " << std::sqrt(stiffness.value / link) / (2 * M_PI) << " Hz)";
        sc.evidence = ev.str();
        sc.fit_error = sf.final_error;
        sc.validation_error = after;
        sc.validation_gain = before - after;
        kept.push_back(sc);
        out.causes = kept;
        break;  // one transmission per identification: its joint fit holds every other cause
    }
    return out;
}

SimulationFit refine_by_simulation(const sim::Model& m, const std::vector<const Record*>& records,
                                   const std::vector<CauseStart>& causes, const SimulationFitOptions& options) {
    return SimulationProblem(m, records, causes, options).solve();
}

}  // namespace mbx::calibration
