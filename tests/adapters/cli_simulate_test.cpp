// `mbx simulate`: options, the files a run writes (checked against closed
// forms), and that every refusal exits non-zero with a message and writes
// nothing.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "cli_support.h"
#include "tests/common/skip.h"
#include "tests/common/slow_build.h"
#include "core/report/json_value.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

namespace {

using Run = atest::CliRun;
using atest::run_cli;

struct Csv {
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
    int column(const std::string& name) const {
        for (size_t k = 0; k < columns.size(); ++k)
            if (columns[k] == name) return int(k);
        return -1;
    }
};

Csv read_csv(const std::string& path) {
    std::istringstream in(atest::read_file(path));
    Csv c;
    std::string line;
    std::getline(in, line);
    std::istringstream header(line);
    for (std::string cell; std::getline(header, cell, ',');) c.columns.push_back(cell);
    while (std::getline(in, line)) {
        std::istringstream row(line);
        std::vector<double> values;
        for (std::string cell; std::getline(row, cell, ',');) values.push_back(std::stod(cell));
        REQUIRE(values.size() == c.columns.size());
        c.rows.push_back(values);
    }
    return c;
}

const std::string kEmps = std::string(MBX_SAMPLES_DIR) + "/emps_axis/emps_axis.xml";

}  // namespace

TEST_CASE("cli simulate: the EMPS carriage falls along its slide as gravity along it says") {
    atest::TempDir dir("mbx_cli_simulate");
    // Gravity 2 m/s^2 along the slide (+x) and a start at 0.1 m/s: q = 0.1 t + t^2,
    // which RK4 integrates exactly.
    const Run r = run_cli(dir, "simulate '" + kEmps + "' -o '" + dir.file("out") +
                                   "' --gravity 2,0,0 --set 40:-:41.qd=0.1 --stop-time 0.5 --output-step 0.05");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("trajectory.csv") != std::string::npos);
    const Csv c = read_csv(dir.file("out/trajectory.csv"));
    REQUIRE(c.columns.size() == 3);
    CHECK(c.columns[1] == "BED--CARRIAGE.q");
    CHECK(c.columns[2] == "BED--CARRIAGE.qd");
    REQUIRE(c.rows.size() == 11);
    for (const auto& row : c.rows) {
        const double t = row[0];
        CHECK(row[1] == mbx_test::relative_to(0.1 * t + t * t, 1.1, 1e-12));  // on the scale of q(1 s)
        CHECK(row[2] == mbx_test::relative(0.1 + 2 * t, 1e-12));
    }
    const std::string json = atest::read_file(dir.file("out/simulation.json"));
    CHECK(json.find("\"steps\": 500") != std::string::npos);
    CHECK(json.find("\"gravity\"") != std::string::npos);
}

TEST_CASE("cli simulate: a set coordinate of the four-bar moves the others, and every loop stays closed") {
    atest::TempDir dir("mbx_cli_simulate");
    const Run r = run_cli(dir, "simulate fourbar -o '" + dir.file("out") + "' --set rev_A.q=0.3 --stop-time 0.3");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const Csv c = read_csv(dir.file("out/trajectory.csv"));
    const int a = c.column("rev_A.q"), b = c.column("rev_B.q");
    REQUIRE(a > 0);
    REQUIRE(b > 0);
    CHECK(c.rows[0][size_t(a)] == mbx_test::relative(0.3, 1e-12));
    CHECK(std::fabs(c.rows[0][size_t(b)]) > 0.01);  // solved for, not left at the CAD pose
    const std::string json = atest::read_file(dir.file("out/simulation.json"));
    const size_t at = json.find("\"max_loop_closure_residual\": ");
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(json.substr(at + 29)) < 1e-9);
}

