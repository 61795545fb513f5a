#include "calibration/calibrate.h"

#include <chrono>
#include <cmath>

#include "calibration/records/body_quantities.h"
#include "calibration/simulation/model_extension.h"
#include "calibration/simulation/replay.h"
#include "calibration/simulation/transmission_stage.h"
#include "core/finding.h"
#include "core/heartbeat.h"
#include "core/text_format.h"

namespace mbx::calibration {

double relative_error(const std::vector<double>& measured, const std::vector<double>& simulated) {
    double e = 0, n = 0;
    for (size_t k = 0; k < measured.size() && k < simulated.size(); ++k) {
        if (!std::isfinite(simulated[k])) continue;
        e += (measured[k] - simulated[k]) * (measured[k] - simulated[k]);
        n += measured[k] * measured[k];
    }
    return n > 0 ? 100 * std::sqrt(e / n) : 0;
}

namespace {

// Every `stride`-th sample, so that a plot has about `points` of them.
size_t stride_for(size_t n, size_t points) { return points > 0 && n > points ? (n + points - 1) / points : 1; }

struct Replayed {
    std::vector<std::vector<std::vector<double>>> values;  // per record, per compared signal, per sample
};

Replayed replay_all(const sim::Model& m, const Experiment& e, const std::vector<Record>& records,
                    const std::vector<ComparedSignal>& compared, const ReplayAdjustments& adjust,
                    double done, double share) {
    Replayed r;
    for (size_t i = 0; i < records.size(); ++i) {
        const double from = done + share * double(i) / double(records.size());
        heartbeat("replay", from);
        const HeartbeatShare part(from, from + share / double(records.size()));
        r.values.push_back(replay(m, e, records[i], compared, adjust));
    }
    return r;
}

// Errors of one replay of every record, per compared signal and combined by role.
void score(const Experiment& e, const std::vector<Record>& records, const std::vector<ComparedSignal>& compared,
           const Replayed& sim, StepErrors& step) {
    double err[2] = {0, 0}, ref[2] = {0, 0};
    for (size_t r = 0; r < records.size(); ++r) {
        const Record& rec = records[r];
        for (size_t c = 0; c < compared.size(); ++c) {
            const ComparedSignal& cs = compared[c];
            const std::vector<double>& meas = *measured_values(rec, cs);
            const std::vector<double> reference = error_reference(e, rec, cs, meas);
            const std::vector<double>& s = sim.values[r][c];
            double ee = 0, nn = 0;
            size_t count = 0;
            for (size_t k = 0; k < meas.size(); ++k) {
                if (!std::isfinite(s[k])) continue;
                ee += (meas[k] - s[k]) * (meas[k] - s[k]);
                nn += reference[k] * reference[k];
                ++count;
            }
            // Sums of squares of values beyond 1e150 overflow: an error of
            // "inf %" or "nan %" would read as a result. Say which signal.
            if (!std::isfinite(ee) || !std::isfinite(nn))
                throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"),
                            rec.path + ": the error of the compared " + quantity_name(cs.quantity) +
                                " overflows (its sum of squares is not finite): measured or simulated values beyond 1e150");
            SignalError se;
            se.record = int(r), se.role = rec.role, se.joint = cs.joint, se.quantity = cs.quantity, se.weight = cs.weight;
            se.body = cs.body, se.component = cs.component, se.point = cs.point;
            se.relative = nn > 0 ? 100 * std::sqrt(ee / nn) : 0;
            se.rms = count ? std::sqrt(ee / double(count)) : 0;
            step.simulated.push_back(se);
            const int role = rec.role == Role::Fit ? 0 : 1;
            err[role] += cs.weight * ee, ref[role] += cs.weight * nn;
        }
    }
    step.simulated_fit = ref[0] > 0 ? 100 * std::sqrt(err[0] / ref[0]) : 0;
    step.simulated_validation = ref[1] > 0 ? 100 * std::sqrt(err[1] / ref[1]) : 0;
}

// Whether a later stage left the identified causes and their values as they were.
bool same_causes(const Identification& a, const Identification& b) {
    if (a.causes.size() != b.causes.size()) return false;
    for (size_t i = 0; i < a.causes.size(); ++i) {
        const SelectedCause &x = a.causes[i], &y = b.causes[i];
        if (x.candidate.cause != y.candidate.cause || x.candidate.joint != y.candidate.joint ||
            x.candidate.body != y.candidate.body || x.parameters.size() != y.parameters.size())
            return false;
        for (size_t k = 0; k < x.parameters.size(); ++k)
            if (x.parameters[k].value != y.parameters[k].value) return false;
    }
    return true;
}

std::string step_label(const sim::Model& m, const SelectedCause& c) {
    return c.candidate.cause + " on " + subject_text(m, c.candidate);
}

std::vector<ResidualCloud> residual_clouds(const sim::Model& m, const RegressionRows& fit, const Identification& id,
                                           size_t points) {
    const Eigen::Index A = Eigen::Index(fit.actuated.size());
    const Eigen::VectorXd y = fit.y();
    Eigen::VectorXd explained = Eigen::VectorXd::Zero(y.size());
    for (const SelectedCause& c : id.causes) {
        const Eigen::MatrixXd cols = c.candidate.columns(fit);
        for (Eigen::Index p = 0; p < cols.cols() && p < Eigen::Index(c.parameters.size()); ++p)
            explained += c.parameters[size_t(p)].value * cols.col(p);
    }
    std::vector<ResidualCloud> out;
    const size_t stride = stride_for(size_t(fit.samples), points);
    for (Eigen::Index a = 0; a < A; ++a) {
        const int dof = fit.actuated[size_t(a)];
        const double w = fit.weight[size_t(a)];
        ResidualCloud rc;
        rc.joint = m.dof_joint[size_t(dof)];
        const int qi = m.joints[size_t(rc.joint)].q_index;
        for (int s = 0; s < fit.samples; s += int(stride)) {
            rc.velocity.push_back(fit.qd(s, dof));
            rc.position.push_back(fit.q(s, qi));
            rc.before.push_back(y[s * A + a] / w);
            rc.after.push_back((y[s * A + a] - explained[s * A + a]) / w);
        }
        out.push_back(std::move(rc));
    }
    return out;
}

}  // namespace

