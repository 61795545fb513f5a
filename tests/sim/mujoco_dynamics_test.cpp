// mbx's mass matrix and inverse dynamics against MuJoCo's (mj_fullM, mj_rne)
// on mbx's own MJCF export, at random states, for every built-in, every
// sample, the real PMXML exports in ../shared and the small assemblies of the
// MJCF tests: trees, floating bodies and loops.
#include <Eigen/Eigenvalues>
#include <chrono>

#include "sim/dynamics.h"
#include "tests/export/test_inputs.h"
#include "sim_mujoco_support.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

struct Worst {
    double mass = 0, rne = 0;  // largest error relative to the matrix's (vector's) largest entry
};

Worst check_against_mujoco(const simtest::Input& c, int trials) {
    CAPTURE(c.label);
    auto t = c.open();
    mbx_test::TempDir dir("mbx_sim_mj");
    simtest::Pair p = simtest::make_pair(*t, dir);
    mjModel* mm = p.run.model.get();
    mjData* md = p.run.data.get();
    // MuJoCo may have more: the helper slider of a prismatic cut (its velocity stays 0 here).
    REQUIRE(mm->nv >= p.model.nv);
    REQUIRE(p.model.nv > 0);
    sim::Data d(p.model);
    std::mt19937 rng(7);
    Worst worst;
    for (int trial = 0; trial < trials; ++trial) {
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
        const double scale = std::max(1e-300, M_expected.cwiseAbs().maxCoeff());
        const double m_err = (d.M - M_expected).cwiseAbs().maxCoeff() / scale;
        CHECK(m_err < 1e-9);
        worst.mass = std::max(worst.mass, m_err);

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
        const double tscale = std::max(1e-300, tau_expected.cwiseAbs().maxCoeff());
        const double r_err = (tau - tau_expected).cwiseAbs().maxCoeff() / tscale;
        CHECK(r_err < 1e-9);
        worst.rne = std::max(worst.rne, r_err);
    }
    MESSAGE(c.label << ": nv " << p.model.nv << ", loops " << p.model.closures.size() << ", worst relative error M "
                    << worst.mass << ", RNE " << worst.rne);
    return worst;
}

}  // namespace

// Measured worst relative errors (largest entry difference over the largest
// entry) are 1e-15 .. 1e-13: round-off. A wrong inertia transform, axis or
// velocity product shows at 1e-3 or more.
TEST_CASE("sim: mass matrix and inverse dynamics equal MuJoCo's on the small assemblies") {
    for (const simtest::Input& c : simtest::small_inputs()) check_against_mujoco(c, 5);
}

TEST_CASE("sim: mass matrix and inverse dynamics equal MuJoCo's on every built-in") {
    for (const simtest::Input& c : simtest::builtin_inputs()) check_against_mujoco(c, 5);
}

TEST_CASE("sim: mass matrix and inverse dynamics equal MuJoCo's on every sample") {
    for (const simtest::Input& c : simtest::sample_inputs()) check_against_mujoco(c, 5);
}

TEST_CASE("sim: mass matrix and inverse dynamics equal MuJoCo's on the real PMXML exports") {
    for (const simtest::Input& c : simtest::shared_pmxml_inputs()) {
        const auto start = std::chrono::steady_clock::now();
        check_against_mujoco(c, 3);
        MESSAGE(c.label << ": " << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s");
    }
}

// make_pair gives mbx MuJoCo's compiled inertials, so build_model's own are
// checked here: every body with mass in the mechanism has the mass, centre
// of mass and inertia MuJoCo compiled from the export. MuJoCo diagonalises
// fullinertia iteratively (measured: within 5e-8 of the body's
// largest entry, joints_showcase and ironCub the worst); a swapped axis or a missing parallel-axis term
// is off by far more than 1e-6. CAD inertias that break the triangle
// inequality are left out: the export lets MuJoCo balance them.
TEST_CASE("sim: build_model's body inertials are the ones MuJoCo compiles from the export") {
    std::vector<simtest::Input> inputs = simtest::builtin_inputs();
    for (const auto& list : {simtest::sample_inputs(), simtest::shared_pmxml_inputs(), simtest::small_inputs()})
        inputs.insert(inputs.end(), list.begin(), list.end());
    for (const simtest::Input& c : inputs) {
        CAPTURE(c.label);
        auto t = c.open();
        mbx_test::TempDir dir("mbx_sim_inertials");
        const sim::Model model = sim::build_model(*t->mechanism);
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        int checked = 0;
        double worst = 0;
        for (const MjcfBody& b : run.layout.bodies) {
            if (b.body < 0) continue;
            const RigidBody& rb = t->mechanism->bodies[size_t(b.body)];
            const Eigen::SelfAdjointEigenSolver<Mat3> eig(rb.inertia);
            const Vec3 p = eig.eigenvalues();
            if (!(rb.mass > 0) || p[0] + p[1] < p[2] * (1 + 1e-9)) continue;
            const sim::Inertia<double> mine = model.bodies[size_t(model.body_of_source[size_t(b.body)])].inertia;
            const sim::Inertia<double> theirs =
                simtest::mujoco_inertia(run.model.get(), mj_name2id(run.model.get(), mjOBJ_BODY, b.name.c_str()));
            CAPTURE(b.name);
            CHECK(std::fabs(mine.mass - theirs.mass) <= 1e-12 * theirs.mass);
            CHECK((mine.h - theirs.h).norm() <= 1e-12 * theirs.mass * std::max(1.0, theirs.h.norm() / theirs.mass));
            const double e = (mine.I - theirs.I).cwiseAbs().maxCoeff() / theirs.I.cwiseAbs().maxCoeff();
            CHECK(e < 1e-6);
            worst = std::max(worst, e);
            ++checked;
        }
        CHECK(checked > 0);
        MESSAGE(c.label << ": " << checked << " bodies, worst inertia difference " << worst);
    }
}
}  // namespace MBX_UNITY_ID
