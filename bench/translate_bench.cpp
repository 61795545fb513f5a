// Translation throughput on generated assemblies with loops and welds, from
// 1k to 100k bodies: bodies per second, peak memory of the translation, the
// time to write the report, and the ratio of the largest to the smallest
// per-body time (near 1 when cost grows linearly). Each size runs in its own
// process so peaks are separate.
//
//   bench_translate [max_bodies]   (default 100000)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "mbx/mbx.h"
#include "peak_memory.h"
#include "apps/stub_host/assemblies/stub_assembly.h"

namespace {

using mbx_bench::reset_peak;
using mbx_bench::status_kb;

struct Result {
    double seconds_per_body;
    double report_seconds;
    double peak_mb;
    unsigned bodies, loops;
};

Result measure(size_t n) {
    mbx_stub::Assembly assembly = mbx_stub::generate_assembly(n, 42);
    mbx_stub::Host host(assembly);
    mbx_context* ctx = nullptr;
    mbx_context_create(&ctx);
    const long before_kb = status_kb("VmRSS:");
    reset_peak();
    const auto t0 = std::chrono::steady_clock::now();
    mbx_mechanism* mech = nullptr;
    if (mbx_translate(ctx, host.table(), nullptr, &mech) != MBX_OK) {
        std::fprintf(stderr, "translation failed: %s\n", mbx_context_last_error(ctx));
        std::exit(1);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const long peak_kb = status_kb("VmHWM:");
    char dir[] = "/tmp/mbx_bench_XXXXXX";
    const bool have_dir = mkdtemp(dir) != nullptr;
    const auto r0 = std::chrono::steady_clock::now();
    if (have_dir && mbx_mechanism_write_report(ctx, mech, dir) != MBX_OK) {
        std::fprintf(stderr, "report failed: %s\n", mbx_context_last_error(ctx));
        std::exit(1);
    }
    const double report_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
    if (have_dir) {
        for (const char* f : {"/report.json", "/report.txt"}) std::remove((std::string(dir) + f).c_str());
        rmdir(dir);
    }
    mbx_mechanism_summary s{};
    s.struct_size = sizeof s;
    mbx_mechanism_get_summary(mech, &s);
    mbx_mechanism_destroy(mech);
    mbx_context_destroy(ctx);
    return {seconds / double(s.part_count), report_seconds, double(peak_kb - before_kb) / 1024.0, s.part_count,
            s.loop_count};
}

}  // namespace

int main(int argc, char** argv) {
    const size_t max_bodies = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 100000;
    std::vector<size_t> sizes;
    for (size_t n : {1000u, 3000u, 10000u, 30000u, 100000u})
        if (n <= max_bodies) sizes.push_back(n);

    std::printf("%10s %8s %14s %12s %14s %12s\n", "bodies", "loops", "bodies/s", "us/body", "peak MB", "report s");
    std::vector<double> per_body;
    for (size_t n : sizes) {
        int pipe_fd[2];
        if (pipe(pipe_fd) != 0) return 1;
        pid_t pid = fork();
        if (pid == 0) {
            close(pipe_fd[0]);
            measure(n);  // warm-up: allocator and page cache, as a real host would be
            Result r = measure(n);
            if (write(pipe_fd[1], &r, sizeof r) != sizeof r) _exit(1);
            _exit(0);
        }
        close(pipe_fd[1]);
        Result r{};
        const bool ok = read(pipe_fd[0], &r, sizeof r) == sizeof r;
        close(pipe_fd[0]);
        int status = 0;
        waitpid(pid, &status, 0);
        if (!ok || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
            std::fprintf(stderr, "benchmark of %zu bodies failed\n", n);
            return 1;
        }
        per_body.push_back(r.seconds_per_body);
        std::printf("%10u %8u %14.0f %12.2f %14.1f %12.3f\n", r.bodies, r.loops, 1.0 / r.seconds_per_body,
                    r.seconds_per_body * 1e6, r.peak_mb, r.report_seconds);
    }
    if (per_body.size() > 1)
        std::printf("per-body time ratio, largest/smallest assembly: %.2f (1.0 = linear)\n",
                    per_body.back() / per_body.front());
    return 0;
}
