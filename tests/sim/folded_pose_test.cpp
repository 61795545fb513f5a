// Body poses of revolute and prismatic joints come from terms folded once
// per model (JointT::prepare_pose); they must be the composition
// parent_to_joint * (joint motion) * joint_to_child they replace, at any
// angle or displacement, also in a model cast to another scalar. Checked
// against the composition written out here on every test input with such
// joints (hinges at general axes, sliders, cut joints of both kinds).
#include <doctest/doctest.h>

#include <random>

#include "sim/build_model.h"
#include "sim/dynamics.h"
#include "tests/export/test_inputs.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// World poses by composing the three transforms per joint.
std::vector<sim::Transform<double>> composed_poses(const sim::Model& m, const Eigen::VectorXd& q) {
    std::vector<sim::Transform<double>> x(m.bodies.size());
    for (size_t b = 1; b < m.bodies.size(); ++b) {
        const sim::JointT<double>& j = m.joints[b - 1];
        const sim::Transform<double> motion = sim::joint_transform<double>(j.kind, j.axis, q.data() + j.q_index);
        x[b] = x[size_t(m.bodies[b].parent)] * (j.parent_to_joint * motion * j.joint_to_child);
    }
    return x;
}

double pose_gap(const sim::Transform<double>& a, const sim::Transform<double>& b) {
    return std::max((a.R - b.R).lpNorm<Eigen::Infinity>(), (a.p - b.p).lpNorm<Eigen::Infinity>());
}

}  // namespace

TEST_CASE("sim: folded revolute and prismatic poses equal the composed joint transforms") {
    std::vector<simtest::Input> inputs = simtest::builtin_inputs();
    for (simtest::Input& in : simtest::small_inputs()) inputs.push_back(std::move(in));
    for (simtest::Input& in : simtest::sample_inputs()) inputs.push_back(std::move(in));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> angle(-3.0, 3.0);
    int folded = 0, prismatic = 0;
    for (const simtest::Input& in : inputs) {
        CAPTURE(in.label);
        auto t = in.open();
        const sim::Model m = sim::build_model(*t->mechanism);
        for (const sim::JointT<double>& j : m.joints) {
            const bool one_dof = j.kind == sim::JointKind::Revolute || j.kind == sim::JointKind::Prismatic;
            CHECK(j.pose_prepared == one_dof);
            folded += one_dof;
            prismatic += j.kind == sim::JointKind::Prismatic;
        }
        const sim::ModelT<double> cast = m.cast<double>();  // the cast path folds its own terms
        sim::Data d(m), dc(cast);
        for (int trial = 0; trial < 5; ++trial) {
            Eigen::VectorXd q = m.q_reference;
            for (const sim::JointT<double>& j : m.joints)
                if (j.nq() == 1) q[j.q_index] = j.kind == sim::JointKind::Prismatic ? 0.05 * angle(rng) : angle(rng);
            d.q = dc.q = q;
            sim::update_positions(m, d);
            sim::update_positions(cast, dc);
            const std::vector<sim::Transform<double>> want = composed_poses(m, q);
            for (size_t b = 1; b < m.bodies.size(); ++b) {
                CHECK(pose_gap(d.x_world[b], want[b]) < 1e-12);
                CHECK(pose_gap(dc.x_world[b], want[b]) < 1e-12);
            }
        }
    }
    CHECK(folded > 20);
    CHECK(prismatic > 0);  // the slider terms are exercised too
}
}  // namespace MBX_UNITY_ID
