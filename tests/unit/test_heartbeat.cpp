// The heartbeat long runs report through (core/heartbeat.h): the callback
// comes by wall time whatever the loop's pace, shares of a run map their
// fractions onto the whole, and a cancel is sticky (every later beat, on any
// thread of the run, throws it; code that cannot throw asks cancelled()).
#include <doctest/doctest.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/finding.h"
#include "core/heartbeat.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using Clock = std::chrono::steady_clock;

TEST_CASE("heartbeat: the callback comes by wall time, not per item") {
    std::vector<double> at;
    const Clock::time_point start = Clock::now();
    auto since = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    Heartbeat h([&](const char*, double) { return at.push_back(since()), true; }, "the test", std::chrono::milliseconds(10));
    const HeartbeatScope scope(&h);
    long items = 0;
    while (since() < 0.2) heartbeat(), ++items;  // millions of items, about 20 calls
    MESSAGE(items << " items, " << at.size() << " calls, longest gap " << 1e3 * h.longest_gap() << " ms");
    CHECK(at.size() >= 15);
    CHECK(at.size() <= 22);
    CHECK(h.longest_gap() < 0.015);
    CHECK(items > 1000 * long(at.size()));

    // Slow items: each beat past the interval reports.
    at.clear();
    for (int k = 0; k < 5; ++k) {
        std::this_thread::sleep_for(std::chrono::milliseconds(12));
        heartbeat();
    }
    CHECK(at.size() == 5);
}

TEST_CASE("heartbeat: shares map a part's fractions onto the stage, nested, and a part without one moves nothing") {
    std::vector<double> fractions;
    std::vector<std::string> stages;
    Heartbeat h(
        [&](const char* s, double f) {
            stages.push_back(s);
            fractions.push_back(f);
            return true;
        },
        "the test", std::chrono::milliseconds(0));
    const HeartbeatScope scope(&h);
    heartbeat("replay", 0.2);
    {
        const HeartbeatShare record(0.2, 0.4);
        heartbeat(0.5);  // half of the record: 0.3 of the stage
        {
            const HeartbeatShare window(0.5, 1.0);  // the record's second half: 0.3 - 0.4
            heartbeat(0.5);
            heartbeat(2.0);  // clamped to the part's end
        }
        heartbeat(1.0);
    }
    heartbeat(0.9);  // no share: an item done, the stage's fraction stands
    heartbeat("identify", 0.25);
    const std::vector<double> expected{0.2, 0.3, 0.35, 0.4, 0.4, 0.4, 0.25};
    REQUIRE(fractions.size() == expected.size());
    for (size_t k = 0; k < expected.size(); ++k) {
        CAPTURE(k);
        CHECK(fractions[k] == mbx_test::relative(expected[k], 1e-12));
    }
    CHECK(stages.front() == "replay");
    CHECK(stages.back() == "identify");
}

TEST_CASE("heartbeat: a cancel is thrown at once, again at every later beat, and on the run's other threads") {
    int calls = 0;
    Heartbeat h([&](const char*, double) { return ++calls < 3; }, "the simulation", std::chrono::milliseconds(0));
    const HeartbeatScope scope(&h);
    h.stage("simulating", 0);
    h.beat(0.1);
    CHECK(!h.cancelled());
    try {
        h.beat(0.25);
        FAIL("no cancel");
    } catch (const Error& e) {
        CHECK(e.status() == MBX_ERROR_CANCELLED);
        CHECK(std::string(e.what()) == "the simulation was cancelled during 'simulating' at 25.0 %");
    }
    CHECK(h.cancelled());
    // Sticky: a loop that swallowed the error meets it again at its next beat,
    // without asking the host a second time.
    CHECK_THROWS_AS(heartbeat(), Error);
    CHECK_THROWS_AS(h.throw_if_cancelled(), Error);
    CHECK(calls == 3);
    // A worker of the run learns of it at its next beat.
    std::string worker_saw;
    std::thread worker([&] {
        const HeartbeatScope beating(&h);
        try {
            heartbeat();
        } catch (const Error& e) {
            worker_saw = e.what();
        }
    });
    worker.join();
    CHECK(worker_saw.find("cancelled during 'simulating'") != std::string::npos);
}

TEST_CASE("heartbeat: workers' beats never call the host, and a loop outside any run beats into nothing") {
    int calls = 0;
    Heartbeat h([&](const char*, double) { return ++calls, true; }, "the test", std::chrono::milliseconds(0));
    std::thread worker([&] {
        const HeartbeatScope beating(&h);
        for (int k = 0; k < 1000; ++k) heartbeat(0.5);
    });
    worker.join();
    CHECK(calls == 0);
    CHECK(current_heartbeat() == nullptr);
    heartbeat();
    heartbeat(0.5);
    heartbeat("stage", 0.5);  // no run: nothing to report to, nothing thrown
    {
        const HeartbeatScope scope(&h);
        CHECK(current_heartbeat() == &h);
        {
            const HeartbeatScope none(nullptr);
            heartbeat();
            CHECK(calls == 0);
        }
        heartbeat();
        CHECK(calls == 1);
    }
    CHECK(current_heartbeat() == nullptr);
}

}  // namespace MBX_UNITY_ID
