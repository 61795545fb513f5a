// The PMXML + VRML file adapter against the floor set by a bare pugixml parse
// of the same XML: generated assemblies (mbx_pmxml_generator) are read, their
// VRML shapes matched and the result translated, for 10k and 100k parts by
// default so the growth shows. Generation and every measured stage run in
// their own child process, so each peak RSS (VmHWM, reset through
// /proc/self/clear_refs) is that stage's alone. The bare parse and the
// adapter read the same file from the page cache.
//
//   bench_file_adapter [parts ...]   (default: 10000 100000)
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "file_adapter.h"
#include "generate_pmxml.h"
#include "mbx/mbx.h"
#include "peak_memory.h"

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

using mbx_bench::reset_peak;
using mbx_bench::status_kb;

// What one child reports.
struct Figures {
    double pugixml = 0;          // load_file
    double open = 0;             // FileAdapter::open: PMXML + VRML read, shapes matched
    double translate = 0;        // mbx_translate
    double translate_mass = 0;   // mbx_translate with the mass check (pulls every shape)
    double peak_mb = 0;
    size_t matched_meshes = 0;
    unsigned rigid_bodies = 0;
};

enum class Stage { pugixml, adapter, adapter_mass };

// The generated assembly, as plain data a child can hand back through a pipe.
struct Generated {
    size_t parts = 0, rigid_bodies = 0, vrml_nodes = 0;
    double seconds = 0;
};

struct Paths {
    std::string xml, wrl;
};

Figures measure(Stage stage, const Paths& g) {
    Figures f;
    reset_peak();
    if (stage == Stage::pugixml) {
        pugi::xml_document doc;
        const auto t0 = Clock::now();
        const pugi::xml_parse_result r = doc.load_file(g.xml.c_str());
        f.pugixml = since(t0);
        if (!r) {
            std::fprintf(stderr, "pugixml: %s\n", r.description());
            std::exit(1);
        }
        f.peak_mb = double(status_kb("VmHWM:")) / 1024.0;
        return f;
    }
    mbx_files::FileAdapterOptions options;
    options.shapes_path = g.wrl;
    auto t0 = Clock::now();
    const auto adapter = mbx_files::FileAdapter::open(g.xml, options);
    f.open = since(t0);
    f.matched_meshes = adapter->matching().meshes.size();

    mbx_context* ctx = nullptr;
    mbx_context_create(&ctx);
    mbx_translate_options o{};
    o.struct_size = sizeof o;
    if (stage == Stage::adapter_mass) o.flags = MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES;
    mbx_mechanism* mech = nullptr;
    t0 = Clock::now();
    if (mbx_translate(ctx, adapter->table(), &o, &mech) != MBX_OK) {
        std::fprintf(stderr, "translation failed: %s\n", mbx_context_last_error(ctx));
        std::exit(1);
    }
    (stage == Stage::adapter_mass ? f.translate_mass : f.translate) = since(t0);
    f.peak_mb = double(status_kb("VmHWM:")) / 1024.0;
    mbx_mechanism_summary s{};
    s.struct_size = sizeof s;
    mbx_mechanism_get_summary(mech, &s);
    f.rigid_bodies = s.rigid_body_count;
    mbx_mechanism_destroy(mech);
    mbx_context_destroy(ctx);
    return f;
}

// Runs `work` in a child process and reads back what it returns, so that
// neither the generator's nor an earlier stage's heap counts in a peak.
template <class Result, class Work>
bool in_child(Work work, Result& out) {
    int fd[2];
    if (pipe(fd) != 0) return false;
    const pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        const Result r = work();
        if (write(fd[1], &r, sizeof r) != sizeof r) _exit(1);
        _exit(0);
    }
    close(fd[1]);
    const bool ok = read(fd[0], &out, sizeof out) == sizeof out;
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return ok && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// peak_mb < 0: not measured on its own (a stage inside a measured run).
void row(size_t parts, const char* stage, double seconds, double peak_mb, double floor_seconds) {
    char peak[32] = "-";
    if (peak_mb >= 0) std::snprintf(peak, sizeof peak, "%.1f", peak_mb);
    std::printf("%8zu  %-34s %9.3f %10s %12.0f %9.2f\n", parts, stage, seconds, peak, double(parts) / seconds,
                seconds / floor_seconds);
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<size_t> sizes;
    for (int i = 1; i < argc; ++i) sizes.push_back(std::strtoul(argv[i], nullptr, 10));
    if (sizes.empty()) sizes = {10000, 100000};

    std::printf("%8s  %-34s %9s %10s %12s %9s\n", "parts", "stage", "seconds", "peak MB", "parts/s", "x pugixml");
    for (size_t n : sizes) {
        char pattern[] = "/tmp/mbx_bench_file_adapter_XXXXXX";
        if (!mkdtemp(pattern)) return 1;
        const std::string dir = pattern;
        const Paths paths{dir + "/bench.xml", dir + "/bench_a.wrl"};
        Generated g;
        Figures bare{}, adapter{}, with_mass{};
        const bool ok =
            in_child(
                [&] {
                    mbx_samples::GeneratorOptions options;
                    options.parts = n;
                    options.seed = 42;
                    const auto t0 = Clock::now();
                    const mbx_samples::GeneratedCounts c = mbx_samples::generate_pmxml(dir, "bench", options);
                    return Generated{c.parts, c.rigid_bodies, c.vrml_nodes, since(t0)};
                },
                g) &&
            in_child([&] { return measure(Stage::pugixml, paths); }, bare) &&
            in_child([&] { return measure(Stage::adapter, paths); }, adapter) &&
            in_child([&] { return measure(Stage::adapter_mass, paths); }, with_mass);
        const double xml_mb = ok ? double(std::filesystem::file_size(paths.xml)) / 1048576.0 : 0;
        const double wrl_mb = ok ? double(std::filesystem::file_size(paths.wrl)) / 1048576.0 : 0;
        std::filesystem::remove_all(dir);
        if (!ok) {
            std::fprintf(stderr, "benchmark of %zu parts failed\n", n);
            return 1;
        }
        if (adapter.matched_meshes != g.parts || adapter.rigid_bodies != g.rigid_bodies)
            std::fprintf(stderr, "warning: %zu meshes matched (expected %zu), %u rigid bodies (expected %zu)\n",
                         adapter.matched_meshes, g.parts, adapter.rigid_bodies, g.rigid_bodies);
        const double floor = bare.pugixml;
        row(n, "pugixml load_file (floor)", bare.pugixml, bare.peak_mb, floor);
        row(n, "FileAdapter::open (read + match)", adapter.open, -1, floor);
        row(n, "mbx_translate", adapter.translate, -1, floor);
        row(n, "open + translate", adapter.open + adapter.translate, adapter.peak_mb, floor);
        row(n, "open + translate with mass check", with_mass.open + with_mass.translate_mass, with_mass.peak_mb,
            floor);
        std::printf("%8s  (%.0f MB XML, %.0f MB VRML, %zu VRML transforms, generated in %.1f s)\n", "", xml_mb,
                    wrl_mb, g.vrml_nodes, g.seconds);
    }
    return 0;
}
