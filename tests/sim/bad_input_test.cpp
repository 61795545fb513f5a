// Bad input to the simulator: non-finite states, initial values no loop
// closure can satisfy, consistent initialisation from one fixed coordinate,
// and runs that diverge. Each is an mbx::Error naming the joint or the loop,
// never a crash or NaN in the output.
#include <cmath>
#include <limits>

#include "sim/build_model.h"
#include "sim/simulation.h"
#include "sim_cut_check.h"
#include "tests/export/test_inputs.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

namespace a = xtest::mjcf_assemblies;

template <class F> Error expect_error(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e;
    }
    FAIL("no mbx::Error");
    return Error(MBX_OK, {}, "");
}

bool all_finite(const std::vector<double>& v) {
    for (double x : v)
        if (!std::isfinite(x)) return false;
    return true;
}

// The four-bar built-in's joint centres (world, from the mechanism) and
// whether its crank turned by q about A (the +z axis) lets the coupler and
// rocker reach: |B(q) - D| within the sum and difference of |BC| and |CD|.
struct FourbarGeometry {
    Vec3 A, B, C, D;
    explicit FourbarGeometry(const Mechanism& m) {
        auto at = [&](const char* name) {
            for (const Joint& j : m.joints)
                if (j.name == name) return Vec3(j.frame.position);
            FAIL("no joint " << name);
            return Vec3(Vec3::Zero());
        };
        A = at("rev_A"), B = at("rev_B"), C = at("rev_C"), D = at("rev_D");
    }
    bool reachable(double q) const {
        const Vec3 b = A + Eigen::AngleAxisd(q, Vec3::UnitZ()) * (B - A);
        const double bd = (b - D).norm(), bc = (C - B).norm(), cd = (D - C).norm();
        return bd <= bc + cd && bd >= std::fabs(bc - cd);
    }
};

}  // namespace

TEST_CASE("sim: a non-finite state is an error naming the joint") {
    auto t = xtest::translate(a::double_pendulum());
    const sim::Model m = sim::build_model(*t->mechanism);
    REQUIRE(m.joints.size() == 2);
    const std::string elbow = m.joints[1].name;
    sim::Data d(m);

    Error e = expect_error([&] { sim::initial_state(m, d, {{1, 0, false, std::nan("")}}); });
    CHECK(e.status() == MBX_ERROR_INVALID_INPUT);
    CHECK(e.subject().name == elbow);
    CHECK(std::string(e.what()).find(elbow) != std::string::npos);

    e = expect_error([&] { sim::initial_state(m, d, {{1, 0, true, std::numeric_limits<double>::infinity()}}); });
    CHECK(e.subject().name == elbow);

    sim::initial_state(m, d, {});
    d.v[1] = std::numeric_limits<double>::infinity();
    e = expect_error([&] { sim::check_finite_state(m, d, "now"); });
    CHECK(e.subject().name == elbow);
    CHECK(std::string(e.what()).find(elbow) != std::string::npos);

    sim::Trajectory out;
    sim::RunSettings rs;
    rs.stop_time = 0.1;
    e = expect_error([&] { sim::run(m, d, rs, out); });
    CHECK(e.subject().name == elbow);
    CHECK(all_finite(out.values));
}

TEST_CASE("sim: consistent initialisation: fix the four-bar's crank and the rest follows") {
    auto t = xtest::translate_builtin("fourbar");
    const sim::Model m = sim::build_model(*t->mechanism);
    const int crank = sim::find_joint(m, "rev_A");
    REQUIRE(crank >= 0);
    const FourbarGeometry g(*t->mechanism);
    const double q = 0.5, qd = 1.0;
    REQUIRE(g.reachable(q));
    sim::Data d(m);
    sim::initial_state(m, d, {{crank, 0, false, q}, {crank, 0, true, qd}});
    const sim::JointT<double>& j = m.joints[size_t(crank)];
    CHECK(d.q[j.q_index] == q);
    CHECK(d.v[j.v_index] == qd);
    CHECK((d.q - m.q_reference).norm() > 0.5);  // the others moved with it
    sim::update_positions(m, d);
    sim::update_closure_residual(m, d);
    const double residual = d.residual.lpNorm<Eigen::Infinity>() * m.length_scale;
    const simtest::CutGap gap = simtest::worst_cut_gap(*t->mechanism, m, d);
    // The velocities keep the loop closed: a short move along them opens it
    // only to second order (a velocity off the loop's tangent by 1e-3 m/s
    // would open it by 1e-9 m).
    sim::Data e(m);
    e.q = d.q;
    const double eps = 1e-6;
    for (const auto& jt : m.joints) sim::integrate_joint<double>(jt.kind, e.q.data() + jt.q_index, d.v.data() + jt.v_index, eps);
    sim::update_positions(m, e);
    const simtest::CutGap moved = simtest::worst_cut_gap(*t->mechanism, m, e);
    MESSAGE("four-bar from its crank at " << q << " rad: residual " << residual << " m, cut gap " << gap.distance
                                          << " m, after moving 1e-6 s along the velocities " << moved.distance << " m");
    CHECK(residual < 1e-9);
    CHECK(gap.distance < 1e-9);
    CHECK(gap.angle < 1e-9);
    CHECK(moved.distance < 1e-12);
    CHECK(std::fabs(d.v.norm()) > qd);  // the others move too
}

