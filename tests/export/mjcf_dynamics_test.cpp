// MJCF dynamics in MuJoCo 2.2 against analytic results: a compound
// pendulum's period, the energy of a free body and of a double pendulum,
// and loops that stay closed (every cut joint's two frames together) while
// the mechanisms move under gravity and a driving force.
#include <cmath>

#include "export/mjcf/mjcf_defaults.h"
#include "mujoco_assemblies.h"
#include "mujoco_helpers.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

constexpr double kPi = 3.14159265358979323846;

// World pose of rigid body r as MuJoCo has it (ground is fixed at its CAD pose).
Pose mujoco_pose(const xtest::MuJoCoRun& run, const Mechanism& m, int r) {
    if (r == 0) return m.bodies[0].pose;
    const int id = run.body_id(r);
    REQUIRE(id > 0);
    return run.pose(id);
}

// How far a cut joint is from closed: the distance between its frame on the
// parent side and on the child side (minus the sliding component for a
// prismatic joint), and the angle by which the child side left what the
// joint allows (axis for revolute, all rotation for prismatic and weld).
struct CutError {
    double distance = 0;
    double angle = 0;
};

CutError cut_error(const xtest::MuJoCoRun& run, ExportModel& em, int c) {
    const Mechanism& m = em.mechanism();
    const Joint& joint = m.joints[size_t(c)];
    const JointPlacement& p = em.placement(c);
    const Pose parent_side = mujoco_pose(run, m, joint.parent) * p.parent_to_joint;
    const Pose child_side = mujoco_pose(run, m, joint.child) * p.joint_to_child.inverse();
    const Vec3 axis = parent_side.rotation * p.axis;
    Vec3 gap = child_side.position - parent_side.position;
    CutError e;
    switch (joint.type) {
    case MBX_PRIMITIVE_PRISMATIC:
        gap -= axis * axis.dot(gap);
        e.angle = xtest::rotation_error(parent_side.rotation, child_side.rotation);
        break;
    case MBX_PRIMITIVE_REVOLUTE: {
        const Vec3 child_axis = child_side.rotation * p.axis;
        e.angle = std::atan2(axis.cross(child_axis).norm(), axis.dot(child_axis));
        break;
    }
    case MBX_PRIMITIVE_WELD: e.angle = xtest::rotation_error(parent_side.rotation, child_side.rotation); break;
    case MBX_PRIMITIVE_SPHERICAL: break;
    }
    e.distance = gap.norm();
    return e;
}

double total_energy(const mjData* d) { return d->energy[0] + d->energy[1]; }

}  // namespace

TEST_CASE("MJCF: a compound pendulum swings with period 2 pi sqrt(I_pivot / (m g d))") {
    const xtest::mjcf_assemblies::Pendulum pendulum;
    auto t = xtest::translate(pendulum.assembly());
    mbx_test::TempDir dir("mbx_mjcf_pendulum");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
    mjModel* model = run.model.get();
    mjData* data = run.data.get();
    REQUIRE(model->nq == 1);
    CHECK(model->opt.timestep == mjcf_defaults::timestep);
    CHECK(model->opt.integrator == mjINT_RK4);

    // The bob hangs at the assembly pose (qpos0 is the stable equilibrium).
    const double theta0 = 0.02;
    data->qpos[0] = theta0;
    const double g = mjcf_defaults::gravity;
    const double t0 = 2 * kPi * std::sqrt(pendulum.pivot_inertia() / (pendulum.mass * g * pendulum.arm()));
    // Finite amplitude lengthens the period by theta0^2/16 (+11 theta0^4/3072).
    const double expected = t0 * (1 + theta0 * theta0 / 16 + 11 * std::pow(theta0, 4) / 3072);

    // Upward zero crossings, linearly interpolated between steps: at a crossing
    // the angle's curvature is zero, so the interpolation error is O(h^3 w^3)
    // per crossing, far below the step h.
    std::vector<double> crossings;
    double previous = data->qpos[0];
    while (crossings.size() < 7 && data->time < 20 * t0) {
        mj_step(model, data);
        const double now = data->qpos[0];
        if (previous < 0 && now >= 0)
            crossings.push_back(data->time - model->opt.timestep * now / (now - previous));
        previous = now;
    }
    REQUIRE(crossings.size() == 7);
    const double measured = (crossings.back() - crossings.front()) / 6;
    // RK4's phase error per period is about (w h)^4 / 120 ~ 1e-12 here and the
    // series truncation of the amplitude correction is ~ theta0^6 ~ 1e-10:
    // 1e-6 relative leaves room only for a wrong inertia, arm or axis.
    CHECK(std::fabs(measured - expected) < 1e-6 * expected);
    CHECK(std::fabs(measured - t0) > 1e-5 * t0);  // the amplitude correction is resolved, so the test can fail
}

