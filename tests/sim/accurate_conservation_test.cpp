// The accurate mode (CVODE with error control) against closed-form results:
// a passive chain conserves its energy, a compound pendulum swings with the
// period of the elliptic integral, and a loop mechanism stays closed.
#include <cmath>
#include <cstdio>

#include "tests/export/export_fixture.h"
#include "tests/export/mujoco_assemblies.h"
#include "sim/build_model.h"
#include "sim/cvode_session.h"
#include "sim/simulation.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

sim::RunSettings accurate(double stop, double tolerance, double output_step) {
    sim::RunSettings rs;
    rs.integrator.kind = sim::IntegratorKind::Accurate;
    rs.integrator.tolerance = tolerance;
    rs.integrator.step = 0;
    rs.stop_time = stop;
    rs.output_step = output_step;
    return rs;
}

size_t column(const sim::Trajectory& t, const std::string& name) {
    for (size_t c = 0; c < t.columns.size(); ++c)
        if (t.columns[c] == name) return c;
    FAIL("no column " << name);
    return 0;
}

double total_energy(const sim::Model& m, sim::Data& d) {
    sim::update_kinematics(m, d);
    double k = 0, g = 0, s = 0;
    sim::energy(m, d, k, g, s);
    return k + g + s;
}

}  // namespace

TEST_CASE("sim accurate: a passive double pendulum conserves its energy over 10 s") {
    auto t = xtest::translate(xtest::mjcf_assemblies::double_pendulum());
    const sim::Model m = sim::build_model(*t->mechanism);
    REQUIRE(m.nv == 2);
    sim::Data d(m);
    d.q << 1.2, -0.7;  // released from rest well away from hanging: a chaotic swing
    const double e0 = total_energy(m, d);
    sim::Trajectory out;
    const sim::RunSummary s = sim::run(m, d, accurate(10.0, 1e-10, 0.01), out);
    REQUIRE(out.rows() == 1001);
    CHECK(s.energy_start == mbx_test::relative(e0, 1e-14));
    CHECK(s.energy_drift_relative <= 1e-6);
    // The energy the motion exchanges (largest kinetic energy) as a scale that
    // does not depend on where gravity's potential is zero.
    double kinetic_max = 0;
    const size_t c1 = column(out, m.joints[0].name + ".qd"), c2 = column(out, m.joints[1].name + ".qd");
    const size_t q1 = column(out, m.joints[0].name + ".q"), q2 = column(out, m.joints[1].name + ".q");
    for (size_t r = 0; r < out.rows(); ++r) {
        const double* row = &out.values[r * out.columns.size()];
        d.q << row[q1], row[q2];
        d.v << row[c1], row[c2];
        sim::update_kinematics(m, d);
        double k = 0, g = 0, sp = 0;
        sim::energy(m, d, k, g, sp);
        kinetic_max = std::max(kinetic_max, k);
    }
    REQUIRE(kinetic_max > 1.0);
    CHECK(s.energy_drift / kinetic_max <= 1e-6);
    std::printf("[accurate conservation] double pendulum 10 s, tolerance 1e-10: energy drift %.3g J (%.3g of E0 = %.4g J, "
                "%.3g of the largest kinetic energy %.4g J); %lld steps, %lld evaluations, %.3f s wall\n",
                s.energy_drift, s.energy_drift_relative, s.energy_start, s.energy_drift / kinetic_max, kinetic_max,
                s.stats.steps, s.stats.evaluations, s.wall_time);
}

TEST_CASE("sim accurate: a compound pendulum's period is the elliptic-integral period of its amplitude") {
    const xtest::mjcf_assemblies::Pendulum shape;
    auto t = xtest::translate(shape.assembly());
    const sim::Model m = sim::build_model(*t->mechanism);
    REQUIRE(m.nv == 1);
    const double I = shape.pivot_inertia(), arm = shape.arm(), theta0 = 0.5;
    const double g = sim::kDefaultGravity;
    // T = 4 sqrt(I / (m g d)) K(sin(theta0 / 2)) = 2 pi sqrt(I / (m g d)) / AGM(1, cos(theta0 / 2)).
    double a = 1, b = std::cos(theta0 / 2);
    for (int k = 0; k < 10; ++k) {
        const double an = 0.5 * (a + b);
        b = std::sqrt(a * b);
        a = an;
    }
    const double T_small = 2 * M_PI * std::sqrt(I / (shape.mass * g * arm));
    const double T_exact = T_small / a;
    sim::Data d(m);
    d.q[0] = theta0;
    sim::Trajectory out;
    const double dt = 1e-3;
    const sim::RunSummary s = sim::run(m, d, accurate(3.2 * T_exact, 1e-11, dt), out);
    const size_t cq = column(out, m.joints[0].name + ".q"), cv = column(out, m.joints[0].name + ".qd");
    const size_t nc = out.columns.size();
    // Upward zero crossings of q, placed by the cubic Hermite interpolant of
    // (q, qd) between samples (interpolation error ~1e-12 s at this spacing).
    std::vector<double> crossings;
    for (size_t r = 1; r < out.rows(); ++r) {
        const double* p = &out.values[(r - 1) * nc];
        const double* n = &out.values[r * nc];
        if (!(p[cq] < 0 && n[cq] >= 0)) continue;
        const double h = n[0] - p[0];
        auto hermite = [&](double u) {
            const double u2 = u * u, u3 = u2 * u;
            return (2 * u3 - 3 * u2 + 1) * p[cq] + (u3 - 2 * u2 + u) * h * p[cv] + (-2 * u3 + 3 * u2) * n[cq] +
                   (u3 - u2) * h * n[cv];
        };
        double lo = 0, hi = 1;
        for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            (hermite(mid) < 0 ? lo : hi) = mid;
        }
        crossings.push_back(p[0] + 0.5 * (lo + hi) * h);
    }
    REQUIRE(crossings.size() == 3);
    const double T = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
    const double rel = std::fabs(T - T_exact) / T_exact;
    CHECK(rel < 1e-7);
    // The finite amplitude matters at this precision: 1.6 % longer than small-angle.
    CHECK(std::fabs(T - T_small) / T_small > 1e-2);
    std::printf("[accurate conservation] pendulum, amplitude %.2f rad: period %.12f s, elliptic %.12f s (relative "
                "error %.3g; small-angle %.6f s); %lld steps\n",
                theta0, T, T_exact, rel, T_small, s.stats.steps);
}

