// The calibrated description file fed back: a mass error MuJoCo hid in the
// two-link arm's forearm is named, written as the forearm's <body
// mass_scale>, and the model built from that file (the correction applied to
// the mechanism, as mbx_mechanism_set_mechatronics does) replays with the
// calibrated errors and has nothing left to name.
#include <doctest/doctest.h>

#include <cmath>

#include "calibration/calibrate.h"
#include "calibration/calibration_files.h"
#include "hidden_effects.h"
#include "mechatronics/drive_file.h"
#include "temp_dir.h"

using namespace mbx;
using namespace mbx::calibration;

TEST_CASE("calibration: a mass error written to description.xml and fed back replays as calibrated") {
    mbx_test::TempDir dir("mbx_feedback");
    mbx_test::CaseSpec spec;
    spec.name = "mass", spec.mechanism = "two_link_arm", spec.seed = 11;
    spec.effects = {{"mass_error", "two_link_arm/forearm", 0.3, 0.3}};
    const mbx_test::GeneratedCase c = mbx_test::generate_case(spec, dir.file("case"));
    REQUIRE(c.hidden.size() == 1);
    const double truth = c.hidden[0].parameter("relative_mass_change");

    auto t = mbx_test::open_mechanism("two_link_arm");
    Mechanism& mech = *t->mechanism;
    const Experiment e = load_experiment(c.experiment_path);
    const CalibrationResult r = calibrate(mech, {}, e);
    REQUIRE(!r.identification.causes.empty());
    CHECK(r.identification.causes[0].candidate.cause == "mass_error");
    REQUIRE(r.bodies.size() == 1);
    CHECK(r.bodies[0].id == c.hidden[0].body_id);
    CHECK(r.bodies[0].factor == doctest::Approx(1 + truth).epsilon(0.03));
    CHECK(r.unwritten.empty());

    const sim::Model model = sim::build_model(mech, {});
    write_calibration_files(dir.file("out"), mech, model, e, r, "");
    MechatronicSpec fed;
    std::vector<DriveError> errors;
    load_drive_file(dir.file("out/description.xml"), fed, errors);
    REQUIRE(errors.empty());
    REQUIRE(fed.body_masses.size() == 1);
    CHECK(fed.body_masses[0].body == r.bodies[0].id);
    CHECK(fed.body_masses[0].mass_scale == r.bodies[0].factor);
    const std::vector<ResolvedBodyMass> masses = resolve_body_masses(fed.body_masses, mech, errors);
    REQUIRE(errors.empty());
    const double cad_mass = mech.bodies[size_t(masses[0].body)].mass;
    apply_body_masses(mech, cad_inertia(mech), masses);
    CHECK(mech.bodies[size_t(masses[0].body)].mass == doctest::Approx(cad_mass * r.bodies[0].factor));

    const CalibrationResult again = calibrate(mech, {}, e);
    MESSAGE("calibrated " << r.final_step().simulated_fit << " / " << r.final_step().simulated_validation
                          << " %, fed back " << again.baseline().simulated_fit << " / "
                          << again.baseline().simulated_validation << " %");
    CHECK(again.baseline().simulated_fit == doctest::Approx(r.final_step().simulated_fit).epsilon(0.01));
    CHECK(again.baseline().simulated_validation == doctest::Approx(r.final_step().simulated_validation).epsilon(0.01));
    CHECK(again.identification.causes.empty());
}
