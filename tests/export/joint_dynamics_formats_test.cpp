// Joint dynamics (the description file's <joint>) in every export, each read
// back by its consumer: MuJoCo's compiled arrays for MJCF, urdfdom for URDF,
// the MSL 4.0 class index and the connect graph for Modelica. A damped
// pendulum in MuJoCo then decays and rings at the analytic rates.
#include <urdf_parser/urdf_parser.h>

#include <cmath>

#include "apps/stub_host/assemblies/builder.h"
#include "drives_support.h"
#include "joint_dynamics_support.h"
#include "export/mjcf/mjcf_export.h"
#include "modelica_support.h"
#include "mujoco_helpers.h"
#include "export/urdf/urdf_layout.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

constexpr double kPi = 3.14159265358979323846;
const std::string kRot = "Modelica.Mechanics.Rotational.";
const std::string kTrans = "Modelica.Mechanics.Translational.";

namespace build = mbx_stub::build;

const mbx_units kSI{1, 1, 1};

mbx_memory::Assembly carriage_pendulum() { return xtest::carriage_pendulum("lin", true); }
using xtest::joint_named;
using xtest::kBobInertia;
using xtest::kBobMass;
using xtest::kLength;
using xtest::resolve_joints;

const std::string kCarriageJoints =
    "<joint constraint=\"lin/slide\" damping=\"12\" coulomb=\"3.5\" stiffness=\"40\" rest=\"25\" armature=\"0.75\" "
    "lower=\"-150\" upper=\"200\" unit=\"mm\"/>\n"
    "<joint constraint=\"lin/pivot\" damping=\"0.02\" coulomb=\"0.05\" armature=\"0.003\" lower=\"-60\" upper=\"90\" "
    "unit=\"deg\"/>\n";

int mj_dof(const mjModel* model, const xtest::MuJoCoRun& run, int joint) {
    const int jid = mj_name2id(model, mjOBJ_JOINT, xtest::mjcf_joint_name(run.layout, joint).c_str());
    REQUIRE(jid >= 0);
    return jid;
}

}  // namespace

TEST_CASE("joint dynamics: MuJoCo compiles damping, frictionloss, armature, stiffness, springref and range") {
    auto t = xtest::translate(carriage_pendulum());
    const Mechanism& m = *t->mechanism;
    mbx_test::TempDir dir("joint_dynamics_mjcf");
    ExportSettings settings;
    settings.model_name = "carriage";
    settings.joint_dynamics = resolve_joints(m, kCarriageJoints);
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    const mjModel* model = run.model.get();

    const int slide = mj_dof(model, run, joint_named(m, "slide"));
    const int dof_s = model->jnt_dofadr[slide];
    CHECK(model->dof_damping[dof_s] == 12);
    CHECK(model->dof_frictionloss[dof_s] == 3.5);
    CHECK(model->dof_armature[dof_s] == 0.75);
    CHECK(model->jnt_stiffness[slide] == 40);
    CHECK(model->qpos_spring[model->jnt_qposadr[slide]] == mbx_test::relative(0.025, 1e-15));
    CHECK(model->jnt_limited[slide]);
    CHECK(model->jnt_range[2 * slide] == mbx_test::relative(-0.15, 1e-15));
    CHECK(model->jnt_range[2 * slide + 1] == mbx_test::relative(0.2, 1e-15));

    // The description's limits replace the CAD joint's +-2 rad.
    const int pivot = mj_dof(model, run, joint_named(m, "pivot"));
    const int dof_p = model->jnt_dofadr[pivot];
    CHECK(model->dof_damping[dof_p] == 0.02);
    CHECK(model->dof_frictionloss[dof_p] == 0.05);
    CHECK(model->dof_armature[dof_p] == 0.003);
    CHECK(model->jnt_stiffness[pivot] == 0);
    CHECK(model->jnt_limited[pivot]);
    CHECK(model->jnt_range[2 * pivot] == mbx_test::relative(-kPi / 3, 1e-15));
    CHECK(model->jnt_range[2 * pivot + 1] == mbx_test::relative(kPi / 2, 1e-15));

    // Without joint dynamics the same joints carry none of it, and the CAD limits.
    mbx_test::TempDir plain_dir("joint_dynamics_mjcf_plain");
    ExportSettings plain;
    plain.model_name = "carriage";
    xtest::MuJoCoRun bare = xtest::load_mjcf(*t, plain_dir, plain);
    const int bare_pivot = mj_dof(bare.model.get(), bare, joint_named(m, "pivot"));
    CHECK(bare.model->dof_damping[bare.model->jnt_dofadr[bare_pivot]] == 0);
    CHECK(bare.model->dof_frictionloss[bare.model->jnt_dofadr[bare_pivot]] == 0);
    CHECK(bare.model->jnt_range[2 * bare_pivot + 1] == 2);
}

