// The "Hidden effects" requirement on the identification: over the
// fixed-seed suite of hidden_effect_suite (MuJoCo data from mbx's MJCF
// export, noise and quantisation), mbx must name the hidden cause on the
// right joint or body and recover its parameter within the tolerance that
// docs/calibration.md states per cause, in at least 90 % of the
// single-effect cases; name nothing on every clean case; and find both
// effects where two are hidden.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <map>
#include <sstream>

#include "calibration/identification/identify.h"
#include "calibration/simulation/nonlinear_fit.h"
#include "calibration/simulation/transmission_stage.h"
#include "core/finding.h"
#include "hidden_effects.h"
#include "sim/build_model.h"
#include "sim/simulation.h"
#include "tests/common/slow_build.h"
#include "temp_dir.h"
#include "tests/common/skip.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::calibration;
using mbx_test::CaseSpec;
using mbx_test::GeneratedCase;
using mbx_test::HiddenEffect;

namespace {

constexpr bool kSimulationStages = !kSlowBuild;

const sim::Model& model_of(const std::string& mechanism) {
    static std::map<std::string, sim::Model> models;
    auto it = models.find(mechanism);
    if (it == models.end()) {
        auto t = mbx_test::open_mechanism(mechanism);
        it = models.emplace(mechanism, sim::build_model(*t->mechanism)).first;
    }
    return it->second;
}

// How an identified parameter maps to the generator's truth, and the
// tolerance docs/calibration.md states for it (relative, of the true value).
struct Check {
    const char* estimate;
    const char* truth;
    double sign;  // identified = sign * truth (transformed)
    bool gain;    // the estimate is 1 - gain
    double tolerance;
};

Check check_for(const std::string& cause) {
    // The effort offset is identified as what the measured effort carries
    // beyond the joint's needs; the generator adds it to the applied effort:
    // the two are of opposite sign.
    static const std::map<std::string, Check> table = {
        {"viscous_friction", {"damping", "damping", 1, false, 0.03}},
        {"coulomb_friction", {"coulomb", "coulomb", 1, false, 0.03}},
        {"armature", {"armature", "armature", 1, false, 0.03}},
        {"mass_error", {"mass_change", "relative_mass_change", 1, false, 0.03}},
        {"effort_offset", {"offset", "offset", -1, false, 0.03}},
        {"actuator_gain", {"gain_deficit", "gain", 1, true, 0.03}},
        {"delay", {"delay", "delay", 1, false, 0.03}},
        {"sensor_offset", {"offset", "offset", 1, false, 0.03}},
        {"asymmetric_friction", {"coulomb_asymmetry", "coulomb_asymmetry", 1, false, 0.05}},
        {"stribeck_friction", {"stribeck", "stribeck", 1, false, 0.15}},
        {"position_dependent_effort", {"stiffness", "stiffness", 1, false, 0.03}},
        {"compliance", {"stiffness", "stiffness", 1, false, 0.10}},
        {"backlash", {"width", "width", 1, false, 0.25}},
    };
    return table.at(cause);
}

// A hidden mass_error's kind (the generator's com_shift and inertia_error
// are mass errors too), the estimates it is judged by and the tolerance
// docs/calibration.md states for it.
struct BodyTruth {
    enum Kind { Mass, Shift, Inertia } kind = Mass;
    std::vector<std::string> names;
    double tolerance = 0;
};

BodyTruth body_truth(const HiddenEffect& h) {
    BodyTruth b;
    for (const auto& p : h.parameters) {
        if (p.first == "com_shift") b.kind = BodyTruth::Shift;
        if (p.first == "relative_inertia_change") b.kind = BodyTruth::Inertia;
    }
    if (b.kind == BodyTruth::Shift) b.names = {"com_shift_x", "com_shift_y", "com_shift_z"}, b.tolerance = 0.05;
    if (b.kind == BodyTruth::Inertia)
        b.names = {"inertia_change_xx", "inertia_change_yy", "inertia_change_zz",
                   "inertia_change_xy", "inertia_change_xz", "inertia_change_yz"},
        b.tolerance = 0.10;
    return b;
}

bool same_subject(const sim::Model& m, const Candidate& c, const HiddenEffect& h) {
    if (!h.body_id.empty()) return c.body >= 0 && m.bodies[size_t(c.body)].id == h.body_id;
    return c.joint >= 0 && c.joint == sim::find_joint(m, h.joint_id);
}

// Causes that are part of a hidden effect's law besides its own: an
// asymmetric friction has a symmetric Coulomb part.
bool companion(const Candidate& c, const HiddenEffect& h) {
    return h.cause == "asymmetric_friction" && c.cause == "coulomb_friction";
}

struct Verdict {
    bool named = false;       // every hidden effect named on its subject, nothing else
    bool within = false;      // and every parameter within its tolerance
    std::string text;
    std::vector<double> errors;  // relative parameter errors, per hidden effect
};

Verdict judge(const sim::Model& m, const GeneratedCase& g, const Identification& id) {
    Verdict v;
    std::ostringstream s;
    s.precision(4);
    s << g.name << ": named";
    for (const SelectedCause& c : id.causes) {
        s << " " << c.candidate.cause << "(";
        for (const Estimate& e : c.parameters) s << e.name << "=" << e.value << " ";
        if (c.candidate.scale > 0) s << "at " << c.candidate.scale;
        s << ")";
    }
    if (id.causes.empty()) s << " nothing";
    s << " [validation error " << id.baseline_validation_error << " -> " << id.final_validation_error << " %]";
    v.named = true, v.within = true;
    std::vector<bool> explained(id.causes.size(), false);
    for (const HiddenEffect& h : g.hidden) {
        Check k = check_for(h.cause);
        const SelectedCause* found = nullptr;
        for (size_t i = 0; i < id.causes.size(); ++i) {
            const Candidate& c = id.causes[i].candidate;
            if (!same_subject(m, c, h)) continue;
            if (c.cause == h.cause) found = &id.causes[i], explained[i] = true;
            if (companion(c, h)) explained[i] = true;
        }
        s << "; truth " << h.cause;
        for (const auto& [name, value] : h.parameters) s << " " << name << "=" << value;
        if (!found) {
            v.named = v.within = false;
            v.errors.push_back(NAN);
            continue;
        }
        double est = NAN;
        for (const Estimate& e : found->parameters)
            if (e.name == k.estimate) est = e.value;
        double err = NAN;
        if (const BodyTruth b = body_truth(h); b.kind == BodyTruth::Mass) {
            const double truth = k.gain ? 1 - h.parameter(k.truth) : k.sign * h.parameter(k.truth);
            err = std::fabs(est - truth) / std::fabs(truth);
        } else {
            // A shift or an inertia change: the estimated entries against the
            // true ones, as vectors (entries the records cannot see are
            // neither estimated nor compared; none estimated is a miss).
            Eigen::VectorXd e(Eigen::Index(b.names.size())), t(Eigen::Index(b.names.size()));
            int seen = 0;
            for (size_t i = 0; i < b.names.size(); ++i) {
                e[Eigen::Index(i)] = 0, t[Eigen::Index(i)] = h.parameter(b.names[i]);
                for (const Estimate& x : found->parameters)
                    if (x.name == b.names[i]) e[Eigen::Index(i)] = x.value, ++seen;
                if (b.kind == BodyTruth::Inertia && !std::count_if(found->parameters.begin(), found->parameters.end(),
                                                                   [&](const Estimate& x) { return x.name == b.names[i]; }))
                    t[Eigen::Index(i)] = 0;
            }
            err = seen ? (e - t).norm() / t.norm() : NAN;
            k.tolerance = b.tolerance;
        }
        v.errors.push_back(err);
        s << " (error " << 100 * err << " %)";
        v.within = v.within && err <= k.tolerance;
    }
    for (size_t i = 0; i < id.causes.size(); ++i)
        if (!explained[i]) v.named = v.within = false;
    for (const std::string& w : id.warnings) s << "; warning: " << w;
    v.text = s.str();
    return v;
}

}  // namespace