TEST_CASE("cli simulate --progress: a long run shows its fraction, simulated seconds per second and the time left") {
    atest::TempDir dir("mbx_cli_progress");
    const std::string out = dir.file("out");
    // A run of about two seconds of wall time in this build, whatever its speed.
    const Run probe = run_cli(dir, "simulate fourbar --set rev_A.qd=2 --step 1e-4 --stop-time 1 -o '" + out + "'");
    REQUIRE(probe.code == 0);
    const mbx::JsonValue json = mbx::parse_json(atest::read_file(out + "/simulation.json"));
    const mbx::JsonValue* wall_time = json.find("wall_time");
    REQUIRE(wall_time);
    const double wall = wall_time->number;
    REQUIRE(wall > 0);
    const double stop = std::max(2.0, std::round(2.2 / wall));
    const Run r = run_cli(dir, "simulate fourbar --set rev_A.qd=2 --step 1e-4 --stop-time " + std::to_string(int(stop)) +
                                   " -o '" + out + "' --progress");
    REQUIRE(r.code == 0);
    MESSAGE(r.err);
    std::vector<std::string> lines;
    std::istringstream in(r.err);
    for (std::string line; std::getline(in, line);)
        if (line.rfind("mbx: simulating", 0) == 0) lines.push_back(line);
    REQUIRE(lines.size() >= 3);
    CHECK(lines.front() == "mbx: simulating 0.0%");
    CHECK(lines.back().rfind("mbx: simulating 100.0%", 0) == 0);
    CHECK(lines.back().find("took") != std::string::npos);
    // A line a second in between, each with the run's own figures: the
    // fraction, the simulated time it stands for, a rate and what is left.
    double last_percent = 0;
    for (size_t k = 1; k + 1 < lines.size(); ++k) {
        CAPTURE(lines[k]);
        double percent = 0, simulated = 0, of = 0, rate = 0;
        REQUIRE(std::sscanf(lines[k].c_str(), "mbx: simulating %lf%%, %lf of %lf s simulated, %lf s simulated per second",
                            &percent, &simulated, &of, &rate) == 4);
        CHECK(percent > last_percent);
        CHECK(percent < 100);
        CHECK(of == stop);
        CHECK(simulated == mbx_test::relative(percent / 100 * stop, 0.01));
        CHECK(rate > 0);
        CHECK(lines[k].find(" left") != std::string::npos);
        last_percent = percent;
    }
}

// A 1e9 s simulation under an address-space limit of 64 MiB above what the
// CLI needs to start (issue 28; its samples once grew in memory, and the
// accurate mode's sample times took 8 GB before the first step): a fixed-step
// run keeps going within it until it is killed, never out of memory; the
// accurate mode's trajectory that no disk could hold is refused by its size
// before the run, with the free space named. (Release only: AddressSanitizer
// cannot run under an address-space limit.)
TEST_CASE("cli simulate: a 1e9 s run under an address-space limit runs within it or is refused by its size") {
    if (kSlowBuild) MBX_SKIP("AddressSanitizer cannot run under an address-space limit (and the debug build's needs differ)");
    atest::TempDir dir("mbx_cli_simulate_rlimit");
    const long floor = atest::least_cli_address_space(dir);
    REQUIRE(floor > 0);
    const long limit = floor + 64 * 1024;
    const std::string out = dir.file("out");
    const Run running = atest::run_cli_under(dir, limit, "simulate fourbar --set rev_A.qd=2 --stop-time 1e9 --step 1e-2 "
                                                         "--output-step 1e5 -o '" + out + "' --progress", 3);
    INFO(running.err);
    CHECK(running.code == 124);  // still running when timeout stopped it
    CHECK(running.err.find("mbx: simulating") != std::string::npos);
    CHECK(running.err.find("memory") == std::string::npos);
    CHECK(!std::filesystem::exists(out + "/trajectory.csv"));
    const Run refused = atest::run_cli_under(dir, limit, "simulate fourbar --stop-time 1e9 --integrator accurate -o '" + out + "'");
    CHECK(refused.code == 1);
    CHECK(refused.err.find("GiB free: raise the output step") != std::string::npos);
}

