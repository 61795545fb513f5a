// The joint-dynamics terms calibration identifies (effort offset,
// direction-dependent friction and damping, Stribeck peak) in every export.
// MJCF and URDF hold one symmetric friction level and damping per joint: they
// get the mean of the two directions (read back by MuJoCo and urdfdom) and a
// note naming what is lost. Modelica holds the offset and the asymmetric
// Coulomb law exactly -- c+ for qd > 0 and c- for qd < 0 is the mean level
// plus the constant effort -(c+ - c-)/2 -- as a constant torque (force)
// source between the joint's support and axis, and the Stribeck peak as the
// friction table's value at rest; checked against the MSL 4.0 class index.
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

const std::string kRot = "Modelica.Mechanics.Rotational.";
const std::string kTrans = "Modelica.Mechanics.Translational.";
namespace build = mbx_stub::build;
const mbx_units kSI{1, 1, 1};

using xtest::joint_named;
using xtest::resolve_joints;
mbx_memory::Assembly carriage_pendulum() { return xtest::carriage_pendulum("ex", false); }

// Slide: the EMPS rig's offset with asymmetric Coulomb friction and damping.
// Pivot: a Stribeck peak over a symmetric Coulomb level, and an offset.
const std::string kJoints =
    "<joint constraint=\"ex/slide\" offset=\"-3.16\" coulomb=\"2\" coulomb_negative=\"0.5\" damping=\"30\" "
    "damping_negative=\"10\"/>\n"
    "<joint constraint=\"ex/pivot\" coulomb=\"0.1\" stribeck=\"0.4\" stribeck_velocity=\"0.05\" offset=\"0.2\"/>\n";

// The notes of `em` holding `words`.
int notes_with(const ExportModel& em, const std::string& words) {
    int n = 0;
    for (const Finding& f : em.notes())
        if (f.message.find(words) != std::string::npos) {
            CHECK(f.code == MBX_FINDING_EXPORT_APPROXIMATION);
            ++n;
        }
    return n;
}

}  // namespace

TEST_CASE("joint dynamics extra: MJCF writes the symmetric means MuJoCo compiles and notes offset, asymmetry and Stribeck") {
    auto t = xtest::translate(carriage_pendulum());
    const Mechanism& m = *t->mechanism;
    ExportSettings settings;
    settings.model_name = "carriage";
    settings.joint_dynamics = resolve_joints(m, kJoints);

    mbx_test::TempDir dir("joint_dynamics_extra_mjcf");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    const mjModel* model = run.model.get();
    const int slide = mj_name2id(model, mjOBJ_JOINT, xtest::mjcf_joint_name(run.layout, joint_named(m, "slide")).c_str());
    const int pivot = mj_name2id(model, mjOBJ_JOINT, xtest::mjcf_joint_name(run.layout, joint_named(m, "pivot")).c_str());
    REQUIRE(slide >= 0);
    REQUIRE(pivot >= 0);
    CHECK(model->dof_frictionloss[model->jnt_dofadr[slide]] == 1.25);  // (2 + 0.5) / 2
    CHECK(model->dof_damping[model->jnt_dofadr[slide]] == 20);         // (30 + 10) / 2
    CHECK(model->dof_frictionloss[model->jnt_dofadr[pivot]] == mbx_test::relative(0.1, 1e-15));

    ExportModel em = xtest::export_model(*t, settings);
    export_files(em, MBX_EXPORT_MJCF);
    const std::string lead = "MJCF joint friction and damping are symmetric and MuJoCo has no constant joint effort";
    CHECK(notes_with(em, lead) == 2);
    CHECK(notes_with(em, lead + ": joint 'slide' is written without the effort offset -3.16 N, the direction-dependent "
                             "Coulomb friction 2 (q' > 0) / 0.5 (q' < 0) N, written as their mean 1.25 and the "
                             "direction-dependent damping 30 (q' > 0) / 10 (q' < 0) N s/m, written as their mean 20") == 1);
    CHECK(notes_with(em, "joint 'pivot' is written without the effort offset 0.2 N m and the Stribeck peak 0.4 N m over "
                         "0.05 rad/s") == 1);
}

TEST_CASE("joint dynamics extra: URDF writes the symmetric means urdfdom reads and notes what it cannot hold") {
    auto t = xtest::translate(carriage_pendulum());
    const Mechanism& m = *t->mechanism;
    ExportSettings settings;
    settings.model_name = "carriage";
    settings.joint_dynamics = resolve_joints(m, kJoints);
    ExportModel em = xtest::export_model(*t, settings);
    const OutputFiles files = export_files(em, MBX_EXPORT_URDF);
    const OutputFile* f = xtest::find_file(files, "urdf/carriage.urdf");
    REQUIRE(f);
    const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(f->contents);
    REQUIRE(model);
    const UrdfLayout layout = plan_urdf(em);
    const urdf::JointConstSharedPtr slide = model->getJoint(layout.joint_name[size_t(joint_named(m, "slide"))]);
    REQUIRE(slide);
    REQUIRE(slide->dynamics);
    CHECK(slide->dynamics->friction == 1.25);
    CHECK(slide->dynamics->damping == 20);
    const std::string lead = "URDF joint friction and damping are symmetric and it has no constant joint effort";
    CHECK(notes_with(em, lead) == 2);
    CHECK(notes_with(em, lead + ": joint 'slide' is written without the effort offset -3.16 N") == 1);
    CHECK(notes_with(em, "joint 'pivot' is written without the effort offset 0.2 N m and the Stribeck peak") == 1);
}