TEST_CASE("calibration: the hidden-effect suite names each hidden cause, its subject and its value") {
    // MBX_HIDDEN_SEED draws other magnitudes, excitations and noise for a
    // look beyond the fixed suite (the assertions hold for seed 1).
    const char* seed = std::getenv("MBX_HIDDEN_SEED");
    const std::vector<CaseSpec> suite = mbx_test::hidden_effect_suite(seed ? unsigned(std::atoi(seed)) : 1u);
    mbx_test::TempDir dir("mbx_hidden_identify");
    const auto t0 = std::chrono::steady_clock::now();
    double identify_seconds = 0;
    std::map<std::string, std::pair<int, int>> per_mechanism;  // right, total (single effect)
    int single = 0, single_right = 0, clean = 0, clean_quiet = 0, pairs = 0, pairs_right = 0;
    std::map<std::string, std::vector<double>> errors;
    // MBX_HIDDEN_CASES: only the cases whose name contains it (a look at a
    // few; the suite's assertions then do not apply).
    const char* only = std::getenv("MBX_HIDDEN_CASES");
    for (const CaseSpec& spec : suite) {
        if (only && spec.name.find(only) == std::string::npos) continue;
        const GeneratedCase g = mbx_test::generate_case(spec, dir.file(spec.name));
        // Only the simulation stage names a compliance: where it is skipped
        // (below), those cases are not this build's to judge.
        if (!kSimulationStages && g.hidden.size() == 1 && (g.hidden[0].cause == "compliance" || g.hidden[0].cause == "backlash")) {
            MBX_SKIP_PART(spec.name << ": the simulation stage does not run in this build (sanitizers or no optimisation)");
            continue;
        }
        const sim::Model& model = model_of(spec.mechanism);
        const auto t1 = std::chrono::steady_clock::now();
        const Experiment e = load_experiment(g.experiment_path);
        const std::vector<Record> records = load_records(e, model);
        std::vector<const Record*> fit_records, validation_records;
        for (const Record& r : records) (r.role == Role::Fit ? fit_records : validation_records).push_back(&r);
        IdentifyOptions io;
        Identification id;
        try {
            const RegressionRows fit = regression_rows(model, fit_records, io);
            const RegressionRows val = regression_rows(model, validation_records, io, &fit.weight);
            id = identify(model, fit, val, io);
            // The simulation stage (calibration/nonlinear_fit.h): a transmission in place of an
            // armature. Jets through the dynamics cost minutes unoptimised or under sanitizers;
            // there nonlinear_fit_test covers it and the compliance cases are skipped (above).
            if (kSimulationStages) id = transmission_stage(model, fit_records, validation_records, id);
        } catch (const std::exception& x) {
            FAIL_CHECK(spec.name << ": " << x.what());
            continue;
        }
        identify_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        const Verdict v = judge(model, g, id);
        std::string considered;
        for (const std::string& c : id.considered)
            if (!v.within || c.rfind("compliance", 0) == 0 || c.rfind("backlash", 0) == 0) considered += "\n    considered: " + c;
        MESSAGE((v.within ? "right  " : "WRONG  ") << v.text << considered);
        if (g.hidden.empty()) {
            ++clean;
            clean_quiet += id.causes.empty();
            CHECK_MESSAGE(id.causes.empty(), v.text);
        } else if (g.hidden.size() == 1) {
            ++single;
            single_right += v.within;
            auto& pm = per_mechanism[spec.mechanism];
            pm.first += v.within, ++pm.second;
            if (v.named) errors[g.hidden[0].cause].push_back(v.errors[0]);
            // Another cause named in the hidden one's place: the selection
            // must have warned that these records hardly tell the two apart.
            if (!v.named && !id.causes.empty()) {
                bool flagged = false;
                for (const std::string& w : id.warnings)
                    flagged = flagged || w.find(g.hidden[0].cause) != std::string::npos;
                CHECK_MESSAGE(flagged, spec.name << ": named another cause without saying the records hardly tell it from "
                                                 << g.hidden[0].cause);
            }
        } else {
            ++pairs;
            pairs_right += v.within;
            CHECK_MESSAGE(v.within, v.text);
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ostringstream summary;
    summary << "single effects right " << single_right << "/" << single << " (";
    for (const auto& [mech, rt] : per_mechanism) summary << mech << " " << rt.first << "/" << rt.second << " ";
    summary << "), clean quiet " << clean_quiet << "/" << clean << ", two effects " << pairs_right << "/" << pairs
            << "; largest parameter error per cause:";
    for (const auto& [cause, errs] : errors) {
        double worst = 0;
        for (double x : errs) worst = std::max(worst, x);
        summary << " " << cause << " " << 100 * worst << " %";
    }
    summary << "; " << seconds << " s (identification " << identify_seconds << " s)";
    MESSAGE(summary.str());
    if (only) return;
    CHECK(single >= 30);
    CHECK(clean >= 6);
    CHECK(pairs >= 3);
    CHECK(double(single_right) >= 0.9 * double(single));
    CHECK(clean_quiet == clean);
    CHECK(pairs_right == pairs);
}

// The closed chain's rows against MuJoCo's own motion of the four-bar: the
// coordinates the calibration solves from the loop (only the crank is
// measured) must be MuJoCo's, and the projected inverse dynamics must give
// the crank's applied torque, within what the filter and the encoder's
// quantisation leave.
TEST_CASE("calibration: closed-chain rows solve the four-bar's other joints and its crank torque") {
    mbx_test::TempDir dir("mbx_closed_rows");
    CaseSpec spec;
    spec.name = "fourbar";
    spec.mechanism = "fourbar";
    spec.seed = 5;
    std::vector<mbx_test::TrueMotion> motion;
    const GeneratedCase g = mbx_test::generate_case(spec, dir.file(spec.name), &motion);
    const sim::Model& model = model_of("fourbar");
    REQUIRE(!model.closures.empty());
    const std::vector<Record> records = load_records(load_experiment(g.experiment_path), model);
    const RegressionRows rows = regression_rows(model, {&records[0]}, IdentifyOptions());
    const mbx_test::TrueMotion& tm = motion[0];
    REQUIRE(rows.actuated.size() == 1);
    const int crank = rows.actuated[0];
    double q_err = 0, v_err = 0, v_norm = 0, tau_err = 0, tau_norm = 0, a_err = 0, a_norm = 0, ad_err = 0, ad_norm = 0;
    int dependent = 0;
    for (Eigen::Index s = 0; s < rows.samples; ++s) {
        const Eigen::Index k = rows.row_sample[size_t(s)];
        for (const auto& j : model.joints) {
            if (j.v_index == crank) continue;
            dependent += s == 0;
            q_err = std::max(q_err, std::fabs(rows.q(s, j.q_index) - tm.q(k, j.v_index)));
            v_err += std::pow(rows.qd(s, j.v_index) - tm.v(k, j.v_index), 2), v_norm += std::pow(tm.v(k, j.v_index), 2);
        }
        tau_err += std::pow(rows.model_effort(s, 0) - tm.applied(k, 0), 2), tau_norm += std::pow(tm.applied(k, 0), 2);
        a_err += std::pow(rows.qdd(s, crank) - tm.a(k, crank), 2), a_norm += std::pow(tm.a(k, crank), 2);
        for (const auto& j : model.joints)
            if (j.v_index != crank)
                ad_err += std::pow(rows.qdd(s, j.v_index) - tm.a(k, j.v_index), 2), ad_norm += std::pow(tm.a(k, j.v_index), 2);
    }
    MESSAGE("crank acceleration error " << 100 * std::sqrt(a_err / a_norm) << " %, solved joints' " << 100 * std::sqrt(ad_err / ad_norm) << " %");
    MESSAGE("four-bar rows: " << dependent << " solved joints, largest angle error " << q_err << " rad, speed error "
                              << 100 * std::sqrt(v_err / v_norm) << " %, crank torque error "
                              << 100 * std::sqrt(tau_err / tau_norm) << " %");
    CHECK(dependent >= 2);
    CHECK(q_err < 1e-3);
    CHECK(std::sqrt(v_err / v_norm) < 0.01);
    // The crank's measured acceleration is a few per cent off (an encoder
    // step of 1.6e-4 rad twice differentiated); the loop's solution and its
    // projection must add nothing of their own to that.
    const double a_rel = std::sqrt(a_err / a_norm);
    CHECK(a_rel < 0.05);
    CHECK(std::sqrt(ad_err / ad_norm) < 1.1 * a_rel + 0.003);
    CHECK(std::sqrt(tau_err / tau_norm) < 1.1 * a_rel + 0.003);
}

// A closed chain with the wrong coordinates measured is a named error, not a
// crash or a silent fit.
TEST_CASE("calibration: closed-chain rows refuse records that do not fix the loop") {
    const sim::Model& model = model_of("fourbar");
    REQUIRE(model.nv >= 3);
    Record r;
    r.path = "made_up.csv";
    for (int k = 0; k < 400; ++k) r.t.push_back(1e-3 * k);
    auto signal = [&](Quantity q, int dof) {
        Signal s;
        s.quantity = q, s.dof = dof, s.joint = model.dof_joint[size_t(dof)];
        for (double t : r.t) s.values.push_back(q == Quantity::Position ? 0.1 * std::sin(6 * t) : std::cos(6 * t));
        return s;
    };
    // Two measured coordinates where the loop leaves one free.
    r.signals = {signal(Quantity::Position, 0), signal(Quantity::Effort, 0), signal(Quantity::Position, 1)};
    CHECK_THROWS_WITH_AS(regression_rows(model, {&r}, IdentifyOptions()),
                         doctest::Contains("the loops leave 1 coordinate(s) free but 2 are measured"), Error);
    // An effort on a joint whose position is not measured.
    r.signals = {signal(Quantity::Position, 0), signal(Quantity::Effort, 1)};
    CHECK_THROWS_WITH_AS(regression_rows(model, {&r}, IdentifyOptions()),
                         doctest::Contains("has a measured effort but no measured position"), Error);
}
}  // namespace MBX_UNITY_ID