TEST_CASE("MJCF: a free body keeps its energy and starts with 1/2 w^T I w") {
    const xtest::mjcf_assemblies::Tumbler tumbler;
    auto t = xtest::translate(tumbler.assembly());
    mbx_test::TempDir dir("mbx_mjcf_tumbler");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
    mjModel* model = run.model.get();
    mjData* data = run.data.get();
    REQUIRE(model->nq == 7);  // one free joint
    REQUIRE(model->jnt_type[0] == mjJNT_FREE);
    model->opt.disableflags |= mjDSBL_GRAVITY;
    model->opt.enableflags |= mjENBL_ENERGY;

    // A free joint's qvel is the body origin's linear velocity (world) and the
    // angular velocity in the body frame. With the origin at rest, the kinetic
    // energy is 1/2 w^T I_o w, I_o the inertia about the body origin.
    const Vec3 w(0.7, -2.0, 1.3);
    for (int k = 0; k < 3; ++k) data->qvel[3 + k] = w[k];
    const Vec3 c = tumbler.com_body;
    const Mat3 i_origin =
        tumbler.inertia_body + tumbler.mass * (c.squaredNorm() * Mat3::Identity() - c * c.transpose());
    const double by_hand = 0.5 * w.dot(i_origin * w);
    mj_forward(model, data);
    // MuJoCo rebuilds the tensor from its own eigen-decomposition of
    // fullinertia, good to ~1e-11 relative.
    CHECK(std::fabs(data->energy[1] - by_hand) < 1e-9 * by_hand);
    CHECK(data->energy[0] == 0);

    // Torque-free tumbling for 5 s. MuJoCo's RK4 moves a free joint's
    // orientation by a quaternion update per stage; the energy drift it leaves
    // is second order in the step (measured 3.4e-8 at 1 ms, 8.5e-9 at 0.5 ms,
    // 2.1e-9 at 0.25 ms), hence 5e-8 at the exported 0.5 ms.
    const double e0 = total_energy(data);
    double worst = 0;
    while (data->time < 5) {
        mj_step(model, data);
        worst = std::max(worst, std::fabs(total_energy(data) - e0));
    }
    CHECK(worst < 5e-8 * e0);
    CHECK(xtest::warning_count(data) == 0);
}

TEST_CASE("MJCF: a double pendulum under gravity conserves its energy") {
    auto t = xtest::translate(xtest::mjcf_assemblies::double_pendulum());
    mbx_test::TempDir dir("mbx_mjcf_double");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
    mjModel* model = run.model.get();
    mjData* data = run.data.get();
    REQUIRE(model->nq == 2);
    model->opt.enableflags |= mjENBL_ENERGY;
    data->qpos[0] = 0.8;
    data->qpos[1] = -0.5;
    mj_forward(model, data);
    const double e0 = total_energy(data);
    double min_pe = data->energy[0], max_pe = data->energy[0], worst = 0;
    while (data->time < 5) {
        mj_step(model, data);
        mj_energyPos(model, data);
        mj_energyVel(model, data);
        worst = std::max(worst, std::fabs(total_energy(data) - e0));
        min_pe = std::min(min_pe, data->energy[0]);
        max_pe = std::max(max_pe, data->energy[0]);
    }
    const double swing = max_pe - min_pe;  // energy traded between potential and kinetic
    INFO("double pendulum: drift " << worst << " J, exchanged " << swing << " J");
    CHECK(swing > 0.3);  // it really moved (J)
    // Measured drift 7e-8 of the exchanged energy over 5 s at the exported
    // 0.5 ms step (second order in the step, as for the free body); 1e-6
    // still catches any dissipation or a wrong inertial.
    CHECK(worst < 1e-6 * swing);
}

