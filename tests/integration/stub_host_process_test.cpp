// mbx_stub_host run as a separate process, as a CAD system would run the
// plugin: success writes both report files; a host failing midway exits
// non-zero with the SDK's message on stderr and leaves no report behind.
#include <doctest/doctest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/temp_dir.h"
#include "../common/file_text.h"

namespace MBX_UNITY_ID {

namespace fs = std::filesystem;

namespace {

struct Result {
    int exit_code = -1;
    std::string out, err;
};

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

Result run_stub_host(const itest::TempDir& scratch, const std::vector<std::string>& args) {
    std::string command = quoted(MBX_STUB_HOST_PATH) + " --plugin " + quoted(MBX_PLUGIN_PATH);
    for (const std::string& a : args) command += " " + quoted(a);
    const fs::path out = scratch.path / "stdout.txt", err = scratch.path / "stderr.txt";
    command += " >" + quoted(out.string()) + " 2>" + quoted(err.string());
    const int status = std::system(command.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = mbx_test::read_file(out);
    r.err = mbx_test::read_file(err);
    return r;
}

bool has_report_files(const fs::path& dir) {
    if (!fs::exists(dir)) return false;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().find("report") != std::string::npos) return true;
    return false;
}

}  // namespace

TEST_CASE("stub host process: a translation writes the summary and both report files") {
    itest::TempDir s("mbx_stub_host_test");
    const fs::path dir = s.path / "fourbar";
    const Result r = run_stub_host(s, {"--assembly", "fourbar", "-o", dir.string()});
    INFO("stdout:\n" << r.out << "stderr:\n" << r.err);
    CHECK(r.exit_code == 0);
    CHECK(r.out.find("dof: 1") != std::string::npos);
    CHECK(fs::is_regular_file(dir / "report.json"));
    CHECK(fs::is_regular_file(dir / "report.txt"));
}

TEST_CASE("stub host process: a version-1 host prints the same summary") {
    itest::TempDir s("mbx_stub_host_test");
    const Result v2 = run_stub_host(s, {"--assembly", "double_cardan", "-o", (s.path / "v2").string()});
    const Result v1 = run_stub_host(s, {"--assembly", "double_cardan", "-o", (s.path / "v1").string(), "--v1-host"});
    CHECK(v2.exit_code == 0);
    CHECK(v1.exit_code == 0);
    auto summary_lines = [](const std::string& out) {
        // Everything from "parts:" up to the report line; the header lines differ by design.
        const size_t begin = out.find("parts:"), end = out.find("report:");
        return begin == std::string::npos || end == std::string::npos ? std::string() : out.substr(begin, end - begin);
    };
    CHECK(!summary_lines(v2.out).empty());
    CHECK(summary_lines(v1.out) == summary_lines(v2.out));
}

TEST_CASE("stub host process: a host failing midway exits non-zero and leaves no report") {
    itest::TempDir s("mbx_stub_host_test");
    const fs::path dir = s.path / "failed";
    // Body 4 of six_axis_arm is link2_elbow, the third part of link 2.
    const Result r = run_stub_host(s, {"--assembly", "six_axis_arm", "-o", dir.string(), "--fail-at-body", "4"});
    INFO("stdout:\n" << r.out << "stderr:\n" << r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("MBX_ERROR_HOST_CALLBACK") != std::string::npos);
    CHECK(r.err.find("six_axis_arm/link2_elbow") != std::string::npos);
    CHECK_FALSE(has_report_files(dir));
}

TEST_CASE("stub host process: NaN from the host exits non-zero naming the body") {
    itest::TempDir s("mbx_stub_host_test");
    const fs::path dir = s.path / "nan";
    const Result r = run_stub_host(s, {"--assembly", "fourbar", "-o", dir.string(), "--nan-at-body", "3"});
    INFO("stdout:\n" << r.out << "stderr:\n" << r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("MBX_ERROR_INVALID_INPUT") != std::string::npos);
    CHECK(r.err.find("fourbar/crank") != std::string::npos);
    CHECK_FALSE(has_report_files(dir));
}

TEST_CASE("stub host process: bad usage and a missing plugin exit with status 2") {
    itest::TempDir s("mbx_stub_host_test");
    CHECK(run_stub_host(s, {"--assembly", "no_such_thing", "-o", (s.path / "x").string()}).exit_code == 2);
    CHECK(run_stub_host(s, {"--bogus"}).exit_code == 2);
    const std::string command = quoted(MBX_STUB_HOST_PATH) + " --plugin /nonexistent/libmbx.so --assembly fourbar -o " +
                                quoted((s.path / "y").string()) + " >/dev/null 2>&1";
    const int status = std::system(command.c_str());
    CHECK((WIFEXITED(status) && WEXITSTATUS(status) == 2));
}
}  // namespace MBX_UNITY_ID