TEST_CASE("joint dynamics: a drive's armature and back-EMF damping add to the joint's own in MJCF and URDF") {
    auto t = xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm.xml");
    const Mechanism& m = *t->mechanism;
    const std::vector<Drive> drives =
        xtest::resolve_drive_file(m, std::string(MBX_SAMPLES_DIR) + "/mechatronics/five_axis_arm_drives.xml");
    const std::vector<ResolvedJointDynamics> jd =
        resolve_joints(m, "<joint constraint=\"40:-:41\" damping=\"1.5\" coulomb=\"0.8\" armature=\"0.2\"/>\n");
    REQUIRE(jd.size() == 1);
    const Drive* waist = nullptr;
    for (const Drive& d : drives)
        if (d.joint == jd[0].joint) waist = &d;
    REQUIRE(waist);
    REQUIRE(waist->armature > 0);
    REQUIRE(waist->servo.emf_damping > 0);

    mbx_test::TempDir dir("joint_dynamics_driven");
    ExportSettings settings;
    settings.model_name = "arm";
    settings.drives = drives;
    settings.joint_dynamics = jd;
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    const int jid = mj_dof(run.model.get(), run, jd[0].joint);
    const int dof = run.model->jnt_dofadr[jid];
    CHECK(run.model->dof_armature[dof] == mbx_test::relative(waist->armature + 0.2, 1e-14));
    CHECK(run.model->dof_damping[dof] == mbx_test::relative(waist->servo.emf_damping + 1.5, 1e-14));
    CHECK(run.model->dof_frictionloss[dof] == 0.8);

    const OutputFiles files = xtest::export_to(*t, dir, MBX_EXPORT_URDF, settings);
    const OutputFile* urdf_out = xtest::find_file(files, "urdf/arm.urdf");
    REQUIRE(urdf_out);
    const urdf::ModelInterfaceSharedPtr urdf_model = urdf::parseURDF(urdf_out->contents);
    REQUIRE(urdf_model);
    ExportModel em = xtest::export_model(*t, settings);
    const urdf::JointConstSharedPtr joint = urdf_model->getJoint(plan_urdf(em).joint_name[size_t(jd[0].joint)]);
    REQUIRE(joint);
    REQUIRE(joint->dynamics);
    CHECK(joint->dynamics->damping == mbx_test::relative(waist->servo.emf_damping + 1.5, 1e-14));
    CHECK(joint->dynamics->friction == 0.8);
}

TEST_CASE("joint dynamics: urdfdom reads damping, friction and the description's limits, spring and armature are notes") {
    auto t = xtest::translate(carriage_pendulum());
    const Mechanism& m = *t->mechanism;
    mbx_test::TempDir dir("joint_dynamics_urdf");
    ExportSettings settings;
    settings.model_name = "carriage";
    settings.joint_dynamics = resolve_joints(m, kCarriageJoints);
    ExportModel em = xtest::export_model(*t, settings);
    const OutputFiles files = export_files(em, MBX_EXPORT_URDF);
    const OutputFile* f = xtest::find_file(files, "urdf/carriage.urdf");
    REQUIRE(f);
    const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(f->contents);
    REQUIRE(model);
    const UrdfLayout layout = plan_urdf(em);

    const urdf::JointConstSharedPtr slide = model->getJoint(layout.joint_name[size_t(joint_named(m, "slide"))]);
    REQUIRE(slide);
    CHECK(slide->type == urdf::Joint::PRISMATIC);
    REQUIRE(slide->dynamics);
    CHECK(slide->dynamics->damping == 12);
    CHECK(slide->dynamics->friction == 3.5);
    REQUIRE(slide->limits);
    CHECK(slide->limits->lower == mbx_test::relative(-0.15, 1e-15));
    CHECK(slide->limits->upper == mbx_test::relative(0.2, 1e-15));

    const urdf::JointConstSharedPtr pivot = model->getJoint(layout.joint_name[size_t(joint_named(m, "pivot"))]);
    REQUIRE(pivot);
    CHECK(pivot->type == urdf::Joint::REVOLUTE);
    REQUIRE(pivot->dynamics);
    CHECK(pivot->dynamics->damping == 0.02);
    CHECK(pivot->dynamics->friction == 0.05);
    REQUIRE(pivot->limits);
    CHECK(pivot->limits->lower == mbx_test::relative(-kPi / 3, 1e-15));
    CHECK(pivot->limits->upper == mbx_test::relative(kPi / 2, 1e-15));

    // A spring and armature URDF cannot hold: one note per joint that has them.
    int notes = 0;
    for (const Finding& n : em.notes()) {
        if (n.message.find("URDF has no joint spring or armature") == std::string::npos) continue;
        ++notes;
        if (n.message.find("'slide'") != std::string::npos) {
            CHECK(n.message.find("spring (stiffness 40, rest 0.025)") != std::string::npos);
            CHECK(n.message.find("armature 0.75") != std::string::npos);
        } else {
            CHECK(n.message.find("'pivot' is written without its armature 0.003") != std::string::npos);
        }
    }
    CHECK(notes == 2);

    // A continuous joint becomes a revolute when the description limits it.
    auto free_pivot = carriage_pendulum();
    for (mbx_memory::Constraint& c : free_pivot.constraints)
        for (auto& p : c.chain) p.has_limits = false;
    auto t2 = xtest::translate(std::move(free_pivot));
    ExportSettings s2;
    s2.model_name = "carriage";
    const urdf::ModelInterfaceSharedPtr bare = [&] {
        ExportModel plain = xtest::export_model(*t2, s2);
        return urdf::parseURDF(xtest::find_file(export_files(plain, MBX_EXPORT_URDF), "urdf/carriage.urdf")->contents);
    }();
    s2.joint_dynamics = resolve_joints(*t2->mechanism, "<joint constraint=\"lin/pivot\" lower=\"-1\" upper=\"1\"/>\n");
    ExportModel limited = xtest::export_model(*t2, s2);
    const urdf::ModelInterfaceSharedPtr with = urdf::parseURDF(
        xtest::find_file(export_files(limited, MBX_EXPORT_URDF), "urdf/carriage.urdf")->contents);
    REQUIRE(bare);
    REQUIRE(with);
    const std::string name = plan_urdf(limited).joint_name[size_t(joint_named(*t2->mechanism, "pivot"))];
    CHECK(bare->getJoint(name)->type == urdf::Joint::CONTINUOUS);
    CHECK(with->getJoint(name)->type == urdf::Joint::REVOLUTE);
    CHECK(with->getJoint(name)->limits->upper == 1);
}

