// A tilted mounting: MuJoCo's gravity turned 1-3 degrees about a horizontal
// axis under a yaw-pitch-pitch arm is named as mounting_tilt with its angle
// and nothing else, written to description.xml as <mounting>, and read back
// by the description's reader; level records name no tilt.
#include <doctest/doctest.h>

#include <cmath>

#include "calibration/calibrate.h"
#include "calibration/outputs/calibration_files.h"
#include "calibration/records/experiment.h"
#include "core/mechatronics/drive_file.h"
#include "core/mechatronics/mounting.h"
#include "hidden_effects.h"
#include "sim/build_model.h"
#include "temp_dir.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::calibration;

std::string named_text(const Identification& id) {
    std::string text;
    for (const SelectedCause& sc : id.causes) {
        text += " " + sc.candidate.cause + "(";
        for (const Estimate& e : sc.parameters) text += e.name + "=" + std::to_string(e.value) + " ";
        text += ")";
    }
    for (const std::string& w : id.warnings) text += "; warning: " + w;
    return text;
}

TEST_CASE("mounting tilt: gravity turned 1 to 3 degrees is named with its angle, and nothing else") {
    mbx_test::TempDir dir("mbx_tilt");
    struct Tilt {
        const char* axis;
        double degrees;
    };
    for (const Tilt& tilt : {Tilt{"x", 1.0}, Tilt{"y", -2.0}, Tilt{"x", 3.0}}) {
        mbx_test::CaseSpec spec;
        spec.name = std::string("tilt_") + tilt.axis + std::to_string(int(tilt.degrees));
        spec.mechanism = "yaw_arm", spec.seed = 3;
        const double angle = tilt.degrees * M_PI / 180;
        spec.effects = {{"mounting_tilt", tilt.axis, angle, angle}};
        const mbx_test::GeneratedCase c = mbx_test::generate_case(spec, dir.file(spec.name));
        auto t = mbx_test::open_mechanism(spec.mechanism);
        const CalibrationResult r = calibrate(*t->mechanism, {}, load_experiment(c.experiment_path));
        const Identification& id = r.identification;
        MESSAGE(spec.name << ": validation " << id.baseline_validation_error << " -> " << id.final_validation_error
                          << " %, floor " << id.noise_level << " %;" << named_text(id));
        REQUIRE(id.causes.size() == 1);
        CHECK(id.causes[0].candidate.cause == "mounting_tilt");
        const std::string turned = std::string("tilt_") + tilt.axis, other = tilt.axis[0] == 'x' ? "tilt_y" : "tilt_x";
        for (const Estimate& e : id.causes[0].parameters) {
            if (e.name == turned) CHECK(e.value == mbx_test::relative(angle, 0.05));
            // The other axis, where the candidate carries it, stays level to a tenth of the turn.
            if (e.name == other) CHECK(std::abs(e.value) < 0.1 * std::abs(angle));
        }
        REQUIRE(r.mounting_tilted);
        CHECK(r.mounting_tilt[tilt.axis[0] == 'x' ? 0 : 1] == mbx_test::relative(angle, 0.05));
        CHECK(explained_to_noise(id.final_validation_error, id.noise_level));

        // description.xml holds it as <mounting> in degrees; the reader turns it back into the angle.
        const std::string out = dir.file(spec.name + "_out");
        write_calibration_files(out, *t->mechanism, sim::build_model(*t->mechanism), load_experiment(c.experiment_path), r, "");
        MechatronicSpec read;
        std::vector<DriveError> errors;
        load_drive_file(out + "/description.xml", read, errors);
        REQUIRE(errors.empty());
        REQUIRE(read.mounting.given);
        CHECK((tilt.axis[0] == 'x' ? read.mounting.tilt_x : read.mounting.tilt_y) == mbx_test::relative(angle, 0.05));
        // The gravity the simulator then takes is MuJoCo's.
        const Vec3 g = tilted_gravity(Vec3(0, 0, -9.81), read.mounting);
        const Vec3 truth = Eigen::AngleAxisd(angle, tilt.axis[0] == 'x' ? Vec3::UnitX() : Vec3::UnitY()) * Vec3(0, 0, -9.81);
        CHECK((g - truth).norm() < 0.05 * 9.81 * std::abs(angle));
    }
}

TEST_CASE("mounting tilt: level records of the yaw arm name no tilt") {
    mbx_test::TempDir dir("mbx_level");
    mbx_test::CaseSpec spec;
    spec.name = "level", spec.mechanism = "yaw_arm", spec.seed = 3;
    const mbx_test::GeneratedCase c = mbx_test::generate_case(spec, dir.file(spec.name));
    auto t = mbx_test::open_mechanism(spec.mechanism);
    const CalibrationResult r = calibrate(*t->mechanism, {}, load_experiment(c.experiment_path));
    MESSAGE("level: validation " << r.identification.final_validation_error << " %, floor " << r.identification.noise_level
                                 << " %;" << named_text(r.identification));
    CHECK(r.identification.causes.empty());
    CHECK(!r.mounting_tilted);
}

}  // namespace MBX_UNITY_ID
