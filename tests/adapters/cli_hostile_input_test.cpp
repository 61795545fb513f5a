// Hostile files from the command line (issue 28): every file the CLI reads is
// a regular file within the input limit. /dev/zero given as an object
// library, a drive description, an experiment file or a record, and a
// directory given as a record, each end at once (not after reading until
// memory runs out, nor as "not well-formed XML" or "an empty record") with
// the file and what it is named, exit 1, nothing written. And the
// temporaries a killed run left are taken away by the next run.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "cli_support.h"

namespace MBX_UNITY_ID {

namespace {

using atest::run_cli;
const std::string kArm = std::string(MBX_SAMPLES_DIR) + "/emps_axis/emps_axis.xml";
const std::string kDrivesFile = std::string(MBX_SAMPLES_DIR) + "/mechatronics/emps_axis_drives.xml";

// An experiment whose fit and validation record is `record` (the EMPS columns).
std::string experiment_with(const atest::TempDir& dir, const std::string& record) {
    const std::string path = dir.file("experiment.xml");
    std::ofstream(path) << "<experiment version=\"1\">\n  <record file=\"" << record << "\" role=\"fit\"/>\n"
                        << "  <record file=\"" << record << "\" role=\"validation\"/>\n"
                        << "  <time column=\"t_s\" unit=\"s\"/>\n"
                        << "  <column name=\"q_meas_m\" joint=\"40:-:41\" quantity=\"position\" unit=\"m\"/>\n"
                        << "  <column name=\"force_N\" joint=\"40:-:41\" quantity=\"effort\" unit=\"N\"/>\n"
                        << "  <drive mode=\"effort\"/>\n  <compare joint=\"40:-:41\" quantity=\"position\"/>\n"
                        << "</experiment>\n";
    return path;
}

}  // namespace

TEST_CASE("cli: a device, pipe or directory given as a library, drive file, experiment or record is refused at once, named") {
    atest::TempDir dir("mbx_cli_hostile_files");
    const std::string out = dir.file("out");
    struct Case {
        const char* what;
        std::string arguments, named, says;
    };
    const std::vector<Case> cases = {
        {"library", "library /dev/zero", "/dev/zero", "character device"},
        {"--library", "translate '" + kArm + "' --library /dev/zero -o '" + out + "'", "/dev/zero", "character device"},
        {"--drives", "translate '" + kArm + "' --drives /dev/zero -o '" + out + "'", "/dev/zero", "character device"},
        {"--experiment", "calibrate '" + kArm + "' --drives '" + kDrivesFile + "' --experiment /dev/zero -o '" + out + "'",
         "/dev/zero", "character device"},
        {"record", "calibrate '" + kArm + "' --drives '" + kDrivesFile + "' --experiment '" + experiment_with(dir, "/dev/zero") +
                       "' -o '" + out + "'",
         "/dev/zero", "character device"},
    };
    for (const Case& c : cases) {
        const auto t0 = std::chrono::steady_clock::now();
        const atest::CliRun r = run_cli(dir, c.arguments);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        INFO(c.what << ": " << r.out << r.err);
        CHECK(r.code == 1);
        CHECK(r.err.find(c.named) != std::string::npos);
        CHECK(r.err.find(c.says) != std::string::npos);
        CHECK(seconds < 20);  // (the sanitizers' build; a bounded read takes milliseconds)
        CHECK(!std::filesystem::exists(out));
    }
    // A directory as the record: not "an empty record".
    std::filesystem::create_directories(dir.file("records"));
    const atest::CliRun r = run_cli(dir, "calibrate '" + kArm + "' --drives '" + kDrivesFile + "' --experiment '" +
                                             experiment_with(dir, dir.file("records")) + "' -o '" + out + "'");
    INFO(r.out << r.err);
    CHECK(r.code == 1);
    CHECK(r.err.find("records") != std::string::npos);
    CHECK(r.err.find("a directory") != std::string::npos);
    CHECK(!std::filesystem::exists(out));
}


// A translate killed mid-write leaves "<file>.tmp.<pid>.<n>" files beside its
// outputs; the next run into the same folder removes them (their writer is
// gone) and leaves what is not one of them.
TEST_CASE("cli: a killed run's temporaries are removed by the next run into the same folder") {
    atest::TempDir dir("mbx_cli_stale_temporaries");
    const std::string out = dir.file("out");
    const pid_t dead = ::fork();
    if (dead == 0) ::_exit(0);
    REQUIRE(dead > 0);
    ::waitpid(dead, nullptr, 0);
    const std::string pid = std::to_string(long(dead));
    std::filesystem::create_directories(out + "/mjcf");
    const std::vector<std::string> stale = {out + "/report.json.tmp." + pid + ".4", out + "/report.txt.tmp." + pid + ".5",
                                            out + "/mjcf/emps_axis.xml.tmp." + pid + ".0"};
    for (const std::string& f : stale) std::ofstream(f) << "half a file";
    std::ofstream(out + "/notes.txt") << "the user's";
    const atest::CliRun r = run_cli(dir, "translate '" + kArm + "' -o '" + out + "'");
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    for (const std::string& f : stale) CHECK_MESSAGE(!std::filesystem::exists(f), f);
    CHECK(std::filesystem::exists(out + "/notes.txt"));
    CHECK(std::filesystem::exists(out + "/report.json"));
}

}  // namespace MBX_UNITY_ID