TEST_CASE("joint dynamics: Modelica puts MSL spring-damper, friction and inertia on each joint's flanges") {
    auto t = xtest::translate(carriage_pendulum());
    const Mechanism& m = *t->mechanism;
    ExportSettings settings;
    settings.model_name = "carriage";
    settings.joint_dynamics = resolve_joints(m, kCarriageJoints);
    const mtest::Package p = mtest::export_package(*t, settings);
    const OutputFile* f = p.file("Mechatronic.mo");
    REQUIRE_MESSAGE(f, "no Mechatronic.mo");
    const msl::Model model = msl::parse_model(f->contents);
    for (const std::string& e : model.errors) FAIL_CHECK(e);
    msl::Index index = mtest::msl_index();
    index.add(p.name + ".Mechanics", msl::class_info(p.mechanics));
    for (const std::string& err : msl::check_model(index, model)) FAIL_CHECK(err);
    for (const std::string& err : msl::check_model(mtest::msl_index(), p.mechanics)) FAIL_CHECK(err);
    REQUIRE(p.file("package.order"));
    CHECK(p.file("package.order")->contents.find("Mechatronic\nUserModel\n") != std::string::npos);
    const OutputFile* user = p.file("UserModel.mo");
    REQUIRE(user);
    CHECK(user->contents.find("extends " + p.name + ".Mechatronic;") != std::string::npos);

    // Each component's class and parameters, and the flanges it joins.
    const auto connected = [&](const std::string& a, const std::string& b) {
        for (const auto& [x, y] : model.connects)
            if ((x == a && y == b) || (x == b && y == a)) return true;
        return false;
    };
    const auto value = [&](const msl::Component& c, const std::string& mod) {
        const std::string v = c.value(mod);
        REQUIRE_MESSAGE(!v.empty(), c.name << " has no " << mod);
        return msl::parse_number(v);
    };
    const msl::Component* sd = model.find("slide_spring_damper");
    REQUIRE(sd);
    CHECK(sd->class_name == kTrans + "Components.SpringDamper");
    CHECK(value(*sd, "c") == 40);
    CHECK(value(*sd, "d") == 12);
    CHECK(value(*sd, "s_rel0") == mbx_test::relative(0.025, 1e-15));
    CHECK(connected("slide_spring_damper.flange_a", "mechanics.support_slide"));
    CHECK(connected("slide_spring_damper.flange_b", "mechanics.axis_slide"));
    const msl::Component* sf = model.find("slide_friction");
    REQUIRE(sf);
    CHECK(sf->class_name == kTrans + "Components.SupportFriction");
    CHECK(sf->value("f_pos") == "[0, 3.5]");
    CHECK(connected("slide_friction.flange_a", "mechanics.axis_slide"));
    const msl::Component* sm = model.find("slide_armature");
    REQUIRE(sm);
    CHECK(sm->class_name == kTrans + "Components.Mass");
    CHECK(value(*sm, "m") == 0.75);
    CHECK(connected("slide_armature.flange_a", "mechanics.axis_slide"));

    const msl::Component* pd = model.find("pivot_damper");
    REQUIRE(pd);
    CHECK(pd->class_name == kRot + "Components.Damper");
    CHECK(value(*pd, "d") == 0.02);
    CHECK(connected("pivot_damper.flange_a", "mechanics.support_pivot"));
    CHECK(connected("pivot_damper.flange_b", "mechanics.axis_pivot"));
    const msl::Component* pf = model.find("pivot_friction");
    REQUIRE(pf);
    CHECK(pf->class_name == kRot + "Components.BearingFriction");
    CHECK(pf->value("tau_pos") == "[0, 0.05]");
    const msl::Component* pi = model.find("pivot_armature");
    REQUIRE(pi);
    CHECK(pi->class_name == kRot + "Components.Inertia");
    CHECK(value(*pi, "J") == 0.003);
    CHECK(connected("pivot_armature.flange_a", "mechanics.axis_pivot"));
    CHECK(model.find("pivot_spring") == nullptr);

    // Limits have no MSL counterpart: a note per joint.
    int limit_notes = 0;
    for (const Finding& n : p.notes)
        limit_notes += n.message.find("have no position limits: the limits") != std::string::npos;
    CHECK(limit_notes == 2);
}

