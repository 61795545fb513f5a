// Compliance through the whole loop: a transmission MuJoCo hid in the
// two-link arm's elbow (a motor body with the armature, a spring and damper
// to the link) is named by calibrate() with its stiffness within the
// hidden-effect suite's tolerance, written to description.xml as the
// joint's <transmission>, and the model built from that file replays with
// the calibrated errors.
#include <doctest/doctest.h>

#include <cmath>

#include "calibration/calibrate.h"
#include "calibration/outputs/calibration_files.h"
#include "calibration/simulation/model_extension.h"
#include "calibration/simulation/transmission_stage.h"
#include "hidden_effects.h"
#include "core/mechatronics/drive_file.h"
#include "sim/resolved_joint_dynamics.h"
#include "tests/common/slow_build.h"
#include "temp_dir.h"
#include "tests/common/near.h"
#include "tests/common/skip.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::calibration;

TEST_CASE("calibration: compliance is named, written to description.xml and fed back replays as calibrated") {
    if (kSlowBuild) {
        // Jets through the dynamics for the simulation stage take minutes here.
        MBX_SKIP("the simulation stage is too slow in this build (sanitizers or no optimisation)");
    }
    mbx_test::TempDir dir("mbx_compliance");
    mbx_test::CaseSpec spec;
    spec.name = "compliance", spec.mechanism = "two_link_arm", spec.seed = 1;
    spec.effects = {{"compliance", "two_link_arm/elbow", 11, 11}};
    const mbx_test::GeneratedCase c = mbx_test::generate_case(spec, dir.file("case"));
    REQUIRE(c.hidden.size() == 1);
    const double truth = c.hidden[0].parameter("stiffness");

    auto t = mbx_test::open_mechanism("two_link_arm");
    Mechanism& mech = *t->mechanism;
    const Experiment e = load_experiment(c.experiment_path);
    const CalibrationResult r = calibrate(mech, {}, e);
    for (const std::string& w : r.warnings) MESSAGE("warning: " << w);
    for (const std::string& s : r.identification.considered)
        if (s.rfind("compliance", 0) == 0) MESSAGE("considered: " << s);
    const SelectedCause* named = nullptr;
    for (const SelectedCause& s : r.identification.causes) {
        MESSAGE("named " << s.candidate.cause << " on " << s.candidate.joint);
        if (s.candidate.cause == "compliance") named = &s;
    }
    REQUIRE(named);
    const sim::Model model = sim::build_model(mech, {});
    CHECK(model.joints[size_t(named->candidate.joint)].constraint_id == c.hidden[0].joint_id);
    CHECK(r.identification.causes.size() == 1);  // nothing else hidden, nothing else named
    const double stiffness = named->parameters[0].value;
    MESSAGE("stiffness " << stiffness << " (truth " << truth << ", " << 100 * std::fabs(stiffness / truth - 1) << " % off)");
    CHECK(std::fabs(stiffness / truth - 1) < 0.10);
    REQUIRE(r.joints.size() == 1);
    REQUIRE(r.joints[0].transmission_after);
    CHECK(r.joints[0].transmission_after->stiffness == stiffness);
    CHECK(r.unwritten.empty());
    // The replay with the transmission is not worse than the rigid baseline.
    MESSAGE("simulated validation error: baseline " << r.baseline().simulated_validation << " %, calibrated "
                                                    << r.final_step().simulated_validation << " %");
    CHECK(r.final_step().simulated_validation < r.baseline().simulated_validation);

    write_calibration_files(dir.file("out"), mech, model, e, r, "");
    MechatronicSpec fed;
    std::vector<DriveError> errors;
    load_drive_file(dir.file("out/description.xml"), fed, errors);
    for (const DriveError& x : errors) FAIL_CHECK(x.text());
    REQUIRE(fed.joint_dynamics.size() == 1);
    REQUIRE(fed.joint_dynamics[0].transmission);
    CHECK(fed.joint_dynamics[0].transmission->stiffness == stiffness);
    CHECK(fed.joint_dynamics[0].transmission->motor_inertia == named->parameters[2].value);
    const std::vector<ResolvedJointDynamics> resolved = resolve_joint_dynamics(fed, mech, errors);
    REQUIRE(errors.empty());
    sim::BuildOptions options;
    options.joint_dynamics = sim::joint_dynamics_by_joint(resolved);
    options.transmissions = sim::transmissions_by_joint(resolved);
    REQUIRE(options.transmissions.size() == 1);

    const CalibrationResult again = calibrate(mech, options, e);
    MESSAGE("calibrated " << r.final_step().simulated_fit << " / " << r.final_step().simulated_validation
                          << " %, fed back " << again.baseline().simulated_fit << " / "
                          << again.baseline().simulated_validation << " %");
    CHECK(again.baseline().simulated_fit == mbx_test::relative(r.final_step().simulated_fit, 1e-9));
    CHECK(again.baseline().simulated_validation == mbx_test::relative(r.final_step().simulated_validation, 1e-9));
    // The linear stage sees the transmission in its rigid limit (its motor
    // inertia as armature): neither it nor another armature is named again,
    // and the stage says why it does not refit it. (What the rigid limit
    // leaves can still correlate with a body's mass: docs/calibration.md.)
    for (const SelectedCause& s : again.identification.causes) {
        MESSAGE("fed back, named " << s.candidate.cause << " on " << s.candidate.joint << ": " << s.evidence);
        CHECK(s.candidate.cause != "compliance");
        CHECK(s.candidate.cause != "armature");
    }
}

