// The body of every test executable's main.cpp: doctest's runner, and exit
// code 77 (ctest's SKIP_RETURN_CODE, set on every discovered test) when a test
// case skipped (skip.h) and nothing failed.
#pragma once

#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>
#include <string>

#include "tests/common/skip.h"

namespace mbx_test {

// Whether the exception that ended the current case was a SkipTest.
inline bool& skip_thrown() {
    static bool thrown = false;
    return thrown;
}

// Counts the cases that failed for a reason other than a SkipTest: a case
// whose only "failure" is the skip it threw is a skip, nothing more.
struct SkipListener : doctest::IReporter {
    static int& real_failures() {
        static int n = 0;
        return n;
    }
    explicit SkipListener(const doctest::ContextOptions&) {}
    void report_query(const doctest::QueryData&) override {}
    void test_run_start() override {}
    void test_run_end(const doctest::TestRunStats&) override {}
    static int& started() {
        static int n = 0;
        return n;
    }
    void test_case_start(const doctest::TestCaseData&) override {
        skip_thrown() = false;
        ++started();
    }
    void test_case_reenter(const doctest::TestCaseData&) override {}
    void test_case_end(const doctest::CurrentTestCaseStats& stats) override {
        if (!stats.testCaseSuccess && !(skip_thrown() && stats.numAssertsFailedCurrentTest == 0)) ++real_failures();
        skip_thrown() = false;
    }
    void test_case_exception(const doctest::TestCaseException&) override {}
    void subcase_start(const doctest::SubcaseSignature&) override {}
    void subcase_end() override {}
    void log_assert(const doctest::AssertData&) override {}
    void log_message(const doctest::MessageData&) override {}
    void test_case_skipped(const doctest::TestCaseData&) override {}
};

}  // namespace mbx_test

DOCTEST_REGISTER_LISTENER("mbx_skips", 1, mbx_test::SkipListener);

DOCTEST_REGISTER_EXCEPTION_TRANSLATOR(const mbx_test::SkipTest& skip) {
    mbx_test::record_skip(skip.reason);
    mbx_test::skip_thrown() = true;
    return doctest::String(("skipped: " + skip.reason).c_str());
}

int main(int argc, char** argv) {
    doctest::Context context(argc, argv);
    const int status = context.run();
    if (context.shouldExit()) return status;
    // A filter that matches no case ran nothing: that is not a pass.
    bool filtered = false;
    for (int k = 1; k < argc; ++k)
        filtered = filtered || std::string(argv[k]).rfind("--test-case=", 0) == 0 || std::string(argv[k]).rfind("-tc=", 0) == 0;
    if (filtered && mbx_test::SkipListener::started() == 0) {
        std::fprintf(stderr, "no test case matches the filter: nothing ran\n");
        return 3;
    }
    if (mbx_test::SkipListener::real_failures() == 0 && !mbx_test::skip_reasons().empty()) return 77;
    return status;
}