TEST_CASE("joint dynamics extra: Modelica holds the offset and asymmetric Coulomb as a constant source, Stribeck as the table") {
    auto t = xtest::translate(carriage_pendulum());
    const Mechanism& m = *t->mechanism;
    ExportSettings settings;
    settings.model_name = "carriage";
    settings.joint_dynamics = resolve_joints(m, kJoints);
    const mtest::Package p = mtest::export_package(*t, settings);
    const OutputFile* f = p.file("Mechatronic.mo");
    REQUIRE_MESSAGE(f, "no Mechatronic.mo");
    const msl::Model model = msl::parse_model(f->contents);
    for (const std::string& e : model.errors) FAIL_CHECK(e);
    msl::Index index = mtest::msl_index();
    index.add(p.name + ".Mechanics", msl::class_info(p.mechanics));
    for (const std::string& err : msl::check_model(index, model)) FAIL_CHECK(err);

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

    // Slide: effort on the joint -offset - (c+ - c-)/2 = 3.16 - 0.75 = 2.41 N,
    // MSL's source driving its flange (the axis) with +f_constant.
    const msl::Component* so = model.find("slide_offset");
    REQUIRE(so);
    CHECK(so->class_name == kTrans + "Sources.ConstantForce");
    CHECK(value(*so, "f_constant") == mbx_test::relative(2.41, 1e-14));
    CHECK(so->value("useSupport") == "true");
    CHECK(connected("slide_offset.flange", "mechanics.axis_slide"));
    CHECK(connected("slide_offset.support", "mechanics.support_slide"));
    const msl::Component* sf = model.find("slide_friction");
    REQUIRE(sf);
    CHECK(sf->value("f_pos") == "[0, 1.25]");  // the mean level: with the source, c+ up and c- down, stick and slip
    const msl::Component* sd = model.find("slide_damper");
    REQUIRE(sd);
    CHECK(value(*sd, "d") == 20);
    int damping_notes = 0;
    for (const Finding& n : p.notes)
        damping_notes += n.message.find("MSL's dampers are symmetric: joint 'slide' gets the mean damping 20") !=
                         std::string::npos;
    CHECK(damping_notes == 1);

    // Pivot: -offset on the joint; the friction table starts at the static
    // level c + stribeck (peak 1) and falls along exp(-(w/vs)^2).
    const msl::Component* po = model.find("pivot_offset");
    REQUIRE(po);
    CHECK(po->class_name == kRot + "Sources.ConstantTorque");
    CHECK(value(*po, "tau_constant") == -0.2);
    CHECK(connected("pivot_offset.flange", "mechanics.axis_pivot"));
    CHECK(connected("pivot_offset.support", "mechanics.support_pivot"));
    const msl::Component* pf = model.find("pivot_friction");
    REQUIRE(pf);
    CHECK(pf->class_name == kRot + "Components.BearingFriction");
    CHECK(value(*pf, "peak") == 1);
    // Rows [w, tau]: w = 0 at c + stribeck, then every vs / 4 along
    // c + stribeck exp(-(w/vs)^2) to 2.5 vs, then flat at c from 3 vs.
    std::string table = pf->value("tau_pos");
    INFO(table);
    REQUIRE(table.size() > 2);
    REQUIRE(table.front() == '[');
    REQUIRE(table.back() == ']');
    table = table.substr(1, table.size() - 2);
    std::vector<std::pair<double, double>> rows;
    for (size_t at = 0; at <= table.size();) {
        size_t end = table.find(';', at);
        if (end == std::string::npos) end = table.size();
        const std::string row = table.substr(at, end - at);
        const size_t comma = row.find(',');
        REQUIRE(comma != std::string::npos);
        rows.emplace_back(std::stod(row.substr(0, comma)), std::stod(row.substr(comma + 1)));
        at = end + 1;
    }
    REQUIRE(rows.size() == 13);
    CHECK(rows[0].first == 0);
    CHECK(rows[0].second == mbx_test::relative(0.5, 1e-15));  // the static level, exactly (peak 1)
    for (int k = 1; k <= 10; ++k) {
        const double x = 0.25 * k;
        CHECK(rows[size_t(k)].first == mbx_test::relative(x * 0.05, 1e-14));
        CHECK(rows[size_t(k)].second == mbx_test::relative(0.1 + 0.4 * std::exp(-x * x), 1e-14));
    }
    CHECK(rows[11].first == mbx_test::relative(0.15, 1e-14));
    CHECK(rows[12].first == mbx_test::relative(0.2, 1e-14));
    CHECK(rows[11].second == mbx_test::relative(0.1, 1e-15));
    CHECK(rows[12].second == mbx_test::relative(0.1, 1e-15));
}
}  // namespace MBX_UNITY_ID
