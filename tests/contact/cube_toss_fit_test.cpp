// Contact calibration on the real ContactNets cube tosses: the contact
// causes fitted on a fixed training split, named only when the validation
// tosses (which the fit never sees) improve, and the fitted model scored
// against MuJoCo's default contact and against the parameters a published
// study fitted to these same tosses (solref -3294 -45.1, friction 0.218).
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "calibration/records/pose_records.h"
#include "core/finding.h"
#include "cube_tosses.h"
#include "tests/common/slow_build.h"
#include "tests/common/skip.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx_test;
using calibration::PoseError;
using calibration::PoseRecord;

namespace {

// Training: every 50th toss; validation: the other tosses of every tenth.
// In slow builds (slow_build.h) a few of each.
void split(const std::vector<PoseRecord>& all, std::vector<PoseRecord>& fit, std::vector<PoseRecord>& validation) {
    const int fit_every = kSlowBuild ? 190 : 50, validation_every = kSlowBuild ? 95 : 10;
    for (const PoseRecord& r : all) {
        if (r.trial % fit_every == 0) fit.push_back(r);
        else if (r.trial % validation_every == 0) validation.push_back(r);
    }
}

}  // namespace

TEST_CASE("contact calibration: pose records read the tosses and refuse broken ones") {
    const std::vector<PoseRecord> all = calibration::read_pose_records(cube_tosses_path());
    REQUIRE(all.size() == 570);
    CHECK(all[0].trial == 0);
    CHECK(all[0].samples.size() > 50);
    CHECK(std::abs(all[0].samples[1].t - all[0].samples[0].t - 1 / 148.0) < 1e-4);
    CHECK(std::abs(all[0].samples[0].q.norm() - 1) < 1e-12);

    const std::string dir = "cube_toss_fit_test_tmp";
    std::filesystem::create_directories(dir);
    auto write = [&](const std::string& name, const std::string& text) {
        std::ofstream(dir + "/" + name) << text;
        return dir + "/" + name;
    };
    const std::string header = "toss_id,k,t_s,x_m,y_m,z_m,qw,qx,qy,qz,vx_mps,vy_mps,vz_mps,wx_body_radps,wy_body_radps,wz_body_radps\n";
    const std::string row0 = "0,0,0.0,0,0,1,1,0,0,0,0,0,0,0,0,0\n", row1 = "0,1,0.01,0,0,1,1,0,0,0,0,0,0,0,0,0\n";
    CHECK_THROWS_WITH_AS(calibration::read_pose_records(write("no_qz.csv", "toss_id,t_s,x_m\n0,0,0\n")),
                         doctest::Contains("no_qz.csv:1: no column 'y_m'"), Error);
    CHECK_THROWS_WITH_AS(calibration::read_pose_records(write("back.csv", header + row1 + row0)),
                         doctest::Contains("back.csv:3: time does not increase within trial 0"), Error);
    CHECK_THROWS_WITH_AS(calibration::read_pose_records(write("zero_q.csv", header + row0 + "0,1,0.01,0,0,1,0,0,0,0,0,0,0,0,0,0\n")),
                         doctest::Contains("zero_q.csv:3: the orientation quaternion is zero"), Error);
    CHECK_THROWS_WITH_AS(calibration::read_pose_records(write("single.csv", header + row0 + row1 + "1,0,0.0,0,0,1,1,0,0,0,0,0,0,0,0,0\n")),
                         doctest::Contains("trial 1 has fewer than two samples"), Error);
    CHECK_THROWS_WITH_AS(calibration::read_pose_records(write("nan.csv", header + row0 + "0,1,0.01,0,0,nan,1,0,0,0,0,0,0,0,0,0\n")),
                         doctest::Contains("nan.csv:3"), Error);
    std::filesystem::remove_all(dir);
}

