// Independent contexts may be used from different threads at once (mbx.h,
// THREAD SAFETY). Four threads, each with its own context and host, translate
// different builtins 20 times; every result must equal the single-threaded one.
#include <doctest/doctest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "support/fingerprint.h"
#include "support/plugin_fixture.h"

namespace MBX_UNITY_ID {

using namespace itest;

namespace {

// Assertion-free: doctest's REQUIRE would throw across the thread boundary.
std::string translate_once(const mbx_stub::Assembly& a, mbx_context* context) {
    mbx_stub::Host host(a);
    mbx_mechanism* m = nullptr;
    const mbx_status status = api().translate(context, host.table(), nullptr, &m);
    if (status != MBX_OK) return std::string("failed: ") + api().status_name(status);
    MechanismPtr owned(m);
    std::string print = fingerprint(m);
    api().mechanism_release_host(m);
    return print;
}

}  // namespace

TEST_CASE("threads: four contexts translating concurrently give the single-threaded results") {
    const std::vector<std::string> names = mbx_stub::builtin_names();
    REQUIRE(names.size() == 4);
    std::vector<mbx_stub::Assembly> assemblies;
    std::vector<std::string> expected;
    {
        ContextPtr context = make_context();
        for (const auto& name : names) {
            assemblies.push_back(builtin(name));
            expected.push_back(translate_once(assemblies.back(), context.get()));
            REQUIRE_MESSAGE(expected.back().rfind("failed", 0) != 0, name << ": " << expected.back());
        }
    }
    api();  // loaded before the threads start

    constexpr int kRounds = 20;
    std::atomic<int> mismatches{0};
    std::vector<std::string> first_difference(names.size());
    std::vector<std::thread> threads;
    for (size_t t = 0; t < names.size(); ++t) {
        threads.emplace_back([&, t] {
            try {
                ContextPtr context = make_context();
                for (int round = 0; round < kRounds; ++round) {
                    // Each thread also rotates through the others' assemblies,
                    // so the same inputs are in flight on several threads.
                    const size_t which = (t + size_t(round)) % names.size();
                    const std::string got = translate_once(assemblies[which], context.get());
                    if (got != expected[which]) {
                        if (mismatches++ == 0) first_difference[t] = names[which] + " round " + std::to_string(round);
                    }
                }
            } catch (...) {
                ++mismatches;
            }
        });
    }
    for (std::thread& th : threads) th.join();
    std::string where;
    for (const auto& w : first_difference) where += w;
    CHECK_MESSAGE(mismatches.load() == 0, "first difference: " << where);
}
}  // namespace MBX_UNITY_ID
