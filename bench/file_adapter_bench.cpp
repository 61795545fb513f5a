// The PMXML + VRML file adapter against the floor set by a bare pugixml parse
// of the same XML (load_file): generated assemblies (mbx_pmxml_generator) of
// 1k, 10k and 100k parts. For each size it prints the time and the peak
// memory of every stage as a ratio to that floor, and the cost per part:
//
//   pugixml load_file (floor)    the XML parsed into pugixml's DOM, nothing else
//   read_pmxml (reader)          the PMXML reader alone: file -> PmxmlModel,
//                                by parts (the file mapped, no whole DOM)
//   read_pmxml as one DOM        the same forced through pugixml's whole DOM
//                                (the reader's fallback, and how it read before)
//   FileAdapter::open            reader + host assembly, no VRML (the path of
//                                `mbx translate file.xml`)
//   + mbx_translate              what `mbx translate file.xml --format none`
//   + report                     does, report files included
//   with VRML shapes             open with the VRML scene matched to the
//                                bodies, translated with the mass check
//
// Each stage runs in its own child process, so its peak (VmHWM, reset through
// /proc/self/clear_refs) is its alone; memory is counted above the child's
// resident size when the stage starts (the process's libraries and the
// like), so the ratio compares what the stage adds with what the DOM adds.
// Times are the best of `--repeat` runs (default 3), wall and CPU (user +
// system) apart: the machines these run on are shared, the best run is the
// one least disturbed, and CPU time is what a busy machine disturbs least.
// All stages read the file from the page cache.
//
//   bench_file_adapter [--repeat N] [parts ...]   (default: 1000 10000 100000;
//                                                  100k takes about a minute)
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "samples/tools/generate_pmxml.h"
#include "mbx/mbx.h"
#include "child_process.h"
#include "peak_memory.h"
#include "host_adapters/pmxml_vrml/pmxml_reader.h"

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

using mbx_bench::in_child;
using mbx_bench::Timer;
using mbx_bench::reset_peak;
using mbx_bench::status_kb;

enum class Stage { pugixml, reader, reader_dom, cli_path, with_shapes };

// What one child reports; seconds < 0 for a stage it did not run.
struct Figures {
    double seconds[4] = {-1, -1, -1, -1};  // wall, by Step (below)
    double cpu[4] = {-1, -1, -1, -1};      // user + system
    double peak_mb = 0;                     // above the resident size at the start
    size_t matched_meshes = 0;
    unsigned rigid_bodies = 0;
};

// Steps of a child's run, timed separately; a stage's total is their sum.
enum Step { load = 0, open_step = 1, translate_step = 2, report_step = 3 };

struct Paths {
    std::string xml, wrl;
};

[[noreturn]] void die(const char* what, const char* why) {
    std::fprintf(stderr, "%s: %s\n", what, why);
    std::exit(1);
}

// Translates the adapter's table (and writes the report, if `report`).
void translate(const mbx_files::FileAdapter& adapter, bool mass_check, bool report, Figures& f) {
    mbx_context* ctx = nullptr;
    mbx_context_create(&ctx);
    mbx_translate_options o{};
    o.struct_size = sizeof o;
    if (mass_check) o.flags = MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES;  // the CLI's default
    mbx_mechanism* mech = nullptr;
    const Timer t;
    if (mbx_translate(ctx, adapter.table(), &o, &mech) != MBX_OK) die("translation", mbx_context_last_error(ctx));
    t.stop(f.seconds[translate_step], f.cpu[translate_step]);
    if (report) {
        char dir[] = "/tmp/mbx_bench_report_XXXXXX";
        if (!mkdtemp(dir)) die("report", "no temporary directory");
        const Timer r;
        if (mbx_mechanism_write_report(ctx, mech, dir) != MBX_OK) die("report", mbx_context_last_error(ctx));
        r.stop(f.seconds[report_step], f.cpu[report_step]);
        std::filesystem::remove_all(dir);
    }
    mbx_mechanism_summary s{};
    s.struct_size = sizeof s;
    mbx_mechanism_get_summary(mech, &s);
    f.rigid_bodies = s.rigid_body_count;
    mbx_mechanism_destroy(mech);
    mbx_context_destroy(ctx);
}

