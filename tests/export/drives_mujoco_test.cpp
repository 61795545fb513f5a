// The five-axis arm sample driven by library motors (samples/mechatronics):
// MuJoCo simulates the exported MJCF following the motion program, and its
// tracking error is checked against what the controller's design predicts,
// joint by joint: the linear error dynamics
//   J e'' + D e' + K e = J r'' + D r' - tau_g(r)
// with K, D from the drive (servo equivalent plus back-EMF), J the drive's
// armature plus the composite inertia of the joint's subtree about its axis
// and tau_g the gravity torque, both from mbx's forward kinematics at the
// reference. The program moves one joint at a time, base to tip and back tip
// to base, so each moving joint's subtree is at its assembly pose and the
// cross-coupling the design leaves out stays small.
#include <cmath>

#include "drives_support.h"
#include "core/kinematics/forward_kinematics.h"
#include "export/mjcf/mjcf_export.h"
#include "mujoco_helpers.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

const Vec3 kGravity(0, 0, -9.81);

// Composite inertia about joint j's axis and gravity torque about it, for
// the tree at body poses `poses` (forward kinematics at the coordinates).
struct AxisLoad {
    double inertia = 0;
    double gravity_torque = 0;
};

AxisLoad axis_load(const Mechanism& m, ExportModel& em, int j, const std::vector<Pose>& poses) {
    const Joint& joint = m.joints[size_t(j)];
    const JointPlacement& p = em.placement(j);
    const Pose frame = poses[size_t(joint.parent)] * p.parent_to_joint;
    const Vec3 axis = frame.rotation * p.axis;
    const Vec3 at = frame.position;
    // Bodies below the joint: walk the tree from its child.
    std::vector<int> stack{joint.child};
    AxisLoad load;
    while (!stack.empty()) {
        const int b = stack.back();
        stack.pop_back();
        const RigidBody& body = m.bodies[size_t(b)];
        const Pose& pose = poses[size_t(b)];
        const Vec3 com = pose.apply(body.com);
        const Mat3 inertia = pose.rotation * body.inertia * pose.rotation.transpose();
        load.inertia += axis.dot(inertia * axis) + body.mass * axis.cross(com - at).squaredNorm();
        load.gravity_torque += (com - at).cross(body.mass * kGravity).dot(axis);
        for (int c : em.tree().child_joints[size_t(b)]) stack.push_back(m.joints[size_t(c)].child);
    }
    return load;
}

}  // namespace