TEST_CASE("cli simulate: refusals exit non-zero, say why and write nothing") {
    atest::TempDir dir("mbx_cli_simulate");
    const std::string out = dir.file("out");
    struct Case {
        std::string args;
        int code;
        std::string says;
    };
    const std::vector<Case> cases = {
        {"fourbar -o '" + out + "' --set nothing.q=1", 1, "no joint 'nothing'"},
        {"fourbar -o '" + out + "' --set rev_A=1", 2, "--set takes"},
        {"fourbar -o '" + out + "' --set rev_A.q=abc", 2, "--set takes"},
        {"fourbar -o '" + out + "' --integrator magic", 2, "--integrator takes"},
        {"fourbar -o '" + out + "' --gravity 1,2", 2, "--gravity takes"},
        {"fourbar -o '" + out + "' --gravity 0,0,-9.81,1", 2, "--gravity takes"},
        {"fourbar -o '" + out + "' --gravity 0,0,-9.81,junk", 2, "--gravity takes"},
        {"fourbar -o '" + out + "' --gravity 0,0,-9.81junk", 2, "--gravity takes"},
        {"fourbar -o '" + out + "' --step -1", 2, "--step needs a positive number"},
        {"fourbar -o '" + out + "' --stop-time 1 --step 0.003 --output-step 0.01", 1, "whole number of steps"},
        // Counts that would wrap or outgrow memory, refused before the run (they took 0 steps and
        // succeeded, or grew to 8 GB before the first step).
        {"fourbar -o '" + out + "' --stop-time 1e17", 1, "the run would take 1e+19 output samples"},
        {"fourbar -o '" + out + "' --stop-time 1e9 --integrator accurate", 1, "GiB free: raise the output step"},
        {"fourbar -o '" + out + "' --stop-time 1 --output-step 1e9", 1, "longer than the run"},
        {"fourbar -o '" + out + "' --stop-time 1000 --step 1e-12 --output-step 1", 1, "the run would take 1e+15 steps"},
        {"fourbar -o '" + out + "' --set rev_A.q=0.3 --set rev_B.q=0.3 --set rev_C.q=-1.5", 1, "loop"},
        {"fourbar -o '" + out + "' --set rev_A.q=nan", 2, "--set takes"},
        {"no_such_builtin -o '" + out + "'", 1, "no built-in assembly"},
        {"fourbar", 2, "usage: mbx simulate"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.args);
        const Run r = run_cli(dir, "simulate " + c.args);
        CHECK(r.code == c.code);
        CHECK(r.err.find(c.says) != std::string::npos);
        CHECK(!std::filesystem::exists(out + "/trajectory.csv"));
        CHECK(!std::filesystem::exists(out + "/simulation.json"));
    }
}