Figures measure(Stage stage, const Paths& g) {
    Figures f;
    const long start_kb = status_kb("VmRSS:");
    reset_peak();
    const Timer t;
    if (stage == Stage::pugixml) {
        pugi::xml_document doc;
        const pugi::xml_parse_result r = doc.load_file(g.xml.c_str());
        t.stop(f.seconds[load], f.cpu[load]);
        if (!r) die("pugixml", r.description());
        f.peak_mb = double(status_kb("VmHWM:") - start_kb) / 1024.0;
        return f;
    }
    if (stage == Stage::reader || stage == Stage::reader_dom) {
        const mbx_files::PmxmlModel model = mbx_files::read_pmxml(
            g.xml, stage == Stage::reader ? mbx_files::PmxmlParse::automatic : mbx_files::PmxmlParse::whole_dom);
        t.stop(f.seconds[load], f.cpu[load]);
        f.peak_mb = double(status_kb("VmHWM:") - start_kb) / 1024.0;
        return f;
    }
    mbx_files::FileAdapterOptions options;
    if (stage == Stage::with_shapes) options.shapes_path = g.wrl;
    const auto adapter = mbx_files::FileAdapter::open(g.xml, options);
    t.stop(f.seconds[open_step], f.cpu[open_step]);
    f.matched_meshes = adapter->matching().meshes.size();
    translate(*adapter, true, stage == Stage::cli_path, f);
    f.peak_mb = double(status_kb("VmHWM:") - start_kb) / 1024.0;
    return f;
}

// The best of `repeat` children: each step's least time, the least peak.
bool best_of(int repeat, Stage stage, const Paths& paths, Figures& best) {
    for (int r = 0; r < repeat; ++r) {
        Figures f;
        if (!in_child([&] { return measure(stage, paths); }, f)) return false;
        if (r == 0) {
            best = f;
            continue;
        }
        for (int s = 0; s < 4; ++s) {
            best.seconds[s] = std::min(best.seconds[s], f.seconds[s]);
            best.cpu[s] = std::min(best.cpu[s], f.cpu[s]);
        }
        best.peak_mb = std::min(best.peak_mb, f.peak_mb);
    }
    return true;
}

// Steps first..last of `times` (wall or cpu) added up.
double sum(const double* times, int first, int last) {
    double t = 0;
    for (int s = first; s <= last; ++s) t += std::max(0.0, times[s]);
    return t;
}

// Steps first..last of `f` against the floor's load; peak_mb < 0: the
// stage's peak is the one printed on a later row.
void row(size_t parts, const char* stage, const Figures& f, int first, int last, double peak_mb, const Figures& floor) {
    char peak[32] = "-", peak_ratio[32] = "-";
    if (peak_mb >= 0) {
        std::snprintf(peak, sizeof peak, "%.1f", peak_mb);
        std::snprintf(peak_ratio, sizeof peak_ratio, "%.2f", peak_mb / floor.peak_mb);
    }
    const double wall = sum(f.seconds, first, last), cpu = sum(f.cpu, first, last);
    std::printf("%8zu  %-36s %8.3f %7.2f %8.3f %7.2f %9.2f %9s %8s\n", parts, stage, wall, wall / floor.seconds[load],
                cpu, cpu / floor.cpu[load], 1e6 * cpu / double(parts), peak, peak_ratio);
}

struct Summary {
    size_t parts;
    double reader_us, cli_us;  // CPU per part
    double reader_time, reader_cpu, reader_peak, cli_time, cli_cpu, cli_peak;  // ratios to the floor
};

}  // namespace

