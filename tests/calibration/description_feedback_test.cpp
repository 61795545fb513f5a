// The calibrated description file fed back: a mass error or a moved centre
// of mass MuJoCo hid in the two-link arm's forearm is named, written as the
// forearm's <body mass_scale com_shift>, and the model built from that file
// (the correction applied to the mechanism, as mbx_mechanism_set_mechatronics
// does) replays with the calibrated errors and has nothing left to name.
#include <doctest/doctest.h>

#include <cmath>

#include "calibration/calibrate.h"
#include "calibration/outputs/calibration_files.h"
#include "hidden_effects.h"
#include "core/mechatronics/drive_file.h"
#include "temp_dir.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::calibration;

namespace {

// What the calibration of `spec` names and writes, fed back: the file holds
// exactly what was found, and the model built from it replays with the
// calibrated errors and has nothing left to name. Returns the correction.
BodyCorrection fed_back(const mbx_test::CaseSpec& spec, const mbx_test::TempDir& dir) {
    const mbx_test::GeneratedCase c = mbx_test::generate_case(spec, dir.file(spec.name + "/case"));
    REQUIRE(c.hidden.size() == 1);
    auto t = mbx_test::open_mechanism("two_link_arm");
    Mechanism& mech = *t->mechanism;
    const Experiment e = load_experiment(c.experiment_path);
    const CalibrationResult r = calibrate(mech, {}, e);
    REQUIRE(r.identification.causes.size() == 1);
    CHECK(r.identification.causes[0].candidate.cause == "mass_error");
    REQUIRE(r.bodies.size() == 1);
    CHECK(r.bodies[0].id == c.hidden[0].body_id);
    CHECK(r.unwritten.empty());

    const sim::Model model = sim::build_model(mech, {});
    write_calibration_files(dir.file(spec.name + "/out"), mech, model, e, r, "");
    MechatronicSpec fed;
    std::vector<DriveError> errors;
    load_drive_file(dir.file(spec.name + "/out/description.xml"), fed, errors);
    REQUIRE(errors.empty());
    REQUIRE(fed.body_masses.size() == 1);
    CHECK(fed.body_masses[0].body == r.bodies[0].id);
    // What the file holds reads back as exactly what calibration found.
    const BodyCorrection& found = r.bodies[0].correction;
    CHECK(fed.body_masses[0].mass_scale == found.mass_scale);
    for (int k = 0; k < 3; ++k) CHECK(fed.body_masses[0].com_shift[k] == found.com_shift[k]);
    for (int k = 0; k < 6; ++k) CHECK(fed.body_masses[0].inertia_change[size_t(k)] == found.inertia_change[k]);
    const std::vector<ResolvedBodyMass> masses = resolve_body_masses(fed.body_masses, mech, nullptr, errors);
    REQUIRE(errors.empty());
    const RigidBody cad = mech.bodies[size_t(masses[0].body)];
    apply_body_masses(mech, cad_inertia(mech), masses);
    CHECK(mech.bodies[size_t(masses[0].body)].mass == mbx_test::relative(cad.mass * found.mass_scale, 1e-6));
    CHECK((mech.bodies[size_t(masses[0].body)].com - cad.com - found.com_shift).norm() < 1e-12);

    const CalibrationResult again = calibrate(mech, {}, e);
    MESSAGE(spec.name << ": calibrated " << r.final_step().simulated_fit << " / " << r.final_step().simulated_validation
                      << " %, fed back " << again.baseline().simulated_fit << " / "
                      << again.baseline().simulated_validation << " %");
    CHECK(again.baseline().simulated_fit == mbx_test::relative(r.final_step().simulated_fit, 1e-9));
    CHECK(again.baseline().simulated_validation == mbx_test::relative(r.final_step().simulated_validation, 1e-9));
    CHECK(again.identification.causes.empty());
    return found;
}

}  // namespace

TEST_CASE("calibration: a mass error written to description.xml and fed back replays as calibrated") {
    mbx_test::TempDir dir("mbx_feedback");
    mbx_test::CaseSpec spec;
    spec.name = "mass", spec.mechanism = "two_link_arm", spec.seed = 11;
    spec.effects = {{"mass_error", "two_link_arm/forearm", 0.3, 0.3}};
    const BodyCorrection found = fed_back(spec, dir);
    CHECK(found.mass_scale == mbx_test::relative(1.3, 0.03));
    CHECK(found.com_shift.isZero(0));
}

TEST_CASE("calibration: a centre of mass moved, written as com_shift and fed back, replays as calibrated") {
    mbx_test::TempDir dir("mbx_feedback_com");
    mbx_test::CaseSpec spec;
    spec.name = "com", spec.mechanism = "two_link_arm", spec.seed = 11;
    spec.effects = {{"com_shift", "two_link_arm/forearm", 0.04, 0.04, Eigen::Vector3d::UnitZ()}};
    const BodyCorrection found = fed_back(spec, dir);
    CHECK(found.mass_scale == 1);
    CHECK(found.com_shift.z() == mbx_test::relative(0.04, 0.05));
    CHECK(found.com_shift.y() == 0);  // along the joints' axis: no record sees it
}
}  // namespace MBX_UNITY_ID