TEST_CASE("MJCF: loops stay closed while the mechanisms move") {
    struct LoopCase {
        std::string label;
        std::function<std::unique_ptr<xtest::Translated>()> open;
        size_t cuts;
        double drive = 0;  // N*m on the first tree hinge
        // Gravity direction: tilted so that the builtins, whose planar loops
        // lie in horizontal or tilted planes, swing; the exported -z for the
        // sample, whose unlimited vertical slider otherwise free-falls sideways
        // through its loop.
        Vec3 down = Vec3(0.3, -0.5, -0.8).normalized();
    };
    std::vector<LoopCase> cases = {
        {"fourbar", [] { return xtest::translate_builtin("fourbar"); }, 1},
        {"planar_sixbar", [] { return xtest::translate_builtin("planar_sixbar"); }, 2},
        {"double_cardan", [] { return xtest::translate_builtin("double_cardan"); }, 2, 0.002},
        {"spatial (spherical cut)", [] { return xtest::translate(xtest::mjcf_assemblies::spatial()); }, 1},
        {"slider_crank (prismatic cut)", [] { return xtest::translate(xtest::mjcf_assemblies::slider_crank()); }, 1},
        {"sample joints_showcase",
         [] {
             const std::string path = std::string(MBX_SAMPLES_DIR) + "/joints_showcase/joints_showcase";
             mbx_files::FileAdapterOptions o;
             o.shapes_path = path + "_a.wrl";
             return xtest::translate_file(path + ".xml", o);
         },
         1, 0, -Vec3::UnitZ()},
        {"legs_mechanism_2015",
         [] { return xtest::translate_file(mbx_test::shared_data("pmxml/legs_mechanism_2015/LEGS_MECHANISM.xml")); },
         1},
    };
    for (const LoopCase& lc : cases) {
        CAPTURE(lc.label);
        auto t = lc.open();
        const Mechanism& m = *t->mechanism;
        mbx_test::TempDir dir("mbx_mjcf_loops");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        CHECK(run.load_message.empty());
        mjModel* model = run.model.get();
        mjData* data = run.data.get();
        ExportModel em = xtest::export_model(*t);

        std::vector<int> cuts;
        for (size_t j = 0; j < m.joints.size(); ++j)
            if (m.joints[j].cut) cuts.push_back(int(j));
        REQUIRE(cuts.size() == lc.cuts);

        // The double cardan, balanced under gravity, is turned by a small
        // torque on its first hinge.
        const Vec3 g = mjcf_defaults::gravity * lc.down;
        for (int k = 0; k < 3; ++k) model->opt.gravity[k] = g[k];
        int driven = -1;
        for (int j = 0; j < model->njnt && driven < 0; ++j)
            if (model->jnt_type[j] == mjJNT_HINGE) driven = j;
        REQUIRE(driven >= 0);

        // Tolerance per cut: 1e-4 m per 0.1 m of its loop, the loop's size
        // being the largest distance between two of its joints.
        std::vector<double> tolerance;
        for (int c : cuts) {
            double size = 0;
            for (int a : m.loops[size_t(m.joints[size_t(c)].loop)].joints)
                for (int b : m.loops[size_t(m.joints[size_t(c)].loop)].joints)
                    size = std::max(size, (m.joints[size_t(a)].frame.position - m.joints[size_t(b)].frame.position).norm());
            tolerance.push_back(1e-3 * size);
        }

        mj_forward(model, data);
        for (int c : cuts) {
            const CutError e = cut_error(run, em, c);
            CHECK(e.distance < 1e-12);  // closed at qpos0
            CHECK(e.angle < 1e-12);
        }
        double worst_ratio = 0, worst_angle = 0;
        const int driven_dof = model->jnt_dofadr[driven];
        const double start = data->qpos[model->jnt_qposadr[driven]];
        double travel = 0;
        while (data->time < 2) {
            data->qfrc_applied[driven_dof] = lc.drive;
            mj_step(model, data);
            for (size_t k = 0; k < cuts.size(); ++k) {
                const CutError e = cut_error(run, em, cuts[k]);
                worst_ratio = std::max(worst_ratio, e.distance / tolerance[k]);
                worst_angle = std::max(worst_angle, e.angle);
            }
            travel = std::max(travel, std::fabs(data->qpos[model->jnt_qposadr[driven]] - start));
        }
        INFO(lc.label << ": max gap / tolerance " << worst_ratio << ", angle " << worst_angle
                         << " rad, driven joint travel " << travel << " rad");
        CHECK(travel > 0.1);  // the mechanism really moved
        CHECK(worst_ratio < 1);
        CHECK(worst_angle < 1e-3);
        CHECK(xtest::warning_count(data) == 0);
        bool finite = true;
        for (int i = 0; i < model->nq; ++i) finite = finite && std::isfinite(data->qpos[i]);
        CHECK(finite);
    }
}

