// The committed sample files are exactly what mbx_make_samples writes: a
// change to the tools (or a hand edit of a sample) shows up here, not as a
// silently stale sample.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <doctest/doctest.h>

#include "samples/tools/samples.h"
#include "tests/common/skip.h"
#include "temp_dir.h"

namespace MBX_UNITY_ID {

namespace fs = std::filesystem;
using samples_test::TempDir;

namespace {

std::string read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void check_folder(const char* name, void (*make)(const std::string&)) {
    TempDir tmp(std::string("sample_") + name);
    REQUIRE(!tmp.path().empty());
    make(tmp.path());
    const fs::path committed = fs::path(MBX_SAMPLES_DIR) / name;
    size_t files = 0;
    // Sub-folders too (a sample's Simscape twin in simscape/).
    for (const auto& entry : fs::recursive_directory_iterator(tmp.path())) {
        if (entry.is_directory()) continue;
        const fs::path relative = fs::relative(entry.path(), tmp.path());
        INFO("file " << relative.string());
        REQUIRE(fs::exists(committed / relative));
        CHECK(read_all(entry.path()) == read_all(committed / relative));
        ++files;
    }
    // Nothing committed that the tool no longer writes (README.md aside).
    size_t committed_files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(committed))
        committed_files += !entry.is_directory() && entry.path().filename() != "README.md";
    CHECK(committed_files == files);
}

}  // namespace

TEST_CASE("committed samples match mbx_make_samples") {
    check_folder("fourbar_imperial", mbx_samples::make_fourbar_imperial);
    check_folder("double_cardan", mbx_samples::make_double_cardan);
    check_folder("five_axis_arm", mbx_samples::make_five_axis_arm);
    check_folder("joints_showcase", mbx_samples::make_joints_showcase);
    check_folder("emps_axis", mbx_samples::make_emps_axis);
}

TEST_CASE("committed Simscape sample matches mbx_make_samples (its levers are the real STEP parts in ../shared)") {
    if (!fs::exists(fs::path(MBX_SAMPLES_DIR) / "../../shared/data/step/dfki_double_pendulum/lever_200.STEP"))
        MBX_SKIP("no ../shared/data/step/dfki_double_pendulum beside the repository");
    check_folder("double_pendulum_simscape", mbx_samples::make_double_pendulum_simscape);
}
}  // namespace MBX_UNITY_ID
