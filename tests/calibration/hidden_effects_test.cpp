// The hidden-effect generator against physics: along the motion MuJoCo
// produced, mbx's own inverse dynamics (sim::build_model of the same
// translation, an engine independent of MuJoCo's) must explain the recorded
// effort of a clean case to within the noise, and the difference for a case
// with an effect must be that effect with its hidden magnitude. Plus the
// files: they parse, reference what exists, and repeat byte for byte.
#include <doctest/doctest.h>

#include <pugixml.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>

#include "calibration/identification/causes.h"
#include "hidden_effects.h"
#include "sim/build_model.h"
#include "sim/dynamics.h"
#include "sim/loop_closure.h"
#include "sim/simulation.h"
#include "temp_dir.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using mbx_test::CaseSpec;
using mbx_test::EffectSpec;
using mbx_test::GeneratedCase;
using mbx_test::TrueMotion;

namespace {

struct Run {
    GeneratedCase c;
    std::vector<TrueMotion> motion;
};

Run run(const std::string& mechanism, std::vector<EffectSpec> effects, const mbx_test::TempDir& dir, unsigned seed = 7,
        const std::string& name = "case", bool holds = false) {
    CaseSpec s;
    s.name = name;
    s.mechanism = mechanism;
    s.effects = std::move(effects);
    s.seed = seed;
    s.holds = holds;
    s.fit_seconds = 6;
    s.validation_seconds = 3;
    Run r;
    r.c = mbx_test::generate_case(s, dir.file(name), &r.motion);
    return r;
}

// The actuated joints' efforts that produce the recorded motion in `model`
// (samples x actuated). For a loop, the tree's inverse dynamics projected on
// the closure Jacobian's null space: constraint forces do no work along it.
Eigen::MatrixXd inverse_dynamics_along(const sim::Model& model, const TrueMotion& tm) {
    const Eigen::Index n = Eigen::Index(tm.t.size());
    const Eigen::Index na = Eigen::Index(tm.actuated_dof.size());
    Eigen::MatrixXd out(n, na);
    sim::Data d(model);
    Eigen::VectorXd qacc(model.nv), tau(model.nv);
    for (Eigen::Index k = 0; k < n; ++k) {
        for (const auto& j : model.joints)
            if (j.nv() == 1) d.q[j.q_index] = tm.q(k, j.v_index);
        d.v = tm.v.row(k).transpose();
        qacc = tm.a.row(k).transpose();
        sim::update_kinematics(model, d);
        sim::inverse_dynamics(model, d, qacc, tau);
        if (model.closures.empty()) {
            for (Eigen::Index i = 0; i < na; ++i) out(k, i) = tau[tm.actuated_dof[size_t(i)]];
            continue;
        }
        sim::update_closure_jacobian(model, d);
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(d.J, Eigen::ComputeFullV);
        const Eigen::VectorXd& sv = svd.singularValues();
        int rank = 0;
        for (Eigen::Index i = 0; i < sv.size(); ++i) rank += sv[i] > 1e-8 * sv[0];
        const Eigen::MatrixXd N = svd.matrixV().rightCols(model.nv - rank);
        Eigen::MatrixXd B = Eigen::MatrixXd::Zero(model.nv, na);
        for (Eigen::Index i = 0; i < na; ++i) B(tm.actuated_dof[size_t(i)], i) = 1;
        out.row(k) = (N.transpose() * B).colPivHouseholderQr().solve(N.transpose() * tau).transpose();
    }
    return out;
}

// The same motion with accelerations from the positions by central
// differences at the record's rate, as a calibration sees them (MuJoCo's own
// qacc at a sample belongs to the force held over the step after it).
TrueMotion from_positions(const TrueMotion& tm) {
    TrueMotion r = tm;
    const double dt = tm.t[1] - tm.t[0];
    for (Eigen::Index k = 1; k + 1 < tm.q.rows(); ++k)
        r.a.row(k) = (tm.q.row(k + 1) - 2 * tm.q.row(k) + tm.q.row(k - 1)) / (dt * dt);
    return r;
}

double rms(const Eigen::VectorXd& x) { return std::sqrt(x.squaredNorm() / double(x.size())); }

// Least squares of y on the columns of X.
Eigen::VectorXd regress(const Eigen::MatrixXd& X, const Eigen::VectorXd& y) { return X.colPivHouseholderQr().solve(y); }

struct Csv {
    std::vector<std::string> header;
    std::vector<std::vector<double>> rows;
};

std::string read_text(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

// Strict: every cell a finite number, every row as wide as the header (one
// REQUIRE per file, not per cell, so the tests stay fast under sanitizers).
Csv read_csv(const std::string& path) {
    Csv c;
    std::istringstream in(read_text(path));
    std::string line;
    REQUIRE(std::getline(in, line));
    std::stringstream h(line);
    for (std::string cell; std::getline(h, cell, ',');) c.header.push_back(cell);
    int number = 1;
    std::string problem;
    while (std::getline(in, line) && problem.empty()) {
        ++number;
        std::vector<double> row;
        std::stringstream s(line);
        for (std::string cell; std::getline(s, cell, ',');) {
            char* end = nullptr;
            const double x = std::strtod(cell.c_str(), &end);
            if (end != cell.c_str() + cell.size() || cell.empty() || !std::isfinite(x))
                problem = path + ":" + std::to_string(number) + ": bad cell '" + cell + "'";
            row.push_back(x);
        }
        if (row.size() != c.header.size()) problem = path + ":" + std::to_string(number) + ": wrong column count";
        c.rows.push_back(row);
    }
    INFO(problem);
    REQUIRE(problem.empty());
    return c;
}

// The recorded effort column of actuated joint i.
Eigen::VectorXd recorded_effort(const GeneratedCase& c, size_t i, bool fit = true) {
    const Csv csv = read_csv(fit ? c.fit_csv : c.validation_csv);
    size_t col = 0;
    while (col < csv.header.size() && csv.header[col] != c.column_stems[i] + ".effort") ++col;
    REQUIRE(col < csv.header.size());
    Eigen::VectorXd e(Eigen::Index(csv.rows.size()));
    for (size_t k = 0; k < csv.rows.size(); ++k) e[Eigen::Index(k)] = csv.rows[k][col];
    return e;
}

const sim::Model& model_of(const std::string& mechanism) {
    static std::map<std::string, sim::Model> models;
    auto it = models.find(mechanism);
    if (it == models.end()) {
        auto t = mbx_test::open_mechanism(mechanism);
        it = models.emplace(mechanism, sim::build_model(*t->mechanism)).first;
    }
    return it->second;
}

// Speed reversals of a velocity record (sign changes beyond a small band).
int reversals(const Eigen::VectorXd& v) {
    const double band = 0.02 * v.cwiseAbs().maxCoeff();
    int n = 0, sign = 0;
    for (Eigen::Index k = 0; k < v.size(); ++k) {
        const int s = v[k] > band ? 1 : v[k] < -band ? -1 : 0;
        if (s && sign && s != sign) ++n;
        if (s) sign = s;
    }
    return n;
}

}  // namespace

TEST_CASE("hidden effects: clean records equal mbx's inverse dynamics along MuJoCo's motion") {
    mbx_test::TempDir dir("mbx_hidden_clean");
    for (const auto& [mech_, holds_] : std::vector<std::pair<std::string, bool>>{
             {"emps_axis", false}, {"two_link_arm", false}, {"fourbar", false}, {"two_link_arm", true}}) {
        // (C++17 lambdas, CAPTURE's among them, cannot capture a structured binding)
        const std::string& mech = mech_;
        const bool holds = holds_;
        CAPTURE(mech);
        CAPTURE(holds);
        const Run r = run(mech, {}, dir, 7, mech + (holds ? "_rests" : ""), holds);
        REQUIRE(r.motion.size() == 2);
        const sim::Model& model = model_of(mech);
        for (int rec = 0; rec < 2; ++rec) {
            CAPTURE(rec);
            const TrueMotion& tm = r.motion[size_t(rec)];
            const Eigen::MatrixXd id = inverse_dynamics_along(model, tm);
            const Eigen::MatrixXd id_q = inverse_dynamics_along(model, from_positions(tm));
            const Eigen::Index n = Eigen::Index(tm.t.size());
            for (size_t i = 0; i < r.c.joint_names.size(); ++i) {
                CAPTURE(r.c.joint_names[i]);
                const Eigen::VectorXd u = tm.commanded.col(Eigen::Index(i));
                const Eigen::VectorXd e = recorded_effort(r.c, i, rec == 0);
                // MuJoCo's acceleration against mbx's dynamics at the same state and force.
                const double engines = rms(tm.applied.col(Eigen::Index(i)) - id.col(Eigen::Index(i))) / rms(u);
                // The recorded effort against the motion's positions: only noise, and no lag.
                const Eigen::VectorXd r_q = (e - id_q.col(Eigen::Index(i))).segment(1, n - 2);
                Eigen::VectorXd du(n - 2);
                for (Eigen::Index k = 1; k + 1 < n; ++k) du[k - 1] = (u[k + 1] - u[k - 1]) / (tm.t[2] - tm.t[0]);
                // (the noise-free command: noise would blur the lag by ~2e-5 s)
                const Eigen::VectorXd r_u = (u - id_q.col(Eigen::Index(i))).segment(1, n - 2);
                const double lag = -regress(du, r_u)[0];
                const double noise = rms(e - u) / rms(u);
                const Eigen::VectorXd v = tm.v.col(tm.actuated_dof[i]);
                MESSAGE(mech << " " << r.c.joint_names[i] << " rec " << rec << ": effort RMS " << rms(u) << ", |ID - applied| "
                             << 100 * engines << " %, recorded - ID from positions " << 100 * rms(r_q) / rms(u)
                             << " %, lag " << lag << " s, noise " << 100 * noise << " %, speed RMS " << rms(v)
                             << ", reversals " << reversals(v) << ", accel RMS " << rms(tm.a.col(tm.actuated_dof[i])));
                // MuJoCo and mbx agree far below the noise (the loop: MuJoCo's soft closure).
                CHECK(engines < (model.closures.empty() ? 1e-8 : 2e-5));
                CHECK(noise == mbx_test::relative(0.015, 0.15));
                CHECK(rms(r_q) / rms(u) < 0.018);
                CHECK(std::fabs(lag) < 1e-5);  // the step's hold alone would give 2.5e-4
                // Rich excitation: many reversals.
                CHECK(reversals(v) >= (rec == 0 ? 12 : 6) - (holds ? 4 : 0));
            }
        }
    }
}

namespace {

// Along a case's fit record, for actuated joint i: the recorded (noisy)
// effort minus the nominal model's inverse dynamics, and the true motion.
struct Residual {
    Eigen::VectorXd r, q, v, a, u, id;
    double rms_effort = 0;
};

Residual residual_of(const Run& run, size_t i) {
    const TrueMotion tm = from_positions(run.motion[0]);
    const Eigen::MatrixXd id = inverse_dynamics_along(model_of(run.c.mechanism), tm);
    Residual r;
    r.u = recorded_effort(run.c, i);
    r.id = id.col(Eigen::Index(i));
    r.r = r.u - r.id;
    const int dof = tm.actuated_dof[i];
    r.q = tm.q.col(dof), r.v = tm.v.col(dof), r.a = tm.a.col(dof);
    r.rms_effort = rms(r.u);
    return r;
}

Eigen::MatrixXd columns(std::initializer_list<Eigen::VectorXd> cols) {
    Eigen::MatrixXd X(cols.begin()->size(), Eigen::Index(cols.size()));
    Eigen::Index k = 0;
    for (const auto& c : cols) X.col(k++) = c;
    return X;
}

size_t actuated_index(const GeneratedCase& c, const mbx_test::HiddenEffect& h) {
    for (size_t i = 0; i < c.joint_ids.size(); ++i)
        if (c.joint_ids[i] == h.joint_id) return i;
    FAIL("effect on a joint that is not actuated: " << h.joint_id);
    return 0;
}

Eigen::VectorXd smooth_sign(const Eigen::VectorXd& v, double vs) {
    return v.unaryExpr([vs](double x) { return std::tanh(x / vs); });
}

}  // namespace

// Causes MuJoCo expresses itself: the recorded effort minus mbx's inverse
// dynamics of the nominal model is the effect, with the hidden magnitude.
TEST_CASE("hidden effects: MuJoCo's damping, friction loss and armature show with their hidden values") {
    mbx_test::TempDir dir("mbx_hidden_mujoco");
    struct Item {
        std::string mechanism, cause, subject;
        double low, high;
    };
    const std::vector<Item> items = {
        {"emps_axis", "viscous_friction", "40:-:41", 20, 60},
        {"two_link_arm", "viscous_friction", "two_link_arm/elbow", 0.1, 0.4},
        {"fourbar", "viscous_friction", "fourbar/rev_A", 1.2e-4, 3.5e-4},
        {"emps_axis", "coulomb_friction", "40:-:41", 1, 3},
        {"two_link_arm", "coulomb_friction", "two_link_arm/shoulder", 0.3, 1.0},
        {"emps_axis", "armature", "40:-:41", 2, 5},
        {"two_link_arm", "armature", "two_link_arm/shoulder", 0.03, 0.1},
        {"fourbar", "armature", "fourbar/rev_A", 1e-5, 3e-5},
    };
    int n = 0;
    for (const Item& it : items) {
        CAPTURE(it.mechanism);
        CAPTURE(it.cause);
        const Run r = run(it.mechanism, {{it.cause, it.subject, it.low, it.high}}, dir, 11, "c" + std::to_string(n++));
        REQUIRE(r.c.hidden.size() == 1);
        const auto& h = r.c.hidden[0];
        CHECK(h.cause == it.cause);
        const size_t i = actuated_index(r.c, h);
        const Residual res = residual_of(r, i);
        double truth = 0, estimate = 0;
        if (it.cause == "viscous_friction") {
            truth = h.parameter("damping");
            estimate = regress(columns({res.v}), res.r)[0];
        } else if (it.cause == "coulomb_friction") {
            // Sliding samples only: MuJoCo's friction constraint is soft within a few steps of a reversal.
            truth = h.parameter("coulomb");
            const double band = 0.05 * res.v.cwiseAbs().maxCoeff();
            std::vector<double> ys, ss;
            for (Eigen::Index k = 0; k < res.v.size(); ++k)
                if (std::fabs(res.v[k]) > band) ys.push_back(res.r[k]), ss.push_back(res.v[k] > 0 ? 1 : -1);
            estimate = regress(Eigen::Map<Eigen::VectorXd>(ss.data(), Eigen::Index(ss.size())),
                               Eigen::Map<Eigen::VectorXd>(ys.data(), Eigen::Index(ys.size())))[0];
        } else {
            truth = h.parameter("armature");
            estimate = regress(columns({res.a}), res.r)[0];
        }
        MESSAGE(it.mechanism << " " << it.cause << ": hidden " << truth << ", regressed " << estimate
                             << ", effect RMS / effort RMS " << rms(res.r) / res.rms_effort);
        CHECK(truth >= it.low);
        CHECK(truth <= it.high);
        CHECK(estimate == mbx_test::relative(truth, 0.05));
    }
}

TEST_CASE("hidden effects: a changed body mass is MuJoCo's, seen by mbx's inverse dynamics of the changed body") {
    mbx_test::TempDir dir("mbx_hidden_mass");
    for (const auto& [mech_, body] : std::vector<std::pair<std::string, std::string>>{
             {"two_link_arm", "two_link_arm/forearm"}, {"fourbar", "fourbar/coupler"}}) {
        const std::string& mech = mech_;  // (CAPTURE cannot capture a structured binding)
        CAPTURE(mech);
        const Run r = run(mech, {{"mass_error", body, 0.2, 0.5}}, dir, 5, mech);
        const auto& h = r.c.hidden.at(0);
        CHECK(h.body_id == body);
        const double change = h.parameter("relative_mass_change");
        sim::Model changed = model_of(mech);
        int b = -1;
        for (size_t k = 0; k < changed.bodies.size(); ++k)
            if (changed.bodies[k].id == body) b = int(k);
        REQUIRE(b > 0);
        auto& in = changed.bodies[size_t(b)].inertia;
        in.mass *= 1 + change, in.h *= 1 + change, in.I *= 1 + change;
        CHECK(in.mass == mbx_test::relative(h.parameter("mass"), 1e-6));
        const Eigen::MatrixXd nominal = inverse_dynamics_along(model_of(mech), r.motion[0]);
        const Eigen::MatrixXd right = inverse_dynamics_along(changed, r.motion[0]);
        for (size_t i = 0; i < r.c.joint_ids.size(); ++i) {
            const Eigen::VectorXd u = r.motion[0].applied.col(Eigen::Index(i));
            const double with_change = rms(u - right.col(Eigen::Index(i))) / rms(u);
            const double without = rms(u - nominal.col(Eigen::Index(i))) / rms(u);
            MESSAGE(mech << " joint " << r.c.joint_names[i] << ": mass change " << change << ", error nominal " << without
                         << ", changed " << with_change);
            CHECK(with_change < 1e-6 * (mech == "fourbar" ? 1e3 : 1));
            CHECK(without > 0.03);
        }
    }
}

// The same for a centre of mass moved and an inertia spread along a
// direction off the body's axes: MuJoCo's body frame is not mbx's, so the
// generator's truth (in mbx's body frame) is right only if the frames were
// mapped; calibration's own corrected_inertia applies it.
TEST_CASE("hidden effects: a moved centre of mass and a changed inertia are MuJoCo's, in mbx's body frame") {
    mbx_test::TempDir dir("mbx_hidden_com");
    const Eigen::Vector3d skew_direction = Eigen::Vector3d(0.6, 0.3, 1.0).normalized();
    for (const std::string kind : {"com_shift", "inertia_error"}) {
        CAPTURE(kind);
        const std::string body = "two_link_arm/forearm";
        const double low = kind == "com_shift" ? 0.03 : 0.5;
        const Run r = run("two_link_arm", {{kind, body, low, low, skew_direction}}, dir, 5, kind);
        const auto& h = r.c.hidden.at(0);
        CHECK(h.cause == "mass_error");
        CHECK(h.body_id == body);
        sim::Model changed = model_of("two_link_arm");
        int b = -1;
        for (size_t k = 0; k < changed.bodies.size(); ++k)
            if (changed.bodies[k].id == body) b = int(k);
        REQUIRE(b > 0);
        double shift[3] = {0, 0, 0}, change[6] = {0, 0, 0, 0, 0, 0};
        if (kind == "com_shift") {
            for (int k = 0; k < 3; ++k) shift[k] = h.parameter(calibration::Candidate::kComShiftNames[k]);
            CHECK(Eigen::Vector3d(shift[0], shift[1], shift[2]).norm() == mbx_test::relative(low, 1e-6));
        } else {
            for (int k = 0; k < 6; ++k) change[k] = h.parameter(calibration::Candidate::kInertiaChangeNames[k]);
            CHECK(change[4] != 0);  // off the axes: products of inertia change too
        }
        const double one = 1;
        changed.bodies[size_t(b)].inertia = calibration::corrected_inertia(changed.bodies[size_t(b)].inertia, one, shift, change);
        const Eigen::MatrixXd nominal = inverse_dynamics_along(model_of("two_link_arm"), r.motion[0]);
        const Eigen::MatrixXd right = inverse_dynamics_along(changed, r.motion[0]);
        for (size_t i = 0; i < r.c.joint_ids.size(); ++i) {
            const Eigen::VectorXd u = r.motion[0].applied.col(Eigen::Index(i));
            const double with_change = rms(u - right.col(Eigen::Index(i))) / rms(u);
            const double without = rms(u - nominal.col(Eigen::Index(i))) / rms(u);
            MESSAGE(kind << " joint " << r.c.joint_names[i] << ": error nominal " << without << ", changed " << with_change);
            CHECK(with_change < 1e-6);
            CHECK(without > 0.005);  // (the forearm's inertia is 0.8 % of the shoulder's effort)
        }
    }
}

// Causes made around MuJoCo: the recorded effort and position against
// mbx's inverse dynamics along MuJoCo's motion.
TEST_CASE("hidden effects: effects added by the generator act on MuJoCo's motion with their hidden values") {
    mbx_test::TempDir dir("mbx_hidden_generator");
    const std::string S = "two_link_arm/shoulder", E = "two_link_arm/elbow", P = "40:-:41";

    SUBCASE("effort offset: recorded = inverse dynamics - offset") {
        const Run r = run("two_link_arm", {{"effort_offset", S, 0.3, 1.0}}, dir);
        const Residual res = residual_of(r, 0);
        CHECK(-res.r.mean() == mbx_test::relative(r.c.hidden[0].parameter("offset"), 0.02));
        const Residual other = residual_of(r, 1);
        CHECK(std::fabs(other.r.mean()) < 0.005 * other.rms_effort);
    }
    SUBCASE("actuator gain: gain * recorded = inverse dynamics") {
        const Run r = run("emps_axis", {{"actuator_gain", P, 0.7, 0.9}}, dir);
        const Residual res = residual_of(r, 0);
        CHECK(regress(columns({res.u}), res.id)[0] == mbx_test::relative(r.c.hidden[0].parameter("gain"), 0.01));
    }
    SUBCASE("delay: inverse dynamics at t = recorded effort at t - delay") {
        const Run r = run("two_link_arm", {{"delay", S, 0.004, 0.012}}, dir);
        const double delay = r.c.hidden[0].parameter("delay");
        const TrueMotion tm = from_positions(r.motion[0]);
        const Eigen::MatrixXd id = inverse_dynamics_along(model_of("two_link_arm"), tm);
        const double dt = tm.t[1] - tm.t[0];
        double shifted = 0, unshifted = 0, norm = 0;
        for (size_t k = 100; k + 1 < tm.t.size(); ++k) {
            const double back = double(k) - delay / dt;
            const size_t k0 = size_t(std::floor(back));
            const double w = back - double(k0);
            const double u = (1 - w) * tm.commanded(Eigen::Index(k0), 0) + w * tm.commanded(Eigen::Index(k0 + 1), 0);
            shifted += std::pow(id(Eigen::Index(k), 0) - u, 2);
            unshifted += std::pow(id(Eigen::Index(k), 0) - tm.commanded(Eigen::Index(k), 0), 2);
            norm += std::pow(id(Eigen::Index(k), 0), 2);
        }
        MESSAGE("delay " << delay << ": error shifted " << std::sqrt(shifted / norm) << ", unshifted " << std::sqrt(unshifted / norm));
        CHECK(std::sqrt(shifted / norm) < 2e-3);
        CHECK(std::sqrt(unshifted / norm) > 0.03);
    }
    SUBCASE("sensor offset: recorded position = true position + offset, efforts unchanged") {
        const Run r = run("two_link_arm", {{"sensor_offset", E, -0.1, -0.05}}, dir);
        const double offset = r.c.hidden[0].parameter("offset");
        const Csv csv = read_csv(r.c.fit_csv);
        REQUIRE(csv.header[3] == "elbow.q");
        const TrueMotion& tm = r.motion[0];
        const int dof = tm.actuated_dof[1];
        double worst = 0;
        for (size_t k = 0; k < csv.rows.size(); ++k)
            worst = std::max(worst, std::fabs(csv.rows[k][3] - tm.q(Eigen::Index(k), dof) - offset));
        CHECK(worst <= 0.5 * 2 * M_PI / 40000 + 1e-12);
        const Residual res = residual_of(r, 1);
        CHECK(rms(res.r) < 0.02 * res.rms_effort);  // only noise
    }
    SUBCASE("asymmetric friction: c tanh(v/vs) + dc |tanh(v/vs)|, told from an offset at the rests") {
        const Run r = run("emps_axis", {{"asymmetric_friction", P, 1, 3}}, dir, 7, "case", true);
        const auto& h = r.c.hidden[0];
        const Residual res = residual_of(r, 0);
        const Eigen::VectorXd s = smooth_sign(res.v, h.parameter("smoothing_velocity"));
        const Eigen::VectorXd p = regress(columns({s, s.cwiseAbs()}), res.r);
        CHECK(p[0] == mbx_test::relative(h.parameter("coulomb"), 0.02));
        CHECK(p[1] == mbx_test::relative(h.parameter("coulomb_asymmetry"), 0.03));
        CHECK(h.parameter("coulomb_positive") > h.parameter("coulomb_negative"));
        // Symmetric friction plus a constant offset explains the sliding
        // samples alike; the rests (the slide standing still, the asymmetric
        // part gone) leave it a residual the size of the asymmetry.
        const Eigen::VectorXd asym = res.r - columns({s, s.cwiseAbs()}) * p;
        const Eigen::VectorXd ones = Eigen::VectorXd::Ones(s.size());
        const Eigen::VectorXd off = res.r - columns({s, ones}) * regress(columns({s, ones}), res.r);
        MESSAGE("asymmetric friction: residual RMS as asymmetry " << rms(asym) << ", as offset " << rms(off)
                                                                  << ", noise " << r.motion[0].effort_noise_sigma_first);
        CHECK(rms(off) > 2 * rms(asym));
    }
    SUBCASE("Stribeck friction") {
        const Run r = run("two_link_arm", {{"stribeck_friction", E, 0.1, 0.3}}, dir);
        const auto& h = r.c.hidden[0];
        const Residual res = residual_of(r, 1);
        const double vst = h.parameter("stribeck_velocity");
        Eigen::VectorXd col = smooth_sign(res.v, h.parameter("smoothing_velocity"));
        for (Eigen::Index k = 0; k < col.size(); ++k) col[k] *= std::exp(-std::pow(res.v[k] / vst, 2));
        CHECK(regress(columns({col}), res.r)[0] == mbx_test::relative(h.parameter("stribeck"), 0.03));
    }
    SUBCASE("position-dependent effort: a spring k q") {
        const Run r = run("emps_axis", {{"position_dependent_effort", P, 60, 200}}, dir);
        const Residual res = residual_of(r, 0);
        CHECK(regress(columns({res.q}), res.r)[0] == mbx_test::relative(r.c.hidden[0].parameter("stiffness"), 0.02));
    }
}

TEST_CASE("hidden effects: files parse and the experiment names existing files and columns") {
    mbx_test::TempDir dir("mbx_hidden_files");
    for (const std::string mech : {"emps_axis", "two_link_arm", "fourbar"}) {
        CAPTURE(mech);
        const Run r = run(mech, {}, dir, 3, mech);
        pugi::xml_document doc;
        REQUIRE(doc.load_file(r.c.experiment_path.c_str()));
        const pugi::xml_node e = doc.child("experiment");
        REQUIRE(e);
        CHECK(std::string(e.attribute("version").value()) == "1");
        CHECK(std::string(e.child("drive").attribute("mode").value()) == "effort");
        const std::string time = e.child("time").attribute("column").value();
        std::set<std::string> roles;
        for (pugi::xml_node rec : e.children("record")) {
            const std::filesystem::path path =
                std::filesystem::path(r.c.experiment_path).parent_path() / rec.attribute("file").value();
            REQUIRE(std::filesystem::exists(path));
            roles.insert(rec.attribute("role").value());
            const Csv csv = read_csv(path.string());
            CHECK(csv.rows.size() >= 3000);
            REQUIRE(csv.header.at(0) == time);
            CHECK(csv.header.size() == 1 + 2 * r.c.joint_ids.size());
            for (pugi::xml_node c : e.children("column")) {
                CHECK(std::find(csv.header.begin(), csv.header.end(), std::string(c.attribute("name").value())) !=
                      csv.header.end());
                CHECK(std::find(r.c.joint_ids.begin(), r.c.joint_ids.end(), std::string(c.attribute("joint").value())) !=
                      r.c.joint_ids.end());
            }
            double smallest = 1, largest = 0;
            for (size_t k = 1; k < csv.rows.size(); ++k) {
                smallest = std::min(smallest, csv.rows[k][0] - csv.rows[k - 1][0]);
                largest = std::max(largest, csv.rows[k][0] - csv.rows[k - 1][0]);
            }
            CHECK(smallest == mbx_test::relative(1e-3, 1e-6));  // increasing, at 1 kHz
            CHECK(largest == mbx_test::relative(1e-3, 1e-6));
        }
        CHECK(roles == std::set<std::string>{"fit", "validation"});
        size_t compared = 0;
        for (pugi::xml_node c : e.children("compare")) {
            CHECK(std::string(c.attribute("quantity").value()) == "effort");
            ++compared;
        }
        CHECK(compared == r.c.joint_ids.size());
        // Each joint's id resolves in mbx's model of the input.
        for (const std::string& id : r.c.joint_ids) CHECK(sim::find_joint(model_of(mech), id) >= 0);
        CHECK(std::filesystem::exists(std::filesystem::path(r.c.experiment_path).parent_path() / "truth.json"));
    }
}

TEST_CASE("hidden effects: a seed repeats byte for byte, another seed draws other magnitudes") {
    mbx_test::TempDir da("mbx_hidden_seed"), db("mbx_hidden_seed"), dc("mbx_hidden_seed");
    const std::vector<EffectSpec> effects = {{"viscous_friction", "40:-:41", 20, 60}, {"effort_offset", "40:-:41", 0.8, 2}};
    const Run a = run("emps_axis", effects, da, 21);
    const Run b = run("emps_axis", effects, db, 21);
    const Run c = run("emps_axis", effects, dc, 22);
    for (const char* f : {"fit.csv", "validation.csv", "experiment.xml", "truth.json", "mjcf/emps_axis.xml"}) {
        CAPTURE(f);
        const std::string ta = read_text(da.file(std::string("case/") + f));
        CHECK(!ta.empty());
        CHECK(ta == read_text(db.file(std::string("case/") + f)));
    }
    CHECK(read_text(da.file("case/fit.csv")) != read_text(dc.file("case/fit.csv")));
    for (size_t k = 0; k < effects.size(); ++k)
        CHECK(a.c.hidden[k].parameters[0].second != c.c.hidden[k].parameters[0].second);
}

TEST_CASE("hidden effects: the suite's size, spread and generation time") {
    const std::vector<CaseSpec> suite = mbx_test::hidden_effect_suite(1);
    int single = 0, clean = 0, pairs = 0;
    std::set<std::string> causes, mechanisms, names;
    for (const CaseSpec& s : suite) {
        single += s.effects.size() == 1, clean += s.effects.empty(), pairs += s.effects.size() == 2;
        for (const EffectSpec& e : s.effects) causes.insert(e.cause);
        mechanisms.insert(s.mechanism);
        names.insert(s.name);
    }
    CHECK(single >= 30);
    CHECK(clean >= 6);
    CHECK(pairs >= 3);
    CHECK(names.size() == suite.size());
    CHECK(mechanisms.size() == 3);
    CHECK(causes.size() == mbx_test::generated_causes().size());
    // A different seed, different magnitudes, same list.
    const std::vector<CaseSpec> other = mbx_test::hidden_effect_suite(2);
    REQUIRE(other.size() == suite.size());
    CHECK(other[0].name == suite[0].name);
    CHECK(other[0].seed != suite[0].seed);

    mbx_test::TempDir dir("mbx_hidden_suite");
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<GeneratedCase> cases = mbx_test::generate_suite(suite, dir.path.string());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MESSAGE("suite of " << cases.size() << " cases generated in " << seconds << " s");
    CHECK(cases.size() == suite.size());
    CHECK(std::filesystem::exists(dir.file("truth.json")));
    for (const GeneratedCase& c : cases) {
        CAPTURE(c.name);
        CHECK(std::filesystem::exists(c.experiment_path));
        for (const auto& h : c.hidden) CHECK((!h.joint_id.empty() || !h.body_id.empty()));
    }
}
}  // namespace MBX_UNITY_ID