TEST_CASE("drives: MuJoCo follows the arm's motion program as the controllers' design predicts") {
    auto t = xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm.xml");
    const Mechanism& m = *t->mechanism;
    const std::vector<Drive> drives =
        xtest::resolve_drive_file(m, std::string(MBX_SAMPLES_DIR) + "/mechatronics/five_axis_arm_drives.xml");
    REQUIRE(drives.size() == 5);

    mbx_test::TempDir dir("drives_mujoco");
    ExportSettings settings;
    settings.model_name = "arm";
    settings.drives = drives;
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    mjModel* model = run.model.get();
    mjData* data = run.data.get();
    ExportModel em = xtest::export_model(*t, settings);

    // MuJoCo's ids for each drive's joint and actuator.
    struct Axis {
        const Drive* drive;
        int qpos = -1, dof = -1, actuator = -1;
        double stiffness = 0, damping = 0;
        double e = 0, de = 0;  // design model state
        double worst_gap = 0, worst_design = 0, worst_gravity = 0, peak_force = 0;
    };
    std::vector<Axis> axes;
    for (const Drive& d : drives) {
        Axis a{&d};
        for (const MjcfBody& b : run.layout.bodies)
            for (const MjcfJoint& j : b.joints)
                if (j.joint == d.joint) {
                    const int id = mj_name2id(model, mjOBJ_JOINT, j.name.c_str());
                    REQUIRE(id >= 0);
                    a.qpos = model->jnt_qposadr[id];
                    a.dof = model->jnt_dofadr[id];
                    a.actuator = mj_name2id(model, mjOBJ_ACTUATOR, mjcf_actuator_name(j.name).c_str());
                }
        REQUIRE(a.actuator >= 0);
        a.stiffness = d.servo.stiffness;
        a.damping = d.servo.damping + d.servo.emf_damping;
        axes.push_back(a);
    }

    const double dt = model->opt.timestep;
    const double stop = 14.0;
    std::vector<JointPosition> q_ref(m.joints.size());
    for (double time = 0; time < stop - 0.5 * dt; time += dt) {
        // The reference at this step, for MuJoCo (motor-angle targets) and the design.
        for (Axis& a : axes) {
            q_ref[size_t(a.drive->joint)].value = a.drive->spec.motion.at(time).position;
            data->ctrl[a.actuator] = a.drive->ratio * q_ref[size_t(a.drive->joint)].value;
        }
        const std::vector<Pose> poses = forward_kinematics(m, q_ref);
        for (Axis& a : axes) {
            const MotionSample r = a.drive->spec.motion.at(time);
            const AxisLoad load = axis_load(m, em, a.drive->joint, poses);
            const double J = a.drive->armature + load.inertia;
            // Semi-implicit Euler on the design's error dynamics, at MuJoCo's step.
            const double dde = (J * r.acceleration + a.damping * r.velocity - load.gravity_torque -
                                a.damping * a.de - a.stiffness * a.e) / J;
            a.de += dt * dde;
            a.e += dt * a.de;
            a.worst_gravity = std::max(a.worst_gravity, std::fabs(load.gravity_torque));
        }
        mj_step(model, data);
        for (Axis& a : axes) {
            const double r = a.drive->spec.motion.at(data->time).position;
            const double e_mujoco = r - data->qpos[a.qpos];
            a.worst_gap = std::max(a.worst_gap, std::fabs(e_mujoco - a.e));
            a.worst_design = std::max(a.worst_design, std::fabs(a.e));
            a.peak_force = std::max(a.peak_force, std::fabs(data->actuator_force[a.actuator]));
        }
    }
    REQUIRE(xtest::warning_count(data) == 0);

    for (const Axis& a : axes) {
        const Drive& d = *a.drive;
        INFO("drive " << d.name << ": design error up to " << a.worst_design << " rad, MuJoCo differs by up to "
                      << a.worst_gap << " rad; peak motor torque " << a.peak_force << " N m of "
                      << d.effort_limit / d.ratio);
        // The design is linear: the motion program must keep the motor off its limit.
        CHECK(a.peak_force < 0.9 * d.effort_limit / d.ratio);
        // The design's tracking error is real (so the comparison means
        // something) and MuJoCo's follows it within 5 % of its size (measured: 0.4-2.5 %).
        CHECK(a.worst_design > 1e-3);
        CHECK(a.worst_gap < 0.05 * a.worst_design);
        CHECK(d.spec.motion.at(stop).position == 0.0);
    }
    // At the end every target is back at zero and the arm is at rest, sagged
    // under gravity: the static equilibrium K q = tau_g(q) of the design,
    // solved by fixed-point iteration (tau_g changes little as the arm sags).
    std::vector<JointPosition> sagged(m.joints.size());
    for (int iteration = 0; iteration < 50; ++iteration)
        for (const Axis& a : axes)
            sagged[size_t(a.drive->joint)].value =
                axis_load(m, em, a.drive->joint, forward_kinematics(m, sagged)).gravity_torque / a.stiffness;
    for (const Axis& a : axes) {
        const double expected = sagged[size_t(a.drive->joint)].value;
        INFO("drive " << a.drive->name << ": static sag " << expected << " rad, MuJoCo " << data->qpos[a.qpos]);
        CHECK(std::fabs(data->qpos[a.qpos] - expected) < 1e-3 * std::fabs(expected) + 1e-7);
    }
}

TEST_CASE("drives: MJCF joints carry the drive's armature and back-EMF damping, actuators its gear and limit") {
    auto t = xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm.xml");
    const std::vector<Drive> drives = xtest::resolve_drive_file(
        *t->mechanism, std::string(MBX_SAMPLES_DIR) + "/mechatronics/five_axis_arm_drives.xml");
    mbx_test::TempDir dir("drives_mjcf");
    ExportSettings settings;
    settings.drives = drives;
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    const mjModel* model = run.model.get();
    REQUIRE(model->nu == int(drives.size()));
    for (const Drive& d : drives) {
        const std::string joint = xtest::mjcf_joint_name(run.layout, d.joint);
        const int jid = mj_name2id(model, mjOBJ_JOINT, joint.c_str());
        const int aid = mj_name2id(model, mjOBJ_ACTUATOR, mjcf_actuator_name(joint).c_str());
        REQUIRE(jid >= 0);
        REQUIRE(aid >= 0);
        const int dof = model->jnt_dofadr[jid];
        // Rotor J N^2 plus the transmission's own J N_t^2, from the library's raw values.
        const double expected = d.motor.rotor_inertia * d.ratio * d.ratio +
                                d.transmission_inertia * d.transmission_ratio * d.transmission_ratio;
        CHECK(model->dof_armature[dof] == mbx_test::relative(expected, 1e-12));
        CHECK(model->dof_damping[dof] == mbx_test::relative(d.servo.emf_damping, 1e-12));
        CHECK(model->actuator_gear[6 * aid] == mbx_test::relative(d.ratio, 1e-12));
        CHECK(model->actuator_forcerange[2 * aid + 1] * model->actuator_gear[6 * aid] ==
              mbx_test::relative(d.effort_limit, 1e-12));
        CHECK(model->actuator_trnid[2 * aid] == jid);
    }
}
}  // namespace MBX_UNITY_ID
