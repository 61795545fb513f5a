// Outside input read whole (core/input_file.h): a regular file is read as it
// is; a device, a pipe and a directory are refused without a byte read (a
// read of /dev/zero would run until memory ran out, a pipe's would wait for
// a writer forever); a file above the input limit is refused naming both
// sizes; the limit follows MBX_INPUT_LIMIT_MB.
#include <doctest/doctest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/csv_table.h"
#include "core/input_file.h"

namespace MBX_UNITY_ID {

namespace fs = std::filesystem;

namespace {

// Sets an environment variable for a scope, then puts the old value back.
struct ScopedEnv {
    std::string name, old;
    bool had = false;
    ScopedEnv(const char* n, const char* value) : name(n) {
        if (const char* v = std::getenv(n)) had = true, old = v;
        ::setenv(n, value, 1);
    }
    ~ScopedEnv() {
        if (had) ::setenv(name.c_str(), old.c_str(), 1);
        else ::unsetenv(name.c_str());
    }
};

}  // namespace

TEST_CASE("input files: regular files are read whole, devices, pipes and directories refused unread") {
    const fs::path dir = fs::temp_directory_path() / ("mbx_input_file_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string text = std::string("t,q\n0,1\n") + std::string(3, '\0') + "tail";
    std::ofstream(dir / "record.csv", std::ios::binary) << text;
    std::string out, why;
    REQUIRE(mbx::read_input_file((dir / "record.csv").string(), out, why));
    CHECK(out == text);
    CHECK(why.empty());

    const auto t0 = std::chrono::steady_clock::now();
    CHECK_FALSE(mbx::read_input_file("/dev/zero", out, why));
    CHECK(why.find("character device") != std::string::npos);
    CHECK(out.size() <= text.size());  // (nothing read into it)
    REQUIRE(::mkfifo((dir / "pipe").c_str(), 0600) == 0);
    CHECK_FALSE(mbx::read_input_file((dir / "pipe").string(), out, why));  // no writer: opening it would block
    CHECK(why.find("a pipe") != std::string::npos);
    CHECK_FALSE(mbx::read_input_file(dir.string(), out, why));
    CHECK(why.find("a directory") != std::string::npos);
    CHECK_FALSE(mbx::read_input_file((dir / "missing.csv").string(), out, why));
    CHECK(why == "cannot open it: no such file");
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 1.0);
    fs::remove_all(dir);
}

TEST_CASE("input files: a file above the input limit is refused with both sizes named, the limit set by MBX_INPUT_LIMIT_MB") {
    const fs::path dir = fs::temp_directory_path() / ("mbx_input_limit_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    {
        ScopedEnv unset("MBX_INPUT_LIMIT_MB", "");
        CHECK(mbx::input_size_limit() == uint64_t(2048) * 1024 * 1024);
    }
    // A sparse 3 GiB file: above the default limit, refused without reading it.
    const fs::path big = dir / "big.csv";
    {
        std::ofstream(big, std::ios::binary) << "t,q\n";
    }
    fs::resize_file(big, uint64_t(3) * 1024 * 1024 * 1024);
    std::string out, why;
    {
        ScopedEnv unset("MBX_INPUT_LIMIT_MB", "");
        CHECK_FALSE(mbx::read_input_file(big.string(), out, why));
        CHECK(why.find("3072 MiB") != std::string::npos);
        CHECK(why.find("2048 MiB") != std::string::npos);
        CHECK(why.find("MBX_INPUT_LIMIT_MB") != std::string::npos);
    }
    // A 2 kB file against a 1 kB limit, and read once the limit is raised.
    const fs::path small = dir / "small.csv";
    std::ofstream(small, std::ios::binary) << std::string(2048, 'x');
    {
        ScopedEnv tiny("MBX_INPUT_LIMIT_MB", "0.0009765625");  // 1024 bytes
        CHECK(mbx::input_size_limit() == 1024);
        CHECK_FALSE(mbx::read_input_file(small.string(), out, why));
        CHECK(why.find("2048 bytes") != std::string::npos);
        CHECK(why.find("1024 bytes") != std::string::npos);
    }
    {
        ScopedEnv raised("MBX_INPUT_LIMIT_MB", "1");
        REQUIRE(mbx::read_input_file(small.string(), out, why));
        CHECK(out.size() == 2048);
    }
    {
        // A limit that is not a number leaves the default, never no limit.
        ScopedEnv junk("MBX_INPUT_LIMIT_MB", "lots");
        CHECK(mbx::input_size_limit() == uint64_t(2048) * 1024 * 1024);
    }
    fs::remove_all(dir);
}

TEST_CASE("records: a file read in 4 MiB pieces gives every row, a line split across pieces included, as its text does") {
    const fs::path dir = fs::temp_directory_path() / ("mbx_csv_pieces_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string path = (dir / "long.csv").string();
    // About 9 MB, CRLF line ends, no newline after the last row: rows cross
    // both piece boundaries at whatever offset their lengths put them.
    std::string text = "\xEF\xBB\xBFt,k,x\r\n";
    const long rows = 300000;
    for (long k = 0; k < rows; ++k) {
        text += std::to_string(k) + "," + std::to_string(3 * k) + ",0.25";
        if (k + 1 < rows) text += "\r\n";
    }
    std::ofstream(path, std::ios::binary) << text;
    const mbx::CsvTable t = mbx::read_csv_table(path, mbx::Subject::model(""));
    REQUIRE(t.header == std::vector<std::string>{"t", "k", "x"});
    REQUIRE(t.columns.size() == 3);
    REQUIRE(long(t.columns[0].size()) == rows);
    long wrong = 0;
    for (long k = 0; k < rows; ++k)
        wrong += t.columns[0][size_t(k)] != double(k) || t.columns[1][size_t(k)] != double(3 * k) || t.columns[2][size_t(k)] != 0.25;
    CHECK(wrong == 0);
    const mbx::CsvTable whole = mbx::read_csv_table_text(text, path, mbx::Subject::model(""));
    CHECK(whole.columns == t.columns);
    // A bad cell past the first piece is named by its line.
    text.replace(text.find("\r\n250000,"), 9, "\r\nx50000,");
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    try {
        mbx::read_csv_table(path, mbx::Subject::model(""));
        FAIL("the bad cell was read");
    } catch (const mbx::Error& e) {
        CHECK(std::string(e.what()).find("long.csv:250002: column 't' is not a finite number") != std::string::npos);
    }
    fs::remove_all(dir);
}

}  // namespace MBX_UNITY_ID
