// Massless joint nodes: a universal joint as two revolutes and a spherical
// as three (nodes between them weigh nothing in mbx's model), a chain that
// ends at a cut joint (the double cardan's leaf node), and motion that
// nothing determines, which must be an error naming the joint.
#include <cmath>

#include "sim/simulation.h"
#include "tests/export/test_inputs.h"
#include "sim_mujoco_support.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx_stub::build;

namespace {

namespace a = xtest::mjcf_assemblies;

// A bob hanging from the ground by one CAD joint made of `chain`.
mbx_stub::Assembly hanging(const std::string& name, const std::vector<Prim>& chain) {
    mbx_stub::Assembly as;
    as.name = name;
    Builder b(as, name, a::kSI, a::kSI);
    b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, Mat3::Identity(), Vec3::Zero(), Vec3::Zero(),
           box_inertia(1.0, 0.1, 0.1, 0.1));
    b.body("bob", "Bob", 0, 1.3, axis_angle(Vec3(1, 2, 3), 0.5), Vec3(0.05, 0.02, 0.7), Vec3(0.06, 0.03, 0.68),
           box_inertia(1.3, 0.05, 0.08, 0.3));
    b.joint("hinge", "ground", "bob", Vec3(0, 0, 1), Mat3::Identity(), chain, a::kWorld, a::kWorld);
    return as;
}

// A planar four-bar (x-z plane, hinges about y) whose coupler joint is
// `coupler_chain`.
mbx_stub::Assembly fourbar_with(const std::vector<Prim>& coupler_chain) {
    mbx_stub::Assembly as;
    as.name = "fourbar_nodes";
    Builder b(as, "fourbar_nodes", a::kSI, a::kSI);
    const Vec3 A(0, 0, 0.5), B(0.03, 0, 0.54), C(0.12, 0, 0.57), D(0.13, 0, 0.5), y = Vec3::UnitY();
    const Mat3 I = Mat3::Identity();
    b.body("ground", "Ground", MBX_BODY_GROUND, 5.0, I, Vec3::Zero(), Vec3(0.06, 0, 0.45), box_inertia(5.0, 0.2, 0.05, 0.05));
    b.body("crank", "Crank", 0, 0.2, rotation_x_to(B - A, y), A, (A + B) / 2, box_inertia(0.2, 0.05, 0.01, 0.01));
    b.body("coupler", "Coupler", 0, 0.3, rotation_x_to(C - B, y), B, (B + C) / 2, box_inertia(0.3, 0.1, 0.01, 0.01));
    b.body("rocker", "Rocker", 0, 0.25, rotation_x_to(C - D, y), D, (C + D) / 2, box_inertia(0.25, 0.07, 0.01, 0.01));
    b.joint("rev_a", "ground", "crank", A, I, {revolute(y)}, a::kWorld, a::kWorld);
    b.joint("rev_b", "crank", "coupler", B, I, coupler_chain, a::kWorld, a::kWorld);
    b.joint("rev_c", "coupler", "rocker", C, I, {revolute(y)}, a::kWorld, a::kWorld);
    b.joint("rev_d", "rocker", "ground", D, I, {revolute(y)}, a::kWorld, a::kWorld);
    return as;
}

}  // namespace

// mbx's nodes weigh nothing; MuJoCo merges a node chain into the bob's body
// (several joints on one body), so the two describe the same mechanism
// exactly. Measured agreement of the accelerations ~1e-15 relative.
TEST_CASE("sim: a universal and a three-revolute joint with massless nodes move as MuJoCo says") {
    for (const auto& [label_, chain] : std::vector<std::pair<std::string, std::vector<Prim>>>{
             {"universal", {revolute(Vec3(1, 0, 0)), revolute(Vec3(0, 1, 0.2))}},
             {"three revolutes", {revolute(Vec3(1, 0, 0)), revolute(Vec3(0, 1, 0)), revolute(Vec3(0.1, 0.2, 1))}}}) {
        const std::string& label = label_;  // (CAPTURE cannot capture a structured binding)
        CAPTURE(label);
        auto t = xtest::translate(hanging("nodes", chain));
        mbx_test::TempDir dir("mbx_sim_nodes");
        simtest::Pair p = simtest::make_pair(*t, dir);
        REQUIRE(p.model.nv == int(chain.size()));
        int massless = 0;
        for (size_t b = 1; b < p.model.bodies.size(); ++b) massless += p.model.bodies[b].inertia.mass == 0;
        REQUIRE(massless == int(chain.size()) - 1);  // the nodes, untouched by make_pair
        mjModel* mm = p.run.model.get();
        mjData* md = p.run.data.get();
        REQUIRE(mm->nv == p.model.nv);
        sim::Data d(p.model);
        std::mt19937 rng(3);
        double worst = 0;
        for (int trial = 0; trial < 5; ++trial) {
            Eigen::VectorXd q, v;
            simtest::random_state(p.model, rng, q, v);
            d.q = q, d.v = v;
            sim::evaluate(p.model, d, sim::FrictionLaw::Regularised);
            p.to_mujoco(q, v);
            mj_forward(mm, md);
            const Eigen::VectorXd expected = p.T.transpose() * Eigen::Map<Eigen::VectorXd>(md->qacc, mm->nv);
            REQUIRE(d.qacc.allFinite());
            worst = std::max(worst, (d.qacc - expected).cwiseAbs().maxCoeff() / expected.cwiseAbs().maxCoeff());
        }
        MESSAGE(label << ": largest relative difference of qacc from MuJoCo's " << worst);
        CHECK(worst < 1e-9);
    }
}

