// Export cost per format on generated assemblies (default 1k, 3k and 10k
// bodies, with loops, welds and a box mesh per link): the time to produce
// each format's files in memory, the time to write them, and both against
// the translation time of the same assembly. Per-body time at the largest
// size over the smallest shows whether cost grows linearly.
//
// Writing is mostly the file system's cost (one file per body for meshes;
// ext4's inode allocator dominates when many files were recently deleted), so
// it is printed apart from the exporters' own work.
//
//   bench_export [max_bodies]   (default 10000)
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/assembly/host_reader.h"
#include "export/export_files.h"
#include "apps/stub_host/assemblies/stub_assembly.h"
#include "core/translator/translate.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Format {
    const char* name;
    uint32_t bits;
};
const Format kFormats[] = {{"modelica", MBX_EXPORT_MODELICA},
                           {"mjcf", MBX_EXPORT_MJCF},
                           {"urdf", MBX_EXPORT_URDF},
                           {"meshes", MBX_EXPORT_MESHES}};
constexpr size_t kFormatCount = sizeof kFormats / sizeof kFormats[0];

}  // namespace

int main(int argc, char** argv) {
    const size_t max_bodies = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 10000;
    const std::filesystem::path root =
        std::filesystem::temp_directory_path() / ("mbx_bench_export_" + std::to_string(::getpid()));

    std::printf("%8s %10s", "bodies", "translate");
    for (const Format& f : kFormats) std::printf(" | %8s %7s %7s", f.name, "ratio", "write");
    std::printf("\n(seconds; ratio = producing the files in memory / translation; write = writing them to disk)\n");
    std::vector<std::vector<double>> per_body(kFormatCount);
    std::vector<size_t> sizes;
    for (size_t n : {1000u, 3000u, 10000u, 30000u})
        if (n <= max_bodies) sizes.push_back(n);
    try {
        for (size_t n : sizes) {
            mbx_stub::Host host(mbx_stub::generate_assembly(n, 7));
            mbx::Progress progress(nullptr, nullptr);
            const auto t0 = Clock::now();
            mbx::Findings findings;
            mbx::Assembly assembly = mbx::read_host(host.table(), mbx::HostReadOptions{}, progress, findings);
            auto m = mbx::translate_assembly(std::move(assembly), std::move(findings), mbx::TranslateOptions{},
                                             progress);
            const double translate_s = since(t0);
            // Meshes are fetched from the host once, before timing, so each
            // format pays only for its own work.
            std::vector<std::vector<mbx::Mesh>> shapes(m->bodies.size());
            for (size_t b = 0; b < m->bodies.size(); ++b)
                shapes[b] = mbx::load_body_shapes(*host.table(), *m, int(b));
            const mbx::BodyShapes fetch = [&shapes](int b) -> const std::vector<mbx::Mesh>& {
                return shapes[size_t(b)];
            };
            std::printf("%8zu %10.3f", n, translate_s);
            for (size_t f = 0; f < kFormatCount; ++f) {
                mbx::ExportSettings settings;
                settings.model_name = "generated";
                mbx::ExportModel model(*m, fetch, settings);
                const auto e0 = Clock::now();
                const mbx::OutputFiles files = mbx::export_files(model, kFormats[f].bits);
                const double produce_s = since(e0);
                const auto w0 = Clock::now();
                mbx::write_output_files((root / (std::to_string(n) + kFormats[f].name)).string(), files);
                const double write_s = since(w0);
                per_body[f].push_back(produce_s / double(n));
                std::printf(" | %8.3f %7.2f %7.3f", produce_s, produce_s / translate_s, write_s);
            }
            std::printf("\n");
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "export failed: %s\n", e.what());
        std::filesystem::remove_all(root);
        return 1;
    }
    std::filesystem::remove_all(root);
    if (sizes.size() > 1) {
        std::printf("per-body time to produce, largest/smallest assembly (1.0 = linear):");
        for (size_t f = 0; f < kFormatCount; ++f)
            std::printf(" %s %.2f", kFormats[f].name, per_body[f].back() / per_body[f].front());
        std::printf("\n");
    }
    return 0;
}
