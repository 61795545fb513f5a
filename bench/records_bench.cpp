// Reading a measured record: core/csv_table's reader (regular-file check,
// 4 MiB pieces, a heartbeat per row, every cell checked finite and counted)
// on a generated CSV of EMPS-like columns, against its peer: the same file
// read whole and every number converted by a bare std::from_chars pass.
// Both per row and as MB/s, at two sizes, to show the cost stays linear.
//
//   bench_records [million rows]   (default 1; the second size is a tenth)
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

#include "core/csv_table.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// t, q_ref, q_meas, u, force: the EMPS record's columns, with its digits.
void write_record(const std::string& path, long rows) {
    std::ofstream out(path);
    out << "t_s,q_ref_m,q_meas_m,u_drive_V,force_N\n";
    char line[160];
    for (long k = 0; k < rows; ++k) {
        const double t = 1e-3 * double(k), q = 0.1 * std::sin(t), u = 2.5 * std::cos(3 * t);
        std::snprintf(line, sizeof line, "%.6f,%.9e,%.9e,%.9e,%.9e\n", t, q, q + 1e-5 * std::sin(50 * t), u, 35.0 * u);
        out << line;
    }
}

// The peer: read whole, then every comma- or newline-separated number converted.
double bare_pass(const std::string& path, long& numbers) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    std::string text(size_t(in.tellg()), '\0');
    in.seekg(0);
    in.read(text.data(), std::streamsize(text.size()));
    const char* p = text.data() + text.find('\n') + 1;
    const char* end = text.data() + text.size();
    double sum = 0;
    numbers = 0;
    while (p < end) {
        double v = 0;
        const auto r = std::from_chars(p, end, v);
        sum += v;
        ++numbers;
        p = r.ptr + 1;
    }
    return sum;
}

}  // namespace

int main(int argc, char** argv) {
    const double millions = argc > 1 ? std::atof(argv[1]) : 1.0;
    const std::string path = "/tmp/bench_records_" + std::to_string(::getpid()) + ".csv";
    std::printf("%-12s %10s %12s %12s %12s %10s\n", "rows", "MB", "mbx ns/row", "bare ns/row", "mbx MB/s", "mbx/bare");
    for (double scale : {0.1, 1.0}) {
        const long rows = long(millions * scale * 1e6);
        write_record(path, rows);
        std::ifstream size_of(path, std::ios::binary | std::ios::ate);
        const double mb = double(size_of.tellg()) / 1e6;
        double best_mbx = 1e300, best_bare = 1e300;
        for (int repeat = 0; repeat < 3; ++repeat) {
            Clock::time_point t0 = Clock::now();
            const mbx::CsvTable t = mbx::read_csv_table(path, mbx::Subject::model("bench"));
            best_mbx = std::min(best_mbx, since(t0));
            if (t.columns.size() != 5 || long(t.columns[0].size()) != rows) return std::fprintf(stderr, "wrong table\n"), 1;
            t0 = Clock::now();
            long numbers = 0;
            const volatile double sink = bare_pass(path, numbers);
            (void)sink;
            best_bare = std::min(best_bare, since(t0));
            if (numbers != 5 * rows) return std::fprintf(stderr, "wrong bare count\n"), 1;
        }
        std::printf("%-12ld %10.1f %12.1f %12.1f %12.0f %10.2f\n", rows, mb, 1e9 * best_mbx / double(rows),
                    1e9 * best_bare / double(rows), mb / best_mbx, best_mbx / best_bare);
    }
    std::remove(path.c_str());
    return 0;
}
