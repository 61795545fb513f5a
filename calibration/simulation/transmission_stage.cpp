#include "calibration/simulation/transmission_stage.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "calibration/cause_table.h"
#include "core/finding.h"

namespace mbx::calibration {

namespace {

// Where the stage would look: the joints of a named armature or gain.
std::vector<std::string> candidate_joints(const sim::Model& m, const Identification& id) {
    std::vector<std::string> out;
    for (const SelectedCause& c : id.causes)
        if (c.candidate.kind().rigid_motor && c.candidate.joint >= 0)
            out.push_back("'" + m.joints[size_t(c.candidate.joint)].name + "'");
    return out;
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
    return s;
}

std::string percent(double x) {
    std::ostringstream s;
    s.precision(3);
    s << x << " %";
    return s.str();
}

// What the simulation fit holds of the named causes, at their values.
std::vector<CauseStart> starts_of(const Identification& id) {
    std::vector<CauseStart> out;
    for (const SelectedCause& c : id.causes) {
        std::vector<double> v;
        for (const Estimate& e : c.parameters) v.push_back(e.value);
        out.push_back({c.candidate, v});
    }
    return out;
}

// A backlash on one of the actuated joints: the joint whose dead band
// (started from a grid of widths, the motor a third of the link) cuts the
// simulated validation error most, named when its width is beyond
// `backlash_t_ratio` standard errors and the cut is `backlash_relative_gain`
// of the error at least; the causes the joint fit finds insignificant go.
Identification add_backlash(const sim::Model& m, const std::vector<const Record*>& fit,
                            const std::vector<const Record*>& validation, const Identification& linear,
                            const std::vector<int>& actuated, const TransmissionOptions& options) {
    Identification out = linear;
    // The stops want steps of half a millisecond (1 ms time constant).
    SimulationFitOptions o = options.fit;
    o.substeps = std::max(o.substeps, int(std::ceil(fit.front()->sample_period() / 5e-4 - 1e-9)));
    o.max_windows = std::min(o.max_windows, 8), o.max_iterations = std::min(o.max_iterations, 15);
    std::vector<CauseStart> base = starts_of(linear);
    // The model as it is, for the validation error: a viscous friction held at 0 stands for it.
    std::vector<CauseStart> reference = base;
    if (reference.empty()) {
        Candidate none;
        none.cause = cause_name(CauseId::ViscousFriction), none.joint = m.dof_joint[size_t(actuated.front())];
        none.dof = actuated.front(), none.q_index = m.joints[size_t(none.joint)].q_index;
        none.parameters = {"damping"};
        reference.push_back({none, {0.0}});
    }
    SimulationFitOptions held = o;
    held.hold_parameters = true;
    double before = NAN;
    try {
        before = SimulationProblem(m, validation, reference, held).solve().final_error;
    } catch (const Error& e) {
        out.considered.push_back(std::string("backlash: the model as it is does not simulate: ") + e.what());
        return out;
    }
    struct Best {
        double after = INFINITY;
        SimulationFit fit;
        std::vector<CauseStart> trial;
        std::string joint;
    } best;
    for (int dof : actuated) {
        const int j = m.dof_joint[size_t(dof)];
        const sim::JointT<double>& joint = m.joints[size_t(j)];
        const double link = joint.reference_inertia;
        if (!(link > 0)) continue;
        Candidate k;
        k.cause = cause_name(CauseId::Backlash), k.joint = j, k.dof = dof, k.q_index = joint.q_index;
        k.parameters = cause_table()[size_t(CauseId::Backlash)].parameters;
        const double motor = 0.3 * link;
        // Widths: a few tenths of a degree to a few degrees (a tenth of a millimetre to a few on a slide).
        const double unit = joint.kind == sim::JointKind::Prismatic ? 1e-3 : M_PI / 180;
        // Fitted where the joint's load reverses: the only stretches that carry the band's width.
        SimulationFitOptions at_reversals = o;
        at_reversals.reversal_dof = dof;
        SimulationFitOptions probe = at_reversals;
        probe.max_windows = std::max(4, o.max_windows / 2);
        std::vector<std::pair<double, double>> grid;  // residual, width
        for (double w : {0.25, 0.5, 1.0, 2.0, 4.0}) {
            std::vector<CauseStart> trial = base;
            trial.push_back({k, {w * unit, motor}});
            try {
                SimulationProblem p(m, fit, trial, probe);
                Eigen::VectorXd r;
                if (p.evaluate(p.start(), r)) grid.push_back({r.squaredNorm(), w * unit});
            } catch (const Error&) {
            }
        }
        std::ostringstream line;
        line << "backlash on joint '" << joint.name << "': ";
        if (grid.empty()) {
            line << "no grid start simulates";
            out.considered.push_back(line.str());
            continue;
        }
        // The fit error is many-valleyed in the width (a narrower band that
        // lets the link cross in step with another reversal), and the grid's
        // unfitted residuals rank neighbouring widths by noise: the two best
        // grid widths are both refined and the better fit kept.
        std::sort(grid.begin(), grid.end());
        std::vector<CauseStart> trial;
        SimulationFit f;
        double width = 0;
        try {
            for (size_t g = 0; g < std::min<size_t>(2, grid.size()); ++g) {
                std::vector<CauseStart> t = base;
                t.push_back({k, {grid[g].second, motor}});
                SimulationFit fg = refine_by_simulation(m, fit, t, at_reversals);
                if (trial.empty() || fg.final_error < f.final_error) trial = t, f = std::move(fg), width = grid[g].second;
            }
            for (size_t c = 0; c < trial.size(); ++c)
                for (size_t i = 0; i < trial[c].values.size(); ++i) trial[c].values[i] = f.parameters[c][i].value;
            const double after = SimulationProblem(m, validation, trial, held).solve().final_error;
            const Estimate& b = f.parameters.back()[0];
            line << "from " << width << " (grid), width " << b.value << " +- " << b.std_error << ", simulated validation error "
                 << percent(before) << " without, " << percent(after) << " with it";
            if (!f.note.empty()) line << " (" << f.note << ")";
            out.considered.push_back(line.str());
            if (b.value > options.backlash_t_ratio * b.std_error && after < best.after)
                best = {after, f, trial, joint.name};
        } catch (const Error& e) {
            line << e.what();
            out.considered.push_back(line.str());
        }
    }
    if (!(best.after < (1 - options.backlash_relative_gain) * before)) return out;
    std::vector<SelectedCause> kept;
    for (size_t c = 0; c + 1 < best.trial.size(); ++c) {
        const std::vector<Estimate>& est = best.fit.parameters[c];
        bool significant = true;
        for (const Estimate& e : est) significant = significant && std::fabs(e.value) > options.min_t_ratio * e.std_error;
        if (!significant) {
            out.warnings.push_back(best.trial[c].candidate.cause + " dropped: with backlash on joint '" + best.joint +
                                   "' the simulation fit finds it insignificant");
            continue;
        }
        SelectedCause s = linear.causes[c];
        s.parameters = est;
        kept.push_back(s);
    }
    SelectedCause sc;
    sc.candidate = best.trial.back().candidate;
    sc.parameters = best.fit.parameters.back();
    std::ostringstream ev;
    ev << "what the linear causes left (" << percent(linear.final_validation_error)
       << " of the effort on validation) is a dead band: the link waits while the motor crosses it, so the rigid "
          "model misses the effort at every load reversal; the dead band on joint '"
       << best.joint << "' cuts the simulated position error on validation from " << percent(before) << " to "
       << percent(best.after);
    sc.evidence = ev.str();
    // Its rigid limit is an armature. Until calibrate() recomputes every
    // step's inverse-dynamics figures at the refitted values
    // (recompute_errors), it has the linear stage's final ones and no gain.
    sc.fit_error = linear.final_fit_error, sc.validation_error = linear.final_validation_error;
    sc.validation_gain = 0;
    kept.push_back(sc);
    out.causes = kept;
    return out;
}

}  // namespace

sim::Model rigid_limit(const sim::Model& m) {
    if (m.transmissions.empty()) return m;
    sim::Model r = m;
    for (const sim::Transmission& t : m.transmissions) {
        sim::JointT<double>& j = r.joints[size_t(t.joint)];
        j.dynamics.armature += t.motor_inertia;
        j.reference_inertia += t.motor_inertia;
    }
    r.transmissions.clear();
    r.transmission_of_dof.assign(size_t(r.nv), -1);
    return r;
}

Identification transmission_stage(const sim::Model& m, const std::vector<const Record*>& fit,
                                  const std::vector<const Record*>& validation, const Identification& linear,
                                  const TransmissionOptions& options) {
    std::vector<std::string> joints = candidate_joints(m, linear);
    // A dead band's signature: the linear causes leave a large share of the
    // effort (the rigid model misses it at every load reversal).
    const bool dead_band = linear.final_validation_error > options.dead_band_left;
    if (joints.empty() && !dead_band) return linear;
    if (joints.empty()) joints.push_back("(every actuated joint, for backlash)");
    Identification out = linear;
    auto skip = [&](const std::string& why) {
        out.warnings.push_back("compliance was not tried on joint " + joined(joints) + ": " + why);
        return out;
    };
    if (!m.closures.empty())
        return skip("the simulation stage does not carry an elastic transmission in a closed loop yet");
    for (const sim::JointT<double>& j : m.joints)
        if (j.nv() != 1) return skip("the simulation stage handles 1-dof joints only (joint '" + j.name + "')");
    if (!m.transmissions.empty())
        return skip("the model already has an elastic transmission (on joint '" +
                    m.joints[size_t(m.transmissions[0].joint)].name + "'), which the stage does not refit");
    for (const SelectedCause& c : linear.causes)
        if (!simulation_supports(c.candidate.cause))
            return skip("the simulation stage cannot carry " + c.candidate.cause + ", which was named");
    Identification staged;
    try {
        staged = add_transmissions(m, fit, validation, linear, options);
        auto names = [](const Identification& id, const char* cause) {
            for (const SelectedCause& c : id.causes)
                if (c.candidate.cause == cause) return true;
            return false;
        };
        std::vector<int> actuated;
        for (const Signal& s : fit.front()->signals)
            if (s.quantity == Quantity::Effort) actuated.push_back(s.dof);
        if (dead_band && !actuated.empty()) {
            // Where a dead band may be, it is tried from the linear causes
            // too: a compliance fitted on top of linear causes that took a
            // share of the band's signature can fit a dead band's records
            // well. Both named: the lower simulated validation error wins,
            // both measured alike (the stops' finer steps).
            const Identification banded = add_backlash(m, fit, validation, linear, actuated, options);
            if (!names(staged, "compliance")) {
                staged = banded;
            } else if (names(banded, "backlash")) {
                SimulationFitOptions alike = options.fit;
                alike.substeps = std::max(alike.substeps, int(std::ceil(fit.front()->sample_period() / 5e-4 - 1e-9)));
                alike.max_windows = std::min(alike.max_windows, 8);
                alike.hold_parameters = true;
                const double elastic = SimulationProblem(m, validation, starts_of(staged), alike).solve().final_error;
                const double band = SimulationProblem(m, validation, starts_of(banded), alike).solve().final_error;
                std::ostringstream w;
                w << "compliance and backlash both fit the records (simulated validation error " << percent(elastic)
                  << " and " << percent(band) << "): " << (band < elastic ? "backlash" : "compliance")
                  << " is named";
                if (band < elastic) staged = banded;
                staged.warnings.push_back(w.str());
            }
        }
    } catch (const Error& e) {
        return skip(std::string("the simulation fit failed: ") + e.what());
    }
    // The compliance's inverse-dynamics figures: its rigid limit is the
    // armature (or gain) it replaced, so those of that step.
    for (SelectedCause& c : staged.causes) {
        if (c.candidate.kind().id != CauseId::Compliance) continue;
        for (const SelectedCause& was : linear.causes)
            if (was.candidate.joint == c.candidate.joint &&
                was.candidate.kind().rigid_motor) {
                c.fit_error = was.fit_error;
                c.validation_error = was.validation_error;
                c.validation_gain = was.validation_gain;
            }
    }
    return staged;
}

}  // namespace mbx::calibration
