// mbx's simulated trajectories against MuJoCo's on mbx's own MJCF export:
// both engines integrate the same bodies (make_pair) with RK4 at 0.1 ms from
// the same consistent state, under gravity tilted so that planar loops lying
// in horizontal planes move too, and every joint's coordinate is compared
// along the way. Trees should agree to round-off growth; for loops MuJoCo
// closes them with soft equality constraints, whose drift is the error floor.
#include <cmath>

#include "sim/simulation.h"
#include "tests/export/test_inputs.h"
#include "sim_mujoco_support.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

struct TrajectoryCase {
    simtest::Input input;
    double tolerance;  // largest coordinate difference allowed (rad, m)
    Eigen::Vector3d down = Eigen::Vector3d(0.3, -0.5, -0.8).normalized();
    double rate = 1.5;  // initial rate of the first revolute (rad/s)
};

// Largest difference between two MuJoCo positions over the joints mbx has:
// angles and slides directly, balls and free joints by their rotation angle
// and position.
double qpos_difference(const simtest::Pair& p, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    const mjModel* mm = p.run.model.get();
    double worst = 0;
    for (size_t k = 0; k < p.model.joints.size(); ++k) {
        const int id = p.mj_joint[k];
        if (id < 0) continue;
        const int adr = mm->jnt_qposadr[id];
        switch (mm->jnt_type[id]) {
        case mjJNT_HINGE:
        case mjJNT_SLIDE: worst = std::max(worst, std::fabs(a[adr] - b[adr])); break;
        case mjJNT_BALL:
        case mjJNT_FREE: {
            const int o = mm->jnt_type[id] == mjJNT_FREE ? 3 : 0;
            for (int i = 0; i < o; ++i) worst = std::max(worst, std::fabs(a[adr + i] - b[adr + i]));
            const Eigen::Quaterniond qa(a[adr + o], a[adr + o + 1], a[adr + o + 2], a[adr + o + 3]);
            const Eigen::Quaterniond qb(b[adr + o], b[adr + o + 1], b[adr + o + 2], b[adr + o + 3]);
            worst = std::max(worst, qa.normalized().angularDistance(qb.normalized()));
            break;
        }
        }
    }
    return worst;
}

struct Outcome {
    double worst = 0;   // largest coordinate difference
    double travel = 0;  // largest excursion of any coordinate from its start (so the comparison means something)
};

Outcome compare(const TrajectoryCase& c, double duration, double time_constant_steps = 2) {
    const simtest::Input& input = c.input;
    CAPTURE(input.label);
    auto t = input.open();
    mbx_test::TempDir dir("mbx_sim_traj");
    simtest::Pair p = simtest::make_pair(*t, dir);
    mjModel* mm = p.run.model.get();
    mjData* md = p.run.data.get();
    // A zero `down` means along the first joint's axis: for a planar loop, gravity that does no work.
    Eigen::Vector3d down = c.down;
    if (down.isZero()) {
        const auto& j0 = p.model.joints[0];
        sim::Data d0(p.model);
        sim::update_positions(p.model, d0);
        down = (d0.x_world[size_t(j0.body)].R * j0.subspace.col(0).head<3>()).normalized();
    }
    const Eigen::Vector3d g = 9.81 * down;
    p.model.gravity = g;
    for (int k = 0; k < 3; ++k) mm->opt.gravity[k] = g[k];
    // Limits are left out on both sides (a state never reaches CAD limits
    // from rest in these runs, and MuJoCo's soft limits would differ).
    for (auto& j : p.model.joints) j.dynamics.limited = false;
    mm->opt.disableflags |= mjDSBL_LIMIT | mjDSBL_CONTACT;
    const double h = 1e-4;
    mm->opt.timestep = h;
    mm->opt.integrator = mjINT_RK4;
    // The stiffest equality MuJoCo's safety clamp allows at this step
    // (time constant 2 h, critical damping) and impedance near 1.
    for (int e = 0; e < mm->neq; ++e) {
        mm->eq_solref[mjNREF * e] = time_constant_steps * h;
        mm->eq_solref[mjNREF * e + 1] = 1;
        mm->eq_solimp[mjNIMP * e] = 0.9999;
        mm->eq_solimp[mjNIMP * e + 1] = 0.9999;
    }

    // Start: trees tilted away from the assembly pose, loops at it; the first
    // velocity coordinate moving, the others following the loops.
    sim::Data d(p.model);
    std::vector<sim::FixedValue> fixed;
    for (size_t k = 0; k < p.model.joints.size(); ++k) {
        const auto& j = p.model.joints[k];
        if (j.kind != sim::JointKind::Revolute) continue;
        if (fixed.empty()) fixed.push_back({int(k), 0, true, c.rate});
        if (p.model.closures.empty()) fixed.push_back({int(k), 0, false, 0.4});
    }
    if (fixed.empty()) fixed.push_back({0, 0, true, c.rate});  // a free body: its first rate
    sim::initial_state(p.model, d, fixed);
    p.to_mujoco(d.q, d.v);
    mj_forward(mm, md);

    sim::IntegratorSettings is;
    is.kind = sim::IntegratorKind::RK4;
    is.step = h;
    Outcome out;
    const Eigen::VectorXd start = p.mujoco_qpos(d.q);
    const int steps = int(std::lround(duration / h));
    for (int s = 1; s <= steps; ++s) {
        sim::fixed_step(p.model, d, is);
        mj_step(mm, md);
        if (s % 50) continue;
        const Eigen::VectorXd mine = p.mujoco_qpos(d.q);
        const Eigen::VectorXd theirs = Eigen::Map<const Eigen::VectorXd>(md->qpos, mm->nq);
        out.worst = std::max(out.worst, qpos_difference(p, mine, theirs));
        out.travel = std::max(out.travel, qpos_difference(p, mine, start));
    }
    CHECK(xtest::warning_count(md) == 0);
    return out;
}

}  // namespace