// The double cardan's second cross is a node (no part of its own) whose
// chain ends at the cut joint: build_model gives it no mass, and the loop
// closure determines its motion. MJCF needs a stand-in mass there (MuJoCo
// refuses a massless leaf); with that mass in mbx's model the accelerations
// differ from the massless ones in proportion to it, so the massless model is
// the limit of the one MuJoCo agrees with (mujoco_trajectory_test: 3e-8 rad).
// Measured: differences of 3.9e-7 and 3.9e-8 of the largest acceleration for
// the export's stand-in mass and a tenth of it.
TEST_CASE("sim: a massless node whose chain ends at a cut joint is determined by the loop") {
    auto t = xtest::translate_builtin("double_cardan");
    const sim::Model massless = sim::build_model(*t->mechanism);
    int leaf = -1;
    for (size_t b = 1; b < massless.bodies.size(); ++b)
        if (massless.bodies[b].inertia.mass == 0) leaf = int(b);
    REQUIRE(leaf > 0);
    bool ends_at_cut = false;
    for (const auto& c : massless.closures) ends_at_cut |= c.body_a == leaf || c.body_b == leaf;
    CHECK(ends_at_cut);

    sim::Data d(massless);
    sim::initial_state(massless, d, {{0, 0, true, 1.5}});
    sim::evaluate(massless, d, sim::FrictionLaw::Regularised);
    REQUIRE(d.qacc.allFinite());
    const Eigen::VectorXd qacc0 = d.qacc;

    mbx_test::TempDir dir("mbx_sim_leaf");
    const xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
    const double stand_in = run.layout.light_mass;
    REQUIRE(stand_in > 0);
    std::vector<double> differences;
    for (const double mass : {stand_in, stand_in / 10}) {
        sim::Model weighted = massless;
        weighted.bodies[size_t(leaf)].inertia = sim::Inertia<double>::from_com(
            mass, Eigen::Vector3d::Zero(), run.layout.light_inertia * mass / stand_in * Eigen::Matrix3d::Identity());
        sim::Data e(weighted);
        e.q = d.q, e.v = d.v;
        sim::evaluate(weighted, e, sim::FrictionLaw::Regularised);
        differences.push_back((e.qacc - qacc0).cwiseAbs().maxCoeff() / qacc0.cwiseAbs().maxCoeff());
    }
    MESSAGE("leaf node: qacc moves by " << differences[0] << " (stand-in " << stand_in << " kg) and " << differences[1]
                                        << " (a tenth of it) of the largest acceleration");
    CHECK(differences[0] < 1e-5);
    CHECK(differences[0] > 0);
    CHECK(differences[1] / differences[0] == mbx_test::relative(0.1, 0.05));  // linear in the mass: continuous at 0
}

TEST_CASE("sim: a massless node that nothing determines is an error naming its joint") {
    SUBCASE("tree: two coaxial revolutes with a node between them") {
        auto t = xtest::translate(hanging("coaxial", {revolute(Vec3(0, 1, 0)), revolute(Vec3(0, 1, 0))}));
        const sim::Model m = sim::build_model(*t->mechanism);
        REQUIRE(m.nv == 2);
        sim::Data d(m);
        sim::initial_state(m, d, {});
        // The node's spin (first hinge forward, second back) moves no mass.
        const std::string node_joint = m.joints[0].name;
        try {
            sim::evaluate(m, d, sim::FrictionLaw::Regularised);
            FAIL("forward dynamics accepted an undetermined node");
        } catch (const Error& e) {
            MESSAGE(std::string(e.what()));
            CHECK(e.status() == MBX_ERROR_INVALID_INPUT);
            CHECK(e.subject().name == node_joint);
            CHECK(std::string(e.what()).find("'" + node_joint + "'") != std::string::npos);
        }
        // The same chain with its axes apart is a universal joint: determined.
        auto u = xtest::translate(hanging("universal", {revolute(Vec3(0, 1, 0)), revolute(Vec3(1, 0, 0))}));
        const sim::Model mu = sim::build_model(*u->mechanism);
        sim::Data du(mu);
        sim::initial_state(mu, du, {{0, 0, false, 0.3}});
        sim::evaluate(mu, du, sim::FrictionLaw::Regularised);
        CHECK(du.qacc.allFinite());
    }
    SUBCASE("loop: a four-bar whose coupler joint is two coaxial revolutes") {
        auto t = xtest::translate(fourbar_with({revolute(Vec3::UnitY()), revolute(Vec3::UnitY())}));
        const sim::Model m = sim::build_model(*t->mechanism);
        REQUIRE(!m.closures.empty());
        sim::Data d(m);
        sim::initial_state(m, d, {});
        try {
            sim::evaluate(m, d, sim::FrictionLaw::Regularised);
            FAIL("forward dynamics accepted an undetermined node");
        } catch (const Error& e) {
            MESSAGE(std::string(e.what()));
            // Either hinge of the coaxial pair alone moves only the node.
            const std::string named = e.subject().name;
            CHECK(named.rfind("rev_b", 0) == 0);
            CHECK(std::string(e.what()).find("'" + named + "'") != std::string::npos);
        }
        // With one hinge there, the four-bar is determined.
        auto ok = xtest::translate(fourbar_with({revolute(Vec3::UnitY())}));
        const sim::Model mo = sim::build_model(*ok->mechanism);
        sim::Data dd(mo);
        sim::initial_state(mo, dd, {{0, 0, true, 1.0}});
        sim::evaluate(mo, dd, sim::FrictionLaw::Regularised);
        CHECK(dd.qacc.allFinite());
    }
}
}  // namespace MBX_UNITY_ID
