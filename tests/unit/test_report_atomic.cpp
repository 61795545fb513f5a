// Atomic file writing: failures are clean, successes replace entirely.
#include <doctest/doctest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "core/finding.h"
#include "core/report/atomic_file.h"
#include "../common/file_text.h"

namespace MBX_UNITY_ID {

namespace fs = std::filesystem;

namespace {

// A fresh directory per test case, removed afterwards (permissions restored
// first, so a failed read-only test cannot leave debris behind).
struct Scratch {
    fs::path dir;
    explicit Scratch(const char* name) {
        dir = fs::temp_directory_path() / ("mbx_atomic_" + std::to_string(::getpid()) + "_" + name);
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~Scratch() {
        std::error_code ec;
        fs::permissions(dir, fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(dir, ec);
    }
};

void spit(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

std::size_t temporaries_in(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        n += e.path().filename().string().find(".tmp.") != std::string::npos;
    return n;
}

// Runs `write` expecting an I/O error about `path`; returns its message.
template <class F>
std::string expect_io_error(F write, const std::string& path) {
    try {
        write();
    } catch (const mbx::Error& e) {
        CHECK(e.status() == MBX_ERROR_IO);
        CHECK(e.subject().kind == MBX_SUBJECT_FILE);
        CHECK(e.subject().id == path);
        return e.what();
    }
    FAIL("no mbx::Error thrown");
    return {};
}

// Makes `dir` nobody's, then in a child that runs as nobody turns it
// read-only and writes `target`; returns the mbx::Error's message the child
// got ("" when the write succeeded or the error was another kind).
std::string message_of_unprivileged_write(const fs::path& dir, const fs::path& target) {
    constexpr uid_t kNobody = 65534;
    REQUIRE(::chown(dir.c_str(), kNobody, kNobody) == 0);
    REQUIRE(::chown(target.c_str(), kNobody, kNobody) == 0);
    int out[2];
    REQUIRE(::pipe(out) == 0);
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        ::close(out[0]);
        std::string message;
        if (::setgid(kNobody) == 0 && ::setuid(kNobody) == 0 && ::chmod(dir.c_str(), 0500) == 0) {
            try {
                mbx::write_file_atomically(target.string(), "new");
            } catch (const mbx::Error& e) {
                if (e.status() == MBX_ERROR_IO) message = e.what();
            }
        }
        const ssize_t written = ::write(out[1], message.data(), message.size());
        ::_exit(written == ssize_t(message.size()) ? 0 : 1);
    }
    ::close(out[1]);
    std::string message;
    char buffer[512];
    for (ssize_t n; (n = ::read(out[0], buffer, sizeof buffer)) > 0;) message.append(buffer, size_t(n));
    ::close(out[0]);
    int status = 0;
    ::waitpid(child, &status, 0);
    CHECK(WIFEXITED(status));
    return message;
}

}  // namespace

TEST_CASE("atomic: creates missing directories and writes the contents") {
    Scratch s("create");
    const fs::path target = s.dir / "a" / "b" / "file.txt";
    mbx::write_file_atomically(target.string(), std::string("hello\0world", 11));
    CHECK(mbx_test::read_file(target) == std::string("hello\0world", 11));
    CHECK(temporaries_in(s.dir) == 0);
}

TEST_CASE("atomic: an existing file is replaced entirely") {
    Scratch s("replace");
    const fs::path target = s.dir / "report.json";
    spit(target, std::string(10000, 'o'));
    mbx::write_file_atomically(target.string(), "short");
    CHECK(mbx_test::read_file(target) == "short");
    mbx::write_file_atomically(target.string(), "");
    CHECK(mbx_test::read_file(target).empty());
    CHECK(temporaries_in(s.dir) == 0);
}

TEST_CASE("atomic: a parent that is a file fails with MBX_ERROR_IO and leaves nothing") {
    Scratch s("parent_file");
    spit(s.dir / "blocker", "I am a file");
    const std::string target = (s.dir / "blocker" / "out" / "report.json").string();
    const std::string message =
        expect_io_error([&] { mbx::write_file_atomically(target, "data"); }, target);
    CAPTURE(message);
    CHECK(message.find("blocker") != std::string::npos);
    CHECK(message.find("Not a directory") != std::string::npos);
    CHECK(mbx_test::read_file(s.dir / "blocker") == "I am a file");
    CHECK(temporaries_in(s.dir) == 0);
}

TEST_CASE("atomic: a target that is a directory fails and removes the temporary") {
    Scratch s("target_dir");
    fs::create_directories(s.dir / "report.txt");
    const std::string target = (s.dir / "report.txt").string();
    const std::string message = expect_io_error([&] { mbx::write_file_atomically(target, "data"); }, target);
    CAPTURE(message);
    CHECK(message.find("Is a directory") != std::string::npos);
    CHECK(fs::is_directory(target));
    CHECK(temporaries_in(s.dir) == 0);
}

TEST_CASE("atomic: a read-only directory fails cleanly") {
    Scratch s("read_only");
    const fs::path target = s.dir / "report.json";
    spit(target, "old");
    std::string message;
    if (::geteuid() != 0) {
        REQUIRE(::chmod(s.dir.c_str(), 0500) == 0);
        message = expect_io_error([&] { mbx::write_file_atomically(target.string(), "new"); }, target.string());
    } else {
        // Root ignores directory permissions (and CI runs as root): the write
        // is tried by a child that gave root up for nobody's user.
        message = message_of_unprivileged_write(s.dir, target);
    }
    CAPTURE(message);
    CHECK(message.find("Permission denied") != std::string::npos);
    CHECK(message.find(target.string()) != std::string::npos);
    REQUIRE(::chmod(s.dir.c_str(), 0700) == 0);
    CHECK(mbx_test::read_file(target) == "old");
    CHECK(temporaries_in(s.dir) == 0);
}

TEST_CASE("atomic: write_files_atomically replaces a pair together") {
    Scratch s("pair_ok");
    const std::string json = (s.dir / "report.json").string();
    const std::string text = (s.dir / "report.txt").string();
    spit(json, "old json");
    spit(text, "old text");
    mbx::write_files_atomically({{json, "new json"}, {text, "new text"}});
    CHECK(mbx_test::read_file(json) == "new json");
    CHECK(mbx_test::read_file(text) == "new text");
    CHECK(temporaries_in(s.dir) == 0);
}

TEST_CASE("atomic: write_files_atomically keeps the old pair when the second file fails") {
    Scratch s("pair_fail");
    const std::string json = (s.dir / "report.json").string();
    const std::string text = (s.dir / "report.txt").string();
    spit(json, "old json");
    fs::create_directories(text);  // the second rename will fail with EISDIR
    expect_io_error([&] { mbx::write_files_atomically({{json, "new json"}, {text, "new text"}}); }, text);
    CHECK(mbx_test::read_file(json) == "old json");
    CHECK(fs::is_directory(text));
    CHECK(temporaries_in(s.dir) == 0);

    // Same when the first target did not exist before: it must not appear.
    fs::remove(json);
    expect_io_error([&] { mbx::write_files_atomically({{json, "new json"}, {text, "new text"}}); }, text);
    CHECK_FALSE(fs::exists(json));
    CHECK(temporaries_in(s.dir) == 0);
}

TEST_CASE("atomic: write_files_atomically writes nothing when a temporary cannot be created") {
    Scratch s("pair_mkdir");
    spit(s.dir / "blocker", "file");
    const std::string json = (s.dir / "report.json").string();
    const std::string text = (s.dir / "blocker" / "report.txt").string();
    spit(json, "old json");
    expect_io_error([&] { mbx::write_files_atomically({{json, "new json"}, {text, "new text"}}); }, text);
    CHECK(mbx_test::read_file(json) == "old json");
    CHECK(temporaries_in(s.dir) == 0);
}

TEST_CASE("atomic: concurrent writers of one file never clash or leave debris") {
    Scratch s("concurrent");
    const std::string target = (s.dir / "report.json").string();
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            const std::string contents(1000 + static_cast<std::size_t>(t), static_cast<char>('a' + t));
            for (int i = 0; i < 25; ++i) mbx::write_file_atomically(target, contents);
        });
    for (std::thread& th : threads) th.join();
    const std::string result = mbx_test::read_file(target);
    REQUIRE_FALSE(result.empty());
    CHECK(result == std::string(result.size(), result[0]));  // one writer's contents, whole
    CHECK(result.size() == 1000 + static_cast<std::size_t>(result[0] - 'a'));
    CHECK(temporaries_in(s.dir) == 0);
}

// A run killed mid-write leaves its temporaries ("<file>.tmp.<pid>.<n>"); the
// next write into the folder removes those whose process is gone, and leaves
// a live writer's (another process's, this one's) and files that only look
// alike.
TEST_CASE("atomic: a dead writer's temporaries are removed by the next write into the folder, a live one's kept") {
    Scratch s("stale");
    // A pid that is gone: a child that has exited and been reaped.
    const pid_t dead = ::fork();
    if (dead == 0) ::_exit(0);
    REQUIRE(dead > 0);
    ::waitpid(dead, nullptr, 0);
    // A pid that lives: a child waiting to be told to stop.
    const pid_t alive = ::fork();
    if (alive == 0) {
        ::pause();
        ::_exit(0);
    }
    REQUIRE(alive > 0);
    const std::string d = std::to_string(long(dead)), a = std::to_string(long(alive)), self = std::to_string(long(::getpid()));
    const std::vector<std::string> stale = {"report.json.tmp." + d + ".0", "report.txt.tmp." + d + ".17",
                                            "other.stl.tmp." + d + ".3"};
    const std::vector<std::string> kept = {"report.json.tmp." + a + ".2", "report.json.tmp." + self + ".999",
                                           "notes.tmp.txt", "x.tmp.12ab.3", "y.tmp." + d + ".", "old.json"};
    for (const std::string& f : stale) spit(s.dir / f, "half");
    for (const std::string& f : kept) spit(s.dir / f, "mine");
    mbx::write_files_atomically({{(s.dir / "report.json").string(), "{}"}, {(s.dir / "report.txt").string(), "t"}});
    for (const std::string& f : stale) CHECK_MESSAGE(!fs::exists(s.dir / f), f);
    for (const std::string& f : kept) CHECK_MESSAGE(fs::exists(s.dir / f), f);
    CHECK(mbx_test::read_file(s.dir / "report.json") == "{}");
    ::kill(alive, SIGKILL);
    ::waitpid(alive, nullptr, 0);
}
}  // namespace MBX_UNITY_ID
