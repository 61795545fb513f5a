// Long runs (issue 28): a run of 1e9 simulated seconds reports progress at
// least every 100 ms of wall time in each integrator and stops within 100 ms
// of a cancel, leaving no file; a run's trajectory streams to disk, so its
// memory does not grow with its samples; a run whose trajectory would not
// fit the folder's disk is refused before its first step.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "sim/build_model.h"
#include "sim/simulation.h"
#include "temp_dir.h"
#include "tests/export/test_inputs.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

namespace a = xtest::mjcf_assemblies;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// kB of a /proc/self/status line ("VmHWM:", "VmRSS:").
long status_kb(const std::string& key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key, 0) == 0) return std::stol(line.substr(key.size()));
    return -1;
}

size_t entries(const std::filesystem::path& dir) {
    size_t n = 0;
    for (auto it = std::filesystem::directory_iterator(dir); it != std::filesystem::directory_iterator(); ++it) ++n;
    return n;
}

}  // namespace

TEST_CASE("sim: a 1e9 s run reports every 100 ms and a cancel stops it within 100 ms, with no file left") {
    auto t = xtest::translate(a::double_pendulum());
    const sim::Model m = sim::build_model(*t->mechanism);
    for (sim::IntegratorKind kind : {sim::IntegratorKind::RK4, sim::IntegratorKind::Euler, sim::IntegratorKind::Accurate}) {
        const std::string integrator = sim::integrator_name(kind);
        CAPTURE(integrator);
        mbx_test::TempDir dir("mbx_long_run");
        sim::Data d(m);
        sim::initial_state(m, d, {{0, 0, false, 1.0}});
        sim::RunSettings rs;
        rs.integrator.kind = kind;
        rs.integrator.step = kind == sim::IntegratorKind::Accurate ? 0 : 1e-3;
        rs.stop_time = 1e9;
        // One sample every 1e6 s: before the first, a stride per output sample
        // said nothing for hours.
        rs.output_step = 1e6;
        const Clock::time_point start = Clock::now();
        double last_call = 0, largest_gap = 0, cancelled_at = -1, last_fraction = -1;
        int calls = 0;
        bool fractions_rise = true;
        rs.progress = [&](double fraction) {
            const double now = seconds_since(start);
            largest_gap = std::max(largest_gap, now - last_call);
            last_call = now;
            ++calls;
            fractions_rise = fractions_rise && fraction >= last_fraction && fraction < 1e-3;
            last_fraction = fraction;
            if (now < 0.5) return true;
            cancelled_at = now;
            return false;
        };
        bool threw = false;
        try {
            sim::RunFiles files(dir.path.string());
            sim::run(m, d, rs, files);
        } catch (const Error& e) {
            threw = true;
            CHECK(e.status() == MBX_ERROR_CANCELLED);
            CHECK(std::string(e.what()).find("cancelled") != std::string::npos);
        }
        const double stopped = seconds_since(start);
        REQUIRE(threw);
        MESSAGE(integrator << ": " << calls << " progress calls, largest gap " << 1e3 * largest_gap
                                           << " ms, stopped " << 1e3 * (stopped - cancelled_at) << " ms after the cancel");
        CHECK(calls >= 5);
        CHECK(largest_gap <= 0.1);
        CHECK(stopped - cancelled_at <= 0.1);
        CHECK(fractions_rise);
        CHECK(last_fraction > 0);  // real fractions, not 0 until the first of 1000 samples
        // Nothing of the cancelled run: no trajectory, no temporary.
        CHECK(entries(dir.path) == 0);
    }
}

TEST_CASE("sim: a run's samples stream to its file, so a million-sample run's memory stays flat") {
    auto t = xtest::translate(a::double_pendulum());
    const sim::Model m = sim::build_model(*t->mechanism);
    mbx_test::TempDir dir("mbx_stream_run");
    sim::Data d(m);
    sim::initial_state(m, d, {{0, 0, false, 1.0}});
    sim::RunSettings rs;
    rs.integrator.kind = sim::IntegratorKind::Euler;
    rs.integrator.step = 1e-3;
    rs.output_step = 1e-3;
    rs.stop_time = 1000;
    // The peak resident size from here on (Linux resets VmHWM on "5").
    std::ofstream("/proc/self/clear_refs") << "5";
    const long rss_before = status_kb("VmRSS:");
    sim::RunFiles files(dir.path.string());
    const sim::RunSummary s = sim::run(m, d, rs, files);
    files.commit(m, s);
    const long peak = status_kb("VmHWM:");
    REQUIRE(rss_before > 0);
    REQUIRE(peak > 0);
    const auto csv_bytes = std::filesystem::file_size(dir.file("trajectory.csv"));
    MESSAGE("1e6 samples, " << csv_bytes / 1048576 << " MiB of CSV; resident peak grew by " << (peak - rss_before) / 1024
                            << " MiB");
    // Held in memory, the samples alone were 40 MB and their CSV text more than 60 MB.
    CHECK(peak - rss_before < 16 * 1024);
    CHECK(csv_bytes > 60u * 1000 * 1000);
    CHECK(s.samples == 1000001);

    std::ifstream in(dir.file("trajectory.csv"));
    std::string line, last;
    size_t lines = 0;
    while (std::getline(in, line)) ++lines, last.swap(line);
    CHECK(lines == 1000002);  // the header and every sample
    CHECK(last.rfind("1000,", 0) == 0);
    CHECK(entries(dir.path) == 2);  // trajectory.csv and simulation.json, no temporary
}

TEST_CASE("sim: a run whose trajectory cannot fit the folder's disk is refused before its first step") {
    auto t = xtest::translate(a::double_pendulum());
    const sim::Model m = sim::build_model(*t->mechanism);
    mbx_test::TempDir dir("mbx_huge_run");
    sim::Data d(m);
    sim::initial_state(m, d, {});
    sim::RunSettings rs;
    rs.integrator.kind = sim::IntegratorKind::Accurate;
    rs.integrator.step = 0;
    rs.stop_time = 1e9;
    rs.output_step = 1e-3;  // 1e12 samples: some hundred terabytes of CSV
    const Clock::time_point start = Clock::now();
    try {
        sim::RunFiles files(dir.path.string());
        sim::run(m, d, rs, files);
        FAIL("the run was not refused");
    } catch (const Error& e) {
        const std::string what = e.what();
        MESSAGE(what);
        CHECK(e.status() == MBX_ERROR_INVALID_ARGUMENT);
        CHECK(what.find("1e+12 samples") != std::string::npos);
        CHECK(what.find("GiB free") != std::string::npos);
    }
    CHECK(seconds_since(start) < 1);
    CHECK(d.time == 0);
    CHECK(entries(dir.path) == 0);

    // Held in memory, the limit is the trajectory limit.
    sim::Trajectory held;
    try {
        sim::run(m, d, rs, held);
        FAIL("the run was not refused");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("in memory and the limit is 4 GiB") != std::string::npos);
    }
    CHECK(held.values.empty());
}

}  // namespace MBX_UNITY_ID