TEST_CASE("calibration: the rigid limit of a transmission is its motor inertia as armature") {
    auto t = mbx_test::open_mechanism("two_link_arm");
    const sim::Model bare = sim::build_model(*t->mechanism, {});
    sim::BuildOptions options;
    sim::Transmission tr;
    tr.stiffness = 500, tr.motor_inertia = 0.02;
    options.transmissions[bare.joints[1].source] = tr;
    const sim::Model m = sim::build_model(*t->mechanism, options);
    const sim::Model rigid = rigid_limit(m);
    CHECK(rigid.transmissions.empty());
    CHECK(rigid.transmission_of_dof[1] == -1);
    CHECK(rigid.joints[1].dynamics.armature == 0.02);
    CHECK(rigid.joints[1].reference_inertia == mbx_test::relative(bare.joints[1].reference_inertia + 0.02, 1e-6));
    CHECK(rigid.joints[0].dynamics.armature == 0);
}

TEST_CASE("calibration: a named backlash becomes the joint's <transmission backlash> and the model's dead band") {
    auto t = mbx_test::open_mechanism("two_link_arm");
    const Mechanism& mech = *t->mechanism;
    const sim::Model model = sim::build_model(mech, {});
    CalibrationResult r;
    r.steps.emplace_back();
    SelectedCause b;
    b.candidate.cause = "backlash", b.candidate.joint = 1, b.candidate.dof = 1, b.candidate.q_index = model.joints[1].q_index;
    b.candidate.parameters = {"width", "motor_inertia"};
    b.parameters = {{"width", 0.02, 0.004}, {"motor_inertia", 0.007, 1e-4}};
    r.identification.causes.push_back(b);
    const ModelExtension ext = extend(mech, {}, model, r.identification, 1, RegressionRows{});
    CHECK(ext.unwritten.empty());
    REQUIRE(ext.options.transmissions.size() == 1);
    const sim::Model extended = extended_model(mech, ext, DriveMode::Effort);
    REQUIRE(extended.transmissions.size() == 1);
    CHECK(extended.transmissions[0].joint == 1);
    CHECK(extended.transmissions[0].backlash == 0.02);
    CHECK(extended.transmissions[0].stiffness == 0);
    CHECK(extended.transmissions[0].motor_inertia == 0.007);
    r.joints = ext.joints;
    const std::string text = calibrated_description(mech, model, r, "");
    MechatronicSpec spec;
    std::vector<DriveError> errors;
    load_drive_text(text, "description.xml", "", spec, errors);
    for (const DriveError& x : errors) FAIL_CHECK(x.text());
    REQUIRE(spec.joint_dynamics.size() == 1);
    REQUIRE(spec.joint_dynamics[0].transmission);
    CHECK(spec.joint_dynamics[0].transmission->backlash == 0.02);
    CHECK(spec.joint_dynamics[0].transmission->stiffness == 0);
    CHECK(spec.joint_dynamics[0].transmission->motor_inertia == 0.007);
    CHECK(text.find("<transmission motor_inertia=\"0.007\" backlash=\"0.02\"/>") != std::string::npos);
}
}  // namespace MBX_UNITY_ID