TEST_CASE("joint dynamics: the damped pendulum in MuJoCo decays at b / (2 I) and rings at the damped frequency") {
    // I theta'' + b theta' + (m g l + k) theta = 0 at small angles, I the
    // pendulum's inertia about the pivot plus the armature.
    auto a = carriage_pendulum();
    auto t = xtest::translate(std::move(a));
    const Mechanism& m = *t->mechanism;
    const double b = 0.15, k = 3, armature = 0.02;
    mbx_test::TempDir dir("joint_dynamics_decay");
    ExportSettings settings;
    settings.model_name = "pendulum";
    // The swing (in the y-z plane) pushes the carriage only across its x
    // axis, so the pivot stays put.
    settings.joint_dynamics = resolve_joints(
        m, "<joint constraint=\"lin/pivot\" damping=\"" + std::to_string(b) + "\" stiffness=\"" + std::to_string(k) +
               "\" armature=\"" + std::to_string(armature) + "\"/>\n");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    mjModel* model = run.model.get();
    mjData* data = run.data.get();
    const int pivot = mj_dof(model, run, joint_named(m, "pivot"));
    const int slide = mj_dof(model, run, joint_named(m, "slide"));
    const int qp = model->jnt_qposadr[pivot];

    const double I = kBobInertia + kBobMass * kLength * kLength + armature;
    const double omega0_sq = (kBobMass * 9.81 * kLength + k) / I;
    const double rate = b / (2 * I);
    const double omega_d = std::sqrt(omega0_sq - rate * rate);

    data->qpos[qp] = 0.01;
    mj_forward(model, data);
    std::vector<std::pair<double, double>> peaks;  // (time, theta) at local maxima
    double prev2 = data->qpos[qp], prev1 = prev2, t_prev1 = 0;
    const double stop = 6.0;
    double slide_travel = 0;
    while (data->time < stop) {
        mj_step(model, data);
        const double q = data->qpos[qp];
        if (prev1 > prev2 && prev1 >= q && data->time > 1e-3) {
            // Parabola through the last three samples: the peak between samples.
            const double h = model->opt.timestep, c2 = (q - 2 * prev1 + prev2) / (2 * h * h), c1 = (q - prev2) / (2 * h);
            const double dt = -c1 / (2 * c2);
            peaks.push_back({t_prev1 + dt, prev1 + c1 * dt + c2 * dt * dt});
        }
        prev2 = prev1, prev1 = q, t_prev1 = data->time;
        slide_travel = std::max(slide_travel, std::fabs(data->qpos[model->jnt_qposadr[slide]]));
    }
    REQUIRE(peaks.size() >= 4);
    const auto& first = peaks.front();
    const auto& last = peaks.back();
    const double measured_rate = std::log(first.second / last.second) / (last.first - first.first);
    const double measured_period = (last.first - first.first) / double(peaks.size() - 1);
    MESSAGE("decay rate " << measured_rate << " 1/s (analytic " << rate << "), period " << measured_period << " s (analytic "
                          << 2 * kPi / omega_d << "), " << peaks.size() << " peaks, carriage travel " << slide_travel << " m");
    CHECK(slide_travel < 1e-6);
    // Small-angle theory at 0.01 rad is good to ~1e-5; the sampled peaks to better.
    CHECK(measured_rate == mbx_test::relative(rate, 1e-4));
    CHECK(measured_period == mbx_test::relative(2 * kPi / omega_d, 1e-4));
}
}  // namespace MBX_UNITY_ID