// Measured largest differences over 1.5 s (rad; m for the floating body's
// position): pendulum 1.3e-15, double pendulum 3.8e-15, six_axis_arm 4.6e-12
// (trees: both engines run the same RK4 on the same equations); loops:
// double_cardan 3.0e-8 and planar_sixbar 7.2e-8 with gravity along their
// hinge axes, fourbar 5.9e-8 likewise, fourbar swinging under tilted gravity
// 6.2e-4 and the spatial mechanism (spherical cut) 1.6e-4. The loop figures
// are MuJoCo's: its equalities are soft (time constant 2 steps, the stiffest
// its safety clamp allows), and a 4-step time constant makes them several
// times worse, which the test checks. Before build_model capped the closure
// rank, the double cardan drifted 0.047 rad from MuJoCo and lost 7 % of its
// energy: redundant closure rows counted as independent at RK4 stages.
// With gravity in its plane the six-bar reaches a near-toggle pose at 0.73 s
// (lever at 70 rad/s, smallest nonzero singular value of the closure
// Jacobian 0.026): MuJoCo's soft loops lose 5e-3 J there and the runs part,
// so the six-bar is compared with gravity along its axes.
TEST_CASE("sim: trajectories equal MuJoCo's over 1.5 s, trees and loops") {
    namespace a = xtest::mjcf_assemblies;
    const Eigen::Vector3d tilted = Eigen::Vector3d(0.3, -0.5, -0.8).normalized(), along_axes = Eigen::Vector3d::Zero();
    const std::vector<TrajectoryCase> cases = {
        {{"pendulum", [] { return xtest::translate(a::Pendulum().assembly()); }}, 1e-12, tilted, 1.5},
        {{"double pendulum", [] { return xtest::translate(a::double_pendulum()); }}, 1e-12, tilted, 1.5},
        {{"six_axis_arm", [] { return xtest::translate_builtin("six_axis_arm"); }}, 1e-9, tilted, 1.5},
        {{"double_cardan", [] { return xtest::translate_builtin("double_cardan"); }}, 1e-6, along_axes, 1.5},
        {{"planar_sixbar", [] { return xtest::translate_builtin("planar_sixbar"); }}, 1e-6, along_axes, 1.5},
        {{"fourbar", [] { return xtest::translate_builtin("fourbar"); }}, 1e-6, along_axes, 1.5},
        {{"fourbar under tilted gravity", [] { return xtest::translate_builtin("fourbar"); }}, 2e-3, tilted, 0},
        {{"spatial (spherical cut, floating body)", [] { return xtest::translate(a::spatial()); }}, 1e-3, tilted, 1.5},
    };
    for (const TrajectoryCase& c : cases) {
        CAPTURE(c.input.label);
        const Outcome o = compare(c, 1.5);
        MESSAGE(c.input.label << ": largest difference " << o.worst << ", largest travel " << o.travel);
        CHECK(o.travel > 0.3);  // it moved
        CHECK(o.worst < c.tolerance);
        if (c.tolerance > 1e-6) {
            const Outcome softer = compare(c, 1.5, 4);
            MESSAGE(c.input.label << " with MuJoCo's equalities twice as soft: " << softer.worst);
            CHECK(softer.worst > 2 * o.worst);
        }
    }
}
}  // namespace MBX_UNITY_ID