CalibrationResult calibrate(const Mechanism& mech, const sim::BuildOptions& base, const Experiment& e,
                            const CalibrateOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    Heartbeat beat(options.progress, "the calibration");
    HeartbeatScope beating(&beat);
    beat.stage("records", 0);
    CalibrationResult out;
    out.mode = e.mode;
    const sim::Model base_model = sim::build_model(mech, base);
    const std::vector<Record> records = load_records(e, base_model);
    const std::vector<ComparedSignal> compared = compared_signals(e, base_model);
    std::vector<const Record*> fit_records, validation_records;
    for (const Record& r : records) {
        (r.role == Role::Fit ? fit_records : validation_records).push_back(&r);
        out.record_paths.push_back(r.path);
        out.record_roles.push_back(r.role);
    }
    if (fit_records.empty() || validation_records.empty())
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"),
                    e.path + ": calibration needs at least one fit and one validation record");
    if (contact_experiment(e, base_model, records, options.contact)) {
        run_contact_stage(base_model, e, records, options.contact, options, out);
        beat.report_now(1);
        out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        return out;
    }

    beat.stage("identify", 0);
    // Inverse dynamics sees a transmission the model has in its rigid limit.
    const sim::Model rigid = rigid_limit(base_model);
    // The stage's fraction: the rows, then the forward selection's rounds.
    const RegressionRows fit = [&] {
        const HeartbeatShare share(0, 0.2);
        return regression_rows(rigid, fit_records, options.identify);
    }();
    const RegressionRows validation = [&] {
        const HeartbeatShare share(0.2, 0.3);
        return regression_rows(rigid, validation_records, options.identify, &fit.weight);
    }();
    IdentifyOptions identify_options = options.identify;
    const double floor = noise_floor(rigid, validation, validation_records);
    if (std::isnan(identify_options.noise_level)) identify_options.noise_level = floor;
    out.identification = [&] {
        const HeartbeatShare share(0.3, 1);
        return identify(rigid, fit, validation, identify_options);
    }();
    out.identification.noise_level = floor;
    beat.stage("simulation fit", 0);
    const Identification linear = out.identification;
    out.identification = transmission_stage(base_model, fit_records, validation_records, linear);
    if (!same_causes(linear, out.identification)) recompute_errors(out.identification, fit, validation);
    locate_residual(rigid, out.identification, validation);
    const Identification& id = out.identification;

    // Replays before any cause and after each: the simulated gain of every step.
    const size_t steps = id.causes.size() + 1;
    Replayed first, last;
    for (size_t i = 0; i < steps; ++i) {
        const ModelExtension ext = extend(mech, base, base_model, id, i, fit);
        Replayed sim;
        StepErrors step;
        bool failed = false;
        try {
            const sim::Model model = extended_model(mech, ext, e.mode);
            sim = replay_all(model, e, records, compared, ext.adjust, double(i) / double(steps),
                             1.0 / double(steps));
        } catch (const Error& err) {
            // The model as given must replay; a step whose extension does not
            // is reported, and the causes' inverse-dynamics figures still stand.
            if (i == 0 || err.status() == MBX_ERROR_CANCELLED) throw;
            out.warnings.push_back("the replay after naming " + step_label(base_model, id.causes[i - 1]) +
                                   " failed: " + err.what());
            failed = true;
            sim.values.clear();
            for (const Record& r : records)
                sim.values.emplace_back(compared.size(), std::vector<double>(r.t.size(), NAN));
        }
        if (i == 0) {
            step.label = "baseline";
            step.fit_error = id.baseline_fit_error, step.validation_error = id.baseline_validation_error;
        } else {
            const SelectedCause& c = id.causes[i - 1];
            step.label = step_label(base_model, c);
            step.cause = int(i - 1);
            step.fit_error = c.fit_error, step.validation_error = c.validation_error;
        }
        score(e, records, compared, sim, step);
        if (failed) {
            for (SignalError& se : step.simulated) se.relative = se.rms = NAN;
            step.simulated_fit = step.simulated_validation = NAN;
        }
        out.steps.push_back(std::move(step));
        if (i == 0) first = sim;
        if (i + 1 == steps) {
            last = std::move(sim);
            out.joints = ext.joints;
            out.drives = ext.drives;
            out.bodies = ext.bodies;
            out.mounting_tilt = ext.tilt, out.mounting_tilted = ext.tilted;
            out.unwritten = ext.unwritten;
            out.warnings.insert(out.warnings.end(), ext.warnings.begin(), ext.warnings.end());
        }
    }
    beat.report_now(1);
    out.warnings.insert(out.warnings.begin(), id.warnings.begin(), id.warnings.end());
    const StepErrors& b = out.steps.front();
    const StepErrors& f = out.steps.back();
    if (steps > 1 && std::isnan(f.simulated_validation))
        out.warnings.push_back("the calibrated model could not be replayed: its errors are those of inverse dynamics only");
    if (steps > 1 && f.simulated_validation > b.simulated_validation)
        out.warnings.push_back("the named causes lower the inverse-dynamics error but not the simulated validation error (" +
                               readable(b.simulated_validation) + " % -> " + readable(f.simulated_validation) +
                               " %): the replay is limited by something the catalogue does not hold");

    for (size_t r = 0; r < records.size(); ++r) {
        const Record& rec = records[r];
        const size_t stride = stride_for(rec.t.size(), options.plot_points);
        for (size_t c = 0; c < compared.size(); ++c) {
            Trace t;
            t.record = int(r), t.role = rec.role, t.joint = compared[c].joint, t.quantity = compared[c].quantity;
            t.body = compared[c].body, t.component = compared[c].component, t.point = compared[c].point;
            const std::vector<double>& meas = *measured_values(rec, compared[c]);
            for (size_t k = 0; k < rec.t.size(); k += stride) {
                if (!in_window(compared[c], rec, k)) continue;
                t.t.push_back(rec.t[k]);
                t.measured.push_back(meas[k]);
                t.baseline.push_back(first.values[r][c][k]);
                t.calibrated.push_back(last.values[r][c][k]);
            }
            out.traces.push_back(std::move(t));
        }
    }
    out.residuals = residual_clouds(base_model, fit, id, options.plot_points);
    out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return out;
}

}  // namespace mbx::calibration