int main(int argc, char** argv) {
    std::vector<size_t> sizes;
    int repeat = 3;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
            repeat = std::max(1, std::atoi(argv[++i]));
        else
            sizes.push_back(std::strtoul(argv[i], nullptr, 10));
    }
    if (sizes.empty()) sizes = {1000, 10000, 100000};

    std::printf("best of %d runs; x: ratio to pugixml load_file of the same file (wall time, CPU time = user + "
                "system, peak memory above the process's start)\n",
                repeat);
    std::printf("%8s  %-36s %8s %7s %8s %7s %9s %9s %8s\n", "parts", "stage", "wall s", "x wall", "CPU s", "x CPU",
                "CPU us/pt", "peak MB", "x memory");
    std::vector<Summary> summary;
    for (size_t n : sizes) {
        char pattern[] = "/tmp/mbx_bench_file_adapter_XXXXXX";
        if (!mkdtemp(pattern)) return 1;
        const std::string dir = pattern;
        const Paths paths{dir + "/bench.xml", dir + "/bench_a.wrl"};
        Figures bare{}, reader{}, reader_dom{}, cli{}, shapes{};
        struct Generated {
            size_t parts, rigid_bodies, vrml_nodes;
            double seconds;
        } gen{};
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
                gen) &&
            best_of(repeat, Stage::pugixml, paths, bare) && best_of(repeat, Stage::reader, paths, reader) &&
            best_of(repeat, Stage::reader_dom, paths, reader_dom) &&
            best_of(repeat, Stage::cli_path, paths, cli) && best_of(repeat, Stage::with_shapes, paths, shapes);
        const double xml_mb = ok ? double(std::filesystem::file_size(paths.xml)) / 1048576.0 : 0;
        const double wrl_mb = ok ? double(std::filesystem::file_size(paths.wrl)) / 1048576.0 : 0;
        std::filesystem::remove_all(dir);
        if (!ok) {
            std::fprintf(stderr, "benchmark of %zu parts failed\n", n);
            return 1;
        }
        if (shapes.matched_meshes != gen.parts || shapes.rigid_bodies != gen.rigid_bodies ||
            cli.rigid_bodies != gen.rigid_bodies)
            std::fprintf(stderr, "warning: %zu meshes matched (expected %zu), %u rigid bodies (expected %zu)\n",
                         shapes.matched_meshes, gen.parts, shapes.rigid_bodies, gen.rigid_bodies);
        row(n, "pugixml load_file (floor)", bare, load, load, bare.peak_mb, bare);
        row(n, "read_pmxml (the reader, by parts)", reader, load, load, reader.peak_mb, bare);
        row(n, "read_pmxml as one DOM (its fallback)", reader_dom, load, load, reader_dom.peak_mb, bare);
        row(n, "FileAdapter::open, no VRML", cli, open_step, open_step, -1, bare);
        row(n, "  + mbx_translate", cli, open_step, translate_step, -1, bare);
        row(n, "  + report (translate --format none)", cli, open_step, report_step, cli.peak_mb, bare);
        row(n, "with VRML: open (read + match)", shapes, open_step, open_step, -1, bare);
        row(n, "  + mbx_translate with mass check", shapes, open_step, translate_step, shapes.peak_mb, bare);
        std::printf("%8s  (%.0f MB XML, %.0f MB VRML, %zu VRML transforms, generated in %.1f s)\n", "", xml_mb, wrl_mb,
                    gen.vrml_nodes, gen.seconds);
        const double cli_wall = sum(cli.seconds, open_step, report_step), cli_cpu = sum(cli.cpu, open_step, report_step);
        summary.push_back({n, 1e6 * reader.cpu[load] / double(n), 1e6 * cli_cpu / double(n),
                           reader.seconds[load] / bare.seconds[load], reader.cpu[load] / bare.cpu[load],
                           reader.peak_mb / bare.peak_mb, cli_wall / bare.seconds[load], cli_cpu / bare.cpu[load],
                           cli.peak_mb / bare.peak_mb});
    }
    std::printf("\nthe reader (read_pmxml) and `mbx translate --format none` (open + translate + report) against "
                "pugixml load_file:\n");
    std::printf("%8s  %9s %7s %7s %7s   %9s %7s %7s %7s\n", "parts", "CPU us/pt", "x wall", "x CPU", "x mem",
                "CPU us/pt", "x wall", "x CPU", "x mem");
    for (const Summary& s : summary)
        std::printf("%8zu  %9.2f %7.2f %7.2f %7.2f   %9.2f %7.2f %7.2f %7.2f\n", s.parts, s.reader_us, s.reader_time,
                    s.reader_cpu, s.reader_peak, s.cli_us, s.cli_time, s.cli_cpu, s.cli_peak);
    if (summary.size() > 1)
        std::printf("CPU per part, largest/smallest assembly: reader %.2f, translate --format none %.2f "
                    "(1.0 = flat)\n",
                    summary.back().reader_us / summary.front().reader_us, summary.back().cli_us / summary.front().cli_us);
    return 0;
}