TEST_CASE("MJCF: cut joints become connects, welds or a helper slider, each noted where approximate") {
    {
        auto t = xtest::translate_builtin("fourbar");
        mbx_test::TempDir dir("mbx_mjcf_eq");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        // Revolute cut: two connects a fixed spacing apart on the axis.
        REQUIRE(run.model->neq == 2);
        CHECK(run.model->eq_type[0] == mjEQ_CONNECT);
        CHECK(run.model->eq_type[1] == mjEQ_CONNECT);
        CHECK(run.model->eq_solref[0] == 0.001);
        CHECK(run.model->eq_solimp[0] == 0.99);
        const Vec3 a1(run.model->eq_data[0], run.model->eq_data[1], run.model->eq_data[2]);
        const Vec3 a2(run.model->eq_data[mjNEQDATA], run.model->eq_data[mjNEQDATA + 1],
                      run.model->eq_data[mjNEQDATA + 2]);
        CHECK(std::fabs((a1 - a2).norm() - run.layout.axis_spacing) < 1e-12);
    }
    {
        auto t = xtest::translate(xtest::mjcf_assemblies::slider_crank());
        ExportModel em = xtest::export_model(*t);
        OutputFiles files = export_files(em, MBX_EXPORT_MJCF);
        bool noted = false;
        for (const Finding& f : em.notes())
            noted = noted || (f.code == MBX_FINDING_EXPORT_APPROXIMATION &&
                              f.message.find("'slide'") != std::string::npos);
        CHECK(noted);
        mbx_test::TempDir dir("mbx_mjcf_slider");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        REQUIRE(run.model->neq == 1);
        CHECK(run.model->eq_type[0] == mjEQ_WELD);
        // The helper slider carries the cut's limits.
        const int slide = mj_name2id(run.model.get(), mjOBJ_JOINT, "slide");
        REQUIRE(slide >= 0);
        CHECK(run.model->jnt_type[slide] == mjJNT_SLIDE);
        CHECK(run.model->jnt_limited[slide]);
        CHECK(run.model->jnt_range[2 * slide] == -0.1);
        CHECK(run.model->jnt_range[2 * slide + 1] == 0.05);
    }
    {
        // double_cardan's second cardan ends in a cut: its cross is a leaf node
        // with a light stand-in mass, 1e-3 of the lightest body.
        auto t = xtest::translate_builtin("double_cardan");
        const Mechanism& m = *t->mechanism;
        mbx_test::TempDir dir("mbx_mjcf_leaf");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        int leaf = -1;
        double lightest = INFINITY;
        for (size_t b = 0; b < m.bodies.size(); ++b) {
            if (m.bodies[b].kind == MBX_RIGID_BODY_JOINT_NODE) leaf = int(b);
            if (m.bodies[b].kind == MBX_RIGID_BODY_DYNAMIC) lightest = std::min(lightest, m.bodies[b].mass);
        }
        REQUIRE(leaf > 0);
        const int id = run.body_id(leaf);
        REQUIRE(id > 0);
        CHECK(run.model->body_mass[id] == mbx_test::relative(1e-3 * lightest, 1e-12));
        CHECK(run.model->body_jntnum[id] == 1);
        ExportModel em = xtest::export_model(*t);
        export_files(em, MBX_EXPORT_MJCF);
        bool noted = false;
        for (const Finding& f : em.notes())
            noted = noted || (f.code == MBX_FINDING_EXPORT_APPROXIMATION && f.subject.id == m.bodies[size_t(leaf)].id);
        CHECK(noted);
    }
}
}  // namespace MBX_UNITY_ID