TEST_CASE("cli: joint dynamics of a description file reach the report, the MJCF export and the simulation") {
    atest::TempDir dir("mbx_cli_joint_dynamics");
    atest::write_file(dir.file("dyn.xml"), R"(<mechatronics version="1">
  <joint constraint="fourbar/rev_A" damping="0.25" coulomb="0.05" stiffness="2" rest="0.1" armature="0.003"/>
</mechatronics>
)");
    const Run t = run_cli(dir, "translate fourbar --drives '" + dir.file("dyn.xml") + "' --format mjcf -o '" +
                                   dir.file("out") + "'");
    INFO(t.err);
    REQUIRE(t.code == 0);
    const std::string report = atest::read_file(dir.file("out/report.json"));
    CHECK(report.find("\"joint_dynamics\"") != std::string::npos);
    CHECK(report.find("\"damping\": 0.25") != std::string::npos);
    CHECK(atest::read_file(dir.file("out/report.txt")).find("Joint dynamics (1)") != std::string::npos);
    const std::string mjcf = atest::read_file(dir.file("out/mjcf/fourbar.xml"));
    CHECK(mjcf.find("damping=\"0.25\"") != std::string::npos);
    CHECK(mjcf.find("frictionloss=\"0.05\"") != std::string::npos);

    // In the simulation the spring pulls the crank towards its rest angle:
    // released at the CAD pose (0) with gravity off, it starts moving towards +0.1.
    const Run s = run_cli(dir, "simulate fourbar --drives '" + dir.file("dyn.xml") + "' --gravity 0,0,0 --stop-time 0.05 -o '" +
                                   dir.file("sim") + "'");
    INFO(s.err);
    REQUIRE(s.code == 0);
    const Csv c = read_csv(dir.file("sim/trajectory.csv"));
    const int a = c.column("rev_A.q");
    REQUIRE(a > 0);
    CHECK(c.rows.back()[size_t(a)] > 1e-5);
}
}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("cli simulate and view: the four-bar's Simscape twin simulates as its PMXML sample does, and views with its STEP shapes") {
    atest::TempDir dir("mbx_cli_simscape");
    const std::string samples = std::string(MBX_SAMPLES_DIR) + "/fourbar_imperial/";
    // The crank turned by 0.3 rad from the exported pose, released under gravity along the links' plane.
    const std::string options = " --gravity 0,-9.81,0 --stop-time 0.4 --output-step 0.05";
    const Run twin = run_cli(dir, "simulate '" + samples + "simscape/fourbar.xml' -o '" + dir.file("twin") +
                                      "' --set GROUND_LINK--CRANK.q=0.3" + options);
    INFO(twin.err);
    REQUIRE(twin.code == 0);
    const Run pmxml = run_cli(dir, "simulate '" + samples + "fourbar.xml' --shapes '" + samples + "fourbar_a.wrl' -o '" +
                                       dir.file("pmxml") + "' --set 40:-:41.q=0.3" + options);
    INFO(pmxml.err);
    REQUIRE(pmxml.code == 0);
    const Csv a = read_csv(dir.file("twin/trajectory.csv")), b = read_csv(dir.file("pmxml/trajectory.csv"));
    REQUIRE(a.columns.size() == b.columns.size());
    REQUIRE(a.rows.size() == b.rows.size());
    REQUIRE(a.rows.size() == 9);
    // The crank's angle moved (gravity acts) and the two runs agree to the PMXML's six digits.
    const int crank = a.column("GROUND_LINK--CRANK.q");
    REQUIRE(crank > 0);
    CHECK(std::fabs(a.rows.back()[size_t(crank)] - 0.3) > 0.01);
    for (size_t r = 0; r < a.rows.size(); ++r)
        for (size_t k = 0; k < a.columns.size(); ++k) {
            CAPTURE(a.columns[k]);
            CHECK(a.rows[r][k] == mbx_test::within(b.rows[r][k], 1e-4 * (1 + std::fabs(b.rows[r][k])), "six digits"));
        }
    const std::string json = atest::read_file(dir.file("twin/simulation.json"));
    const size_t at = json.find("\"max_loop_closure_residual\": ");
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(json.substr(at + 29)) < 1e-9);

    // The view of the twin along that trajectory draws the parts' STEP meshes.
    const Run view = run_cli(dir, "view '" + samples + "simscape/fourbar.xml' -o '" + dir.file("view") +
                                      "' --trajectory '" + dir.file("twin/trajectory.csv") + "'");
    INFO(view.err);
    REQUIRE(view.code == 0);
    CHECK(atest::read_file(dir.file("view/view.html")).size() > 10000);
    // The same file without its STEP parts beside it has nothing to draw: the meshes were the STEP files'.
    atest::write_file(dir.file("bare.xml"), atest::read_file(samples + "simscape/fourbar.xml"));
    const Run bare = run_cli(dir, "view '" + dir.file("bare.xml") + "' -o '" + dir.file("bare_view") + "' --still");
    CHECK(bare.code != 0);
    CHECK(bare.err.find("no body of the model has a mesh") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("bare_view/view.html")));
}

}  // namespace MBX_UNITY_ID
