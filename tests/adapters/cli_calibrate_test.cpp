// `mbx calibrate`: the EMPS rig end to end from the command line (the
// summary names the causes and the errors the issue asks for; the three
// files appear; description.xml fed back with --drives replays with the
// calibrated errors), and refusals that exit non-zero and write nothing.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "cli_support.h"
#include "tests/common/near.h"
#include "tests/common/skip.h"
#include "tests/common/slow_build.h"

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

// `mbx calibrate` under an address-space limit (ulimit -v, RLIMIT_AS; issue
// 28): from the least limit the CLI starts under (its libraries' mappings)
// up to 1 GiB, every run on a 100 000-sample record (the EMPS training
// record four times) either calibrates, writing its three files, or stops
// with the out-of-memory status naming the limit and its size, writing
// nothing; never an abort, a crash or a bare "out of memory". (Release
// only: AddressSanitizer reserves terabytes of address space for itself.)
TEST_CASE("cli calibrate: under an address-space limit it calibrates or stops naming the limit") {
    if (kSlowBuild) MBX_SKIP("AddressSanitizer cannot run under an address-space limit (and the debug build's needs differ)");
    atest::TempDir dir("mbx_cli_calibrate_rlimit");
    {
        std::ifstream in(mbx_test::shared_data("measured/emps/emps_train.csv"));
        REQUIRE(in);
        std::string header, line;
        std::getline(in, header);
        std::vector<std::string> rows;
        while (std::getline(in, line))
            if (!line.empty()) rows.push_back(line.substr(line.find(',')));
        std::ofstream out(dir.file("long.csv"));
        out << header << "\n";
        long k = 0;
        for (int repeat = 0; repeat < 4; ++repeat)
            for (const std::string& r : rows) out << k * 1e-3 << r << "\n", ++k;
        std::ifstream experiment(kExperiment);
        std::stringstream text;
        text << experiment.rdbuf();
        std::string xml = text.str();
        const std::string train = "../../../shared/data/measured/emps/emps_train.csv",
                          pulses = "../../../shared/data/measured/emps/emps_test_pulses.csv";
        REQUIRE(xml.find(train) != std::string::npos);
        xml.replace(xml.find(train), train.size(), dir.file("long.csv"));
        xml.replace(xml.find(pulses), pulses.size(), mbx_test::shared_data("measured/emps/emps_test_pulses.csv"));
        std::ofstream(dir.file("experiment.xml")) << xml;
    }
    const long floor = atest::least_cli_address_space(dir);
    REQUIRE(floor > 0);
    int calibrated = 0, refused = 0;
    for (long kib = floor; kib <= 1024 * 1024; kib = kib < floor + 32 * 1024 ? kib + 4 * 1024 : kib * 2) {
        const std::string out = dir.file("out" + std::to_string(kib));
        const atest::CliRun r = atest::run_cli_under(dir, kib, "calibrate '" + kEmps + "' --drives '" + kDrives + "' --experiment '" +
                                               dir.file("experiment.xml") + "' -o '" + out + "'");
        CAPTURE(kib);
        INFO(r.out << r.err);
        if (r.code == 0) {
            ++calibrated;
            for (const char* f : {"calibration.json", "calibration.html", "description.xml"})
                CHECK(std::filesystem::exists(std::filesystem::path(out) / f));
            CHECK(r.out.find("+ viscous_friction on joint 'BED--CARRIAGE'") != std::string::npos);
        } else {
            ++refused;
            CHECK(r.code == 1);
            CHECK(r.err.find("MBX_ERROR_OUT_OF_MEMORY") != std::string::npos);
            char size[32];
            std::snprintf(size, sizeof size, "%.4g MiB", double(kib) / 1024);
            CHECK(r.err.find(std::string("address-space limit of ") + size) != std::string::npos);
            CHECK(!std::filesystem::exists(out));
        }
    }
    MESSAGE("starts under " << floor / 1024 << " MiB; " << refused << " limits refused, " << calibrated << " calibrated");
    CHECK(refused >= 1);     // the record needs more than the CLI's start
    CHECK(calibrated >= 4);  // and from some limit on, every larger one (up to 1 GiB) is enough
}

}  // namespace MBX_UNITY_ID