TEST_CASE("sim: initial values no loop closure can satisfy are an error naming the loop's cut joint") {
    auto t = xtest::translate_builtin("fourbar");
    const sim::Model m = sim::build_model(*t->mechanism);
    const int crank = sim::find_joint(m, "rev_A");
    REQUIRE(crank >= 0);
    REQUIRE(m.closures.size() == 1);
    // The four-bar is a non-Grashof triple rocker: its crank cannot point
    // away from D (|BD| = |AB| + |AD| exceeds |BC| + |CD|).
    const FourbarGeometry g(*t->mechanism);
    const double q = 2.2;
    REQUIRE(!g.reachable(q));
    sim::Data d(m);
    const Error e = expect_error([&] { sim::initial_state(m, d, {{crank, 0, false, q}}); });
    MESSAGE(std::string(e.what()));
    CHECK(e.status() == MBX_ERROR_INVALID_INPUT);
    CHECK(e.subject().kind == MBX_SUBJECT_LOOP);
    CHECK(e.subject().id == "rev_D");
    CHECK(std::string(e.what()).find("'rev_D'") != std::string::npos);
    // A velocity that the fixed crank rate and a fixed rocker rate cannot
    // both satisfy names the loop too.
    const int rocker = sim::find_joint(m, "rev_C");
    REQUIRE(rocker >= 0);
    const Error ev = expect_error([&] {
        sim::initial_state(m, d, {{crank, 0, true, 1.0}, {rocker, 0, true, 0.0}, {sim::find_joint(m, "rev_B"), 0, true, 0.0}});
    });
    MESSAGE(std::string(ev.what()));
    CHECK(ev.subject().id == "rev_D");
}

TEST_CASE("sim: a run that diverges is an error, never NaN output") {
    const a::Pendulum pendulum;
    auto t = xtest::translate(pendulum.assembly());
    SUBCASE("absurd effort") {
        const sim::Model m = sim::build_model(*t->mechanism);
        sim::Data d(m);
        sim::initial_state(m, d, {});
        d.effort[0] = 1e308;  // qacc overflows
        sim::RunSettings rs;
        rs.stop_time = 1;
        sim::Trajectory out;
        const Error e = expect_error([&] { sim::run(m, d, rs, out); });
        MESSAGE(std::string(e.what()));
        CHECK(e.subject().name == m.joints[0].name);
        CHECK(out.rows() >= 1);
        CHECK(all_finite(out.values));
    }
    SUBCASE("a step far past RK4's stability bound") {
        sim::BuildOptions o;
        sim::JointDynamics jd;
        jd.stiffness = 1e4;  // w0 h far above 2.8
        o.joint_dynamics[0] = jd;
        const sim::Model m = sim::build_model(*t->mechanism, o);
        sim::Data d(m);
        sim::initial_state(m, d, {{0, 0, false, 0.1}});
        sim::RunSettings rs;
        rs.integrator.step = 0.5;
        rs.output_step = 0.5;
        rs.stop_time = 1e4;
        sim::Trajectory out;
        const Error e = expect_error([&] { sim::run(m, d, rs, out); });
        MESSAGE(std::string(e.what()) << " after " << out.rows() << " samples");
        CHECK(e.subject().name == m.joints[0].name);
        CHECK(out.rows() >= 2);
        CHECK(out.rows() < 2000);  // it stopped at the divergence, not at the stop time
        CHECK(all_finite(out.values));
    }
}
}  // namespace MBX_UNITY_ID
