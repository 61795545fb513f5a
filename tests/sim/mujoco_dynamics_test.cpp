// mbx's mass matrix and inverse dynamics against MuJoCo's (mj_fullM, mj_rne)
// on mbx's own MJCF export, at random states, for trees and loops.
#include <functional>

#include "mujoco_assemblies.h"
#include "sim/dynamics.h"
#include "sim_mujoco_support.h"

using namespace mbx;

namespace {

struct Case {
    std::string label;
    std::function<std::unique_ptr<xtest::Translated>()> open;
};

std::vector<Case> cases() {
    return {
        {"pendulum", [] { return xtest::translate(xtest::mjcf_assemblies::Pendulum().assembly()); }},
        {"tumbler (free body)", [] { return xtest::translate(xtest::mjcf_assemblies::Tumbler().assembly()); }},
        {"double pendulum", [] { return xtest::translate(xtest::mjcf_assemblies::double_pendulum()); }},
        {"spatial (universal, spherical, cylindrical, floating)",
         [] { return xtest::translate(xtest::mjcf_assemblies::spatial()); }},
        {"slider_crank", [] { return xtest::translate(xtest::mjcf_assemblies::slider_crank()); }},
        {"fourbar", [] { return xtest::translate_builtin("fourbar"); }},
        {"double_cardan", [] { return xtest::translate_builtin("double_cardan"); }},
        {"planar_sixbar", [] { return xtest::translate_builtin("planar_sixbar"); }},
        {"six_axis_arm", [] { return xtest::translate_builtin("six_axis_arm"); }},
    };
}

}  // namespace

TEST_CASE("sim: mass matrix and inverse dynamics equal MuJoCo's at random states") {
    for (const Case& c : cases()) {
        CAPTURE(c.label);
        auto t = c.open();
        mbx_test::TempDir dir("mbx_sim_mj");
        simtest::Pair p = simtest::make_pair(*t, dir);
        mjModel* mm = p.run.model.get();
        mjData* md = p.run.data.get();
        // MuJoCo may have more: the helper slider of a prismatic cut (its velocity stays 0 here).
        REQUIRE(mm->nv >= p.model.nv);
        sim::Data d(p.model);
        std::mt19937 rng(7);
        for (int trial = 0; trial < 5; ++trial) {
            Eigen::VectorXd q, v;
            simtest::random_state(p.model, rng, q, v);
            d.q = q;
            d.v = v;
            sim::update_kinematics(p.model, d);
            sim::mass_matrix(p.model, d);
            p.to_mujoco(q, v);
            mj_forward(mm, md);
            Eigen::MatrixXd Mj(mm->nv, mm->nv);
            std::vector<mjtNum> dense(size_t(mm->nv * mm->nv));
            mj_fullM(mm, dense.data(), md->qM);
            for (int r = 0; r < mm->nv; ++r)
                for (int k = 0; k < mm->nv; ++k) Mj(r, k) = dense[size_t(r * mm->nv + k)];
            const Eigen::MatrixXd M_expected = p.T.transpose() * Mj * p.T;
            const double scale = std::max(1.0, M_expected.cwiseAbs().maxCoeff());
            CHECK((d.M - M_expected).cwiseAbs().maxCoeff() < 1e-9 * scale);

            Eigen::VectorXd qacc(p.model.nv);
            std::uniform_real_distribution<double> acc(-3, 3);
            for (int i = 0; i < p.model.nv; ++i) qacc[i] = acc(rng);
            Eigen::VectorXd tau;
            sim::inverse_dynamics(p.model, d, qacc, tau);
            const Eigen::VectorXd qacc_mj = p.T * qacc;  // rates map linearly; no extra bias for hinges, slides, balls
            for (int i = 0; i < mm->nv; ++i) md->qacc[i] = qacc_mj[i];
            std::vector<mjtNum> rne(size_t(mm->nv));
            mj_rne(mm, md, 1, rne.data());
            const Eigen::VectorXd tau_expected = p.T.transpose() * Eigen::Map<Eigen::VectorXd>(rne.data(), mm->nv);
            const double tscale = std::max(1.0, tau_expected.cwiseAbs().maxCoeff());
            CHECK((tau - tau_expected).cwiseAbs().maxCoeff() < 1e-9 * tscale);
        }
    }
}