TEST_CASE("contact calibration: fitted on a training split of the tosses, it beats MuJoCo's published fit on the rest") {
    const std::vector<PoseRecord> all = calibration::read_pose_records(cube_tosses_path());
    std::vector<PoseRecord> fit, validation;
    split(all, fit, validation);
    const CubeScene cube;

    // The naive start: a generic contact (stiff Hunt-Crossley, restitution
    // 0.5 on a corner's share of the mass, mu 0.5), no knowledge of the board.
    calibration::ContactModel start;
    start.settings = nominal_cube_contact();
    start.settings.normal.damping = sim::contact::damping_for_restitution(start.settings.normal, kCubeMass / 4, 1.0, 0.5);
    start.settings.friction.mu_static = start.settings.friction.mu_kinetic = 0.5;
    calibration::ContactFitOptions options;
    options.progress = [](const std::string& m) { MESSAGE(m); };
    if (kSlowBuild) {
        options.causes = {"contact_friction", "contact_damping"};
        options.max_iterations = 2;
    }
    const calibration::ContactFit result = calibration::fit_contact(cube.scene, start, fit, validation, options);

    auto mj_default = mujoco_cube("");
    auto mj_published = mujoco_cube("solref=\"-3294 -45.1\" friction=\"0.218 0.005 0.0001\"");
    const PoseError def = mujoco_error(mj_default.get(), validation), pub = mujoco_error(mj_published.get(), validation);
    const PoseError final_validation = calibration::pose_error(cube.scene, result.model, validation);
    MESSAGE(fit.size() << " training and " << validation.size() << " validation tosses; validation error (% of edge / deg): "
                       << "mbx start " << result.baseline_validation.position << " / " << result.baseline_validation.rotation
                       << ", mbx fitted " << final_validation.position << " / " << final_validation.rotation
                       << ", MuJoCo default " << def.position << " / " << def.rotation << ", MuJoCo published fit "
                       << pub.position << " / " << pub.rotation << "; " << result.rollouts << " toss rollouts");
    for (const auto& s : result.steps) {
        std::ostringstream p;
        for (const auto& v : s.parameters) p << " " << v.name << "=" << v.value << "±" << v.standard_error << " " << v.unit;
        MESSAGE("named " << s.cause << ":" << p.str() << " (" << s.evidence << ")");
    }
    for (const std::string& n : result.notes) MESSAGE(n);

    CHECK(final_validation.diverged == 0);
    REQUIRE_FALSE(result.steps.empty());
    // Every named cause earned its place on the validation tosses.
    PoseError before = result.baseline_validation;
    for (const auto& s : result.steps) {
        CHECK(s.validation.score() < before.score() * (1 - options.min_validation_gain));
        before = s.validation;
    }
    if (!kSlowBuild) {
        // The naive contact is far off; the fit at least halves its error on the tosses it never saw.
        CHECK(final_validation.score() < 0.5 * result.baseline_validation.score());
        // The goal of the issue: better than MuJoCo fitted to these tosses.
        CHECK(final_validation.position < pub.position);
        CHECK(final_validation.rotation < pub.rotation);
    } else {
        MBX_SKIP_PART("the fit's statistics (half the naive error, better than MuJoCo's published fit) need the "
                      "release build's 12 training tosses");
    }
    // Left lying where the tosses end, the fitted model holds the cube without drift.
    int at_rest = 0;
    for (size_t k = 0; k < validation.size(); k += 5) {
        const calibration::Rollout r = calibration::roll_out(cube.scene, result.model, validation[k], 2.0);
        at_rest += r.rest_speed < 1e-4 && r.rest_drift < 1e-6;
        CHECK_MESSAGE(r.rest_drift < 1e-6, "toss " << validation[k].trial << " drifts " << r.rest_drift << " m");
    }
    CHECK(at_rest == int((validation.size() + 4) / 5));
}

TEST_CASE("contact calibration: refuses what it cannot fit") {
    const CubeScene cube;
    std::vector<PoseRecord> all = calibration::read_pose_records(cube_tosses_path());
    std::vector<PoseRecord> one(all.begin(), all.begin() + 1);
    calibration::ContactModel start;
    start.settings = nominal_cube_contact();
    calibration::ContactFitOptions options;
    options.causes = {"contact_glue"};
    CHECK_THROWS_WITH_AS(calibration::fit_contact(cube.scene, start, one, one, options),
                         doctest::Contains("'contact_glue' is not a contact cause"), Error);
    CHECK_THROWS_WITH_AS(calibration::fit_contact(cube.scene, start, one, {}, {}),
                         doctest::Contains("needs fit and validation trials"), Error);
    calibration::ContactScene bare = cube.scene;
    bare.shapes = {ground_plane()};
    CHECK_THROWS_WITH_AS(calibration::fit_contact(bare, start, one, one, {}), doctest::Contains("has no collision shape"), Error);
    calibration::ContactScene world = cube.scene;
    world.body = 0;
    CHECK_THROWS_WITH_AS(calibration::fit_contact(world, start, one, one, {}), doctest::Contains("is not in the model"), Error);
    // A contact far too stiff for the step: the start diverges, and says so.
    calibration::ContactModel wild = start;
    wild.settings.normal.stiffness = 1e14, wild.settings.normal.damping = 0;
    wild.settings.normal.model = sim::contact::NormalModel::Spring;
    options.causes = {"contact_stiffness"};
    CHECK_THROWS_WITH_AS(calibration::fit_contact(cube.scene, wild, one, one, options),
                         doctest::Contains("diverge"), Error);
}
}  // namespace MBX_UNITY_ID
