// `mbx calibrate`: the EMPS rig end to end from the command line (the
// summary names the causes and the errors the issue asks for; the three
// files appear; description.xml fed back with --drives replays with the
// calibrated errors), and refusals that exit non-zero and write nothing.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "cli_support.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

namespace {

using Run = atest::CliRun;
using atest::run_cli;

const std::string kEmps = std::string(MBX_SAMPLES_DIR) + "/emps_axis/emps_axis.xml";
const std::string kDrives = std::string(MBX_SAMPLES_DIR) + "/mechatronics/emps_axis_drives.xml";
const std::string kExperiment = std::string(MBX_SAMPLES_DIR) + "/calibration/emps.xml";

// The "calibrated error <fit> % fit, <validation> % validation" line's numbers.
std::pair<double, double> replay_errors(const std::string& out, const std::string& lead) {
    const size_t at = out.find(lead);
    REQUIRE(at != std::string::npos);
    const char* p = out.c_str() + at + lead.size();
    char* end = nullptr;
    const double fit = std::strtod(p, &end);
    const size_t comma = out.find(", ", at);
    REQUIRE(comma != std::string::npos);
    const double validation = std::strtod(out.c_str() + comma + 2, nullptr);
    return {fit, validation};
}

}  // namespace

TEST_CASE("cli calibrate: EMPS names friction and the offset, and its description.xml reproduces the fit") {
    atest::TempDir dir("mbx_cli_calibrate");
    const std::string out = dir.file("out");
    const Run r = run_cli(dir, "calibrate '" + kEmps + "' --drives '" + kDrives + "' --experiment '" + kExperiment +
                                   "' -o '" + out + "' --progress");
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    for (const char* cause : {"coulomb_friction", "viscous_friction", "effort_offset"})
        CHECK(r.out.find(std::string("+ ") + cause + " on joint 'BED--CARRIAGE'") != std::string::npos);
    CHECK(r.err.find("mbx: replay") != std::string::npos);  // --progress
    const auto [fit, validation] = replay_errors(r.out, "calibrated error ");
    CHECK(fit <= 7);
    CHECK(validation <= 10);
    const auto [fit0, validation0] = replay_errors(r.out, "baseline error ");
    CHECK(fit0 > 65);
    for (const char* f : {"calibration.json", "calibration.html", "description.xml"})
        CHECK(std::filesystem::exists(std::filesystem::path(out) / f));

    const Run again = run_cli(dir, "calibrate '" + kEmps + "' --drives '" + out + "/description.xml' --experiment '" +
                                       kExperiment + "' -o '" + dir.file("again") + "'");
    INFO(again.out << again.err);
    REQUIRE(again.code == 0);
    const auto [fit1, validation1] = replay_errors(again.out, "baseline error ");
    CHECK(fit1 == mbx_test::relative(fit, 0.01));
    CHECK(validation1 == mbx_test::relative(validation, 0.01));
}

TEST_CASE("cli calibrate: usage errors and bad experiments exit non-zero and write nothing") {
    atest::TempDir dir("mbx_cli_calibrate_bad");
    const std::string out = dir.file("out");
    // No experiment: usage.
    Run r = run_cli(dir, "calibrate '" + kEmps + "' -o '" + out + "'");
    CHECK(r.code == 2);
    CHECK(r.err.find("--experiment") != std::string::npos);
    // A missing experiment file: named.
    r = run_cli(dir, "calibrate '" + kEmps + "' --drives '" + kDrives + "' --experiment '" + dir.file("none.xml") +
                         "' -o '" + out + "'");
    CHECK(r.code == 1);
    CHECK(r.err.find("none.xml") != std::string::npos);
    // Closed loop without the drive file: the drive the reference needs is missing.
    r = run_cli(dir, "calibrate '" + kEmps + "' --experiment '" + kExperiment + "' -o '" + out + "'");
    CHECK(r.code == 1);
    CHECK(r.err.find("no drive") != std::string::npos);
    CHECK(!std::filesystem::exists(out));
}
}  // namespace MBX_UNITY_ID
