// The dynamics core templated on the scalar: run with Ceres' Jet, the
// derivatives it carries equal central finite differences of the double
// model, for parameters calibration will fit (a body's mass, a joint's
// damping) and for the state. A wrong template path (a double-only shortcut
// that drops the dual part) gives a zero or wrong derivative. The Jet is the
// simulation fit's own (calibration/simulation/fit_scalar.h), so these are
// the compiled instances calibration differentiates with.

#include <doctest/doctest.h>

#include "tests/export/export_fixture.h"
#include "sim/build_model.h"
#include "calibration/simulation/fit_scalar.h"
#include "sim/joint_forces.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

// A central difference with h = 1e-6 agrees with the exact derivative to about
// 1e-5 of its size; below 1e-6 its rounding (eps / h) takes over.
constexpr const char* kCentralDifference = "a central difference: 1e-5 relative above its rounding floor";

using namespace mbx;
using Jet = mbx::calibration::FitJet;
using mbx::sim::Vec3T;
using mbx::sim::VecXT;

namespace {

// Tree forward dynamics of the six-axis arm at a fixed state, as a function
// of the mass of body `body` and the damping of joint `joint`.
template <class S>
VecXT<S> arm_qacc(const sim::ModelT<double>& base, int body, int joint, const S& mass, const S& damping) {
    sim::ModelT<S> m = base.template cast<S>();
    sim::Inertia<S>& I = m.bodies[size_t(body)].inertia;
    const S scale = mass / S(base.bodies[size_t(body)].inertia.mass);
    I.mass = I.mass * scale, I.h = I.h * scale, I.I = I.I * scale;  // same shape, more material
    m.joints[size_t(joint)].dynamics.damping = damping;
    sim::DataT<S> d(m);
    for (int i = 0; i < m.nv; ++i) {
        d.q[i] = S(0.3 * std::sin(1.0 + i));
        d.v[i] = S(0.8 * std::cos(2.0 + i));
    }
    sim::passive_forces(m, d, sim::FrictionLaw::Regularised);
    d.qfrc_total = d.qfrc_passive;
    sim::forward_dynamics(m, d);
    return d.qacc;
}

}  // namespace

TEST_CASE("sim: Jets through forward dynamics carry the derivatives finite differences give") {
    auto t = xtest::translate_builtin("six_axis_arm");
    const sim::Model model = sim::build_model(*t->mechanism);
    REQUIRE(model.nv >= 6);
    REQUIRE(model.closures.empty());
    const int body = 3, joint = 2;
    const double mass = model.bodies[body].inertia.mass, damping = 0.7;
    REQUIRE(mass > 0);

    const VecXT<Jet> jet = arm_qacc<Jet>(model, body, joint, Jet(mass, 0), Jet(damping, 1));
    const double hm = 1e-6 * mass, hb = 1e-6;
    const Eigen::VectorXd dm = (arm_qacc<double>(model, body, joint, mass + hm, damping) -
                                arm_qacc<double>(model, body, joint, mass - hm, damping)) / (2 * hm);
    const Eigen::VectorXd db = (arm_qacc<double>(model, body, joint, mass, damping + hb) -
                                arm_qacc<double>(model, body, joint, mass, damping - hb)) / (2 * hb);
    const Eigen::VectorXd plain = arm_qacc<double>(model, body, joint, mass, damping);
    double largest_dm = 0, largest_db = 0;
    for (int i = 0; i < model.nv; ++i) {
        CAPTURE(i);
        CHECK(jet[i].a == mbx_test::relative(plain[i], 1e-12));
        CHECK(jet[i].v[0] == mbx_test::within(dm[i], 1e-5 * (std::fabs(dm[i]) + 1e-6), kCentralDifference));
        CHECK(jet[i].v[1] == mbx_test::within(db[i], 1e-5 * (std::fabs(db[i]) + 1e-6), kCentralDifference));
        largest_dm = std::max(largest_dm, std::fabs(dm[i]));
        largest_db = std::max(largest_db, std::fabs(db[i]));
    }
    // The parameters really move the accelerations, so the comparison means something.
    CHECK(largest_dm > 1e-3);
    CHECK(largest_db > 1e-3);
}

TEST_CASE("sim: Jets through the loop-closed solve of the four-bar") {
    auto t = xtest::translate_builtin("fourbar");
    const sim::Model model = sim::build_model(*t->mechanism);
    REQUIRE(!model.closures.empty());
    auto qacc = [&](auto g) {
        using S = decltype(g);
        sim::ModelT<S> m = model.template cast<S>();
        m.gravity = Vec3T<S>(S(0), g, S(-9.81));
        sim::DataT<S> d(m);
        d.qfrc_total.setZero(m.nv);
        sim::forward_dynamics(m, d);
        return d.qacc;
    };
    const VecXT<Jet> jet = qacc(Jet(2.0, 0));
    const double h = 1e-6;
    const Eigen::VectorXd fd = (qacc(2.0 + h) - qacc(2.0 - h)) / (2 * h);
    double largest = 0;
    for (int i = 0; i < model.nv; ++i) {
        CHECK(jet[i].v[0] == mbx_test::within(fd[i], 1e-5 * (std::fabs(fd[i]) + 1e-6), kCentralDifference));
        largest = std::max(largest, std::fabs(fd[i]));
    }
    CHECK(largest > 1e-3);
}
}  // namespace MBX_UNITY_ID