TEST_CASE("sim accurate: the four-bar stays closed within 1e-9 m over 10 s") {
    auto t = xtest::translate_builtin("fourbar");
    const sim::Model m = sim::build_model(*t->mechanism);
    REQUIRE(!m.closures.empty());
    sim::Data d(m);
    sim::initial_state(m, d, {{0, 0, true, 2.0}});  // the crank set turning at 2 rad/s, the rest follows
    sim::Trajectory out;
    const sim::RunSummary s = sim::run(m, d, accurate(10.0, 1e-8, 0.01), out);
    CHECK(s.stats.max_closure_residual <= 1e-9);
    // Independently of the run's own statistic: every sample's closure residual.
    const size_t nc = out.columns.size();
    double worst = 0;
    sim::Data check(m);
    for (size_t r = 0; r < out.rows(); ++r) {
        const double* row = &out.values[r * nc];
        size_t c = 1;
        for (const sim::JointT<double>& j : m.joints) {
            for (int k = 0; k < j.nq(); ++k) check.q[j.q_index + k] = row[c++];
            c += size_t(j.nv());
        }
        sim::update_positions(m, check);
        sim::update_closure_residual(m, check);
        // Rows are scaled: linear ones by 1 / length_scale.
        worst = std::max(worst, check.residual.lpNorm<Eigen::Infinity>() * m.length_scale);
    }
    CHECK(worst <= 1e-9);
    CHECK(s.energy_drift_relative <= 1e-5);
    std::printf("[accurate conservation] four-bar 10 s, tolerance 1e-8: largest closure residual %.3g m after steps, "
                "%.3g m in the samples; energy drift %.3g relative; %lld steps, %lld evaluations, %.3f s wall\n",
                s.stats.max_closure_residual, worst, s.energy_drift_relative, s.stats.steps, s.stats.evaluations,
                s.wall_time);
}

TEST_CASE("sim accurate: a tumbling free body keeps its momentum and a unit quaternion") {
    const xtest::mjcf_assemblies::Tumbler shape;
    auto t = xtest::translate(shape.assembly());
    sim::BuildOptions options;
    options.gravity = Eigen::Vector3d::Zero();
    const sim::Model m = sim::build_model(*t->mechanism, options);
    REQUIRE(m.nv == 6);
    REQUIRE(m.joints[0].kind == sim::JointKind::Free);
    sim::Data d(m);
    d.v << 0.1, 0.05, -0.2, 3.0, 1.0, -2.0;  // spinning off every principal axis: it tumbles
    // Spatial momentum about the world origin, in world axes: constant without forces.
    auto momentum = [&](sim::Data& at) {
        sim::update_kinematics(m, at);
        const Eigen::Matrix<double, 6, 1> body = m.bodies[1].inertia * at.vel[1];
        return Eigen::Matrix<double, 6, 1>(at.x_world[1].force_to_parent(body));
    };
    const Eigen::Matrix<double, 6, 1> h0 = momentum(d);
    const double e0 = total_energy(m, d);
    sim::IntegratorSettings is;
    is.kind = sim::IntegratorKind::Accurate;
    is.tolerance = 1e-10;
    is.step = 0;
    sim::AccurateRequest r;
    r.stop_time = 5.0;
    for (int k = 1; k <= 500; ++k) r.sample_times.push_back(0.01 * k);
    double worst_h = 0, worst_e = 0, worst_norm = 0;
    r.sample = [&](sim::Data& at) {
        worst_norm = std::max(worst_norm, std::fabs(at.q.segment<4>(3).norm() - 1));
        worst_h = std::max(worst_h, (momentum(at) - h0).norm() / h0.norm());
        worst_e = std::max(worst_e, std::fabs(total_energy(m, at) - e0) / e0);
    };
    sim::accurate_advance(m, d, is, r);
    CHECK(worst_h < 1e-7);
    CHECK(worst_e < 1e-7);
    CHECK(worst_norm < 1e-14);
    std::printf("[accurate conservation] free body 5 s, tolerance 1e-10: momentum drift %.3g, energy drift %.3g "
                "(relative), |quaternion| - 1 up to %.3g; %lld steps\n",
                worst_h, worst_e, worst_norm, d.stats.steps);
}
}  // namespace MBX_UNITY_ID
