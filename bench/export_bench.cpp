// Export time per format on generated assemblies (default 1k, 3k and 10k
// bodies, with loops, welds and a box mesh per link), through the C API, and
// each format's ratio to the translation time of the same assembly. The
// per-body time at the largest size over the smallest shows whether cost
// grows linearly.
//
//   bench_export [max_bodies]   (default 10000)
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "mbx/mbx.h"
#include "stub_assembly.h"

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

void die(mbx_context* ctx, const char* what) {
    std::fprintf(stderr, "%s failed: %s\n", what, mbx_context_last_error(ctx));
    std::exit(1);
}

}  // namespace

int main(int argc, char** argv) {
    const size_t max_bodies = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 10000;
    const std::filesystem::path root =
        std::filesystem::temp_directory_path() / ("mbx_bench_export_" + std::to_string(::getpid()));

    std::printf("%8s %10s", "bodies", "translate");
    for (const Format& f : kFormats) std::printf(" %10s %7s", f.name, "ratio");
    std::printf("   (seconds; ratio = export / translation)\n");
    std::vector<std::vector<double>> per_body(kFormatCount);
    std::vector<size_t> sizes;
    for (size_t n : {1000u, 3000u, 10000u, 30000u})
        if (n <= max_bodies) sizes.push_back(n);
    for (size_t n : sizes) {
        mbx_stub::Assembly assembly = mbx_stub::generate_assembly(n, 7);
        mbx_stub::Host host(assembly);
        mbx_context* ctx = nullptr;
        mbx_context_create(&ctx);
        mbx_mechanism* mech = nullptr;
        const auto t0 = Clock::now();
        if (mbx_translate(ctx, host.table(), nullptr, &mech) != MBX_OK) die(ctx, "translation");
        const double translate_s = since(t0);
        // Shapes are fetched from the host on first use; fetch them before
        // timing so each format pays only for its own writing.
        for (uint32_t b = 0;; ++b) {
            mbx_shape_stats st{};
            st.struct_size = sizeof st;
            if (mbx_mechanism_get_shape_stats(ctx, mech, b, &st) != MBX_OK) break;
        }
        std::printf("%8zu %10.3f", n, translate_s);
        for (size_t f = 0; f < kFormatCount; ++f) {
            const std::filesystem::path dir = root / kFormats[f].name;
            mbx_export_options o{};
            o.struct_size = sizeof o;
            o.formats = kFormats[f].bits;
            o.model_name = "generated";
            const auto e0 = Clock::now();
            if (mbx_mechanism_export(ctx, mech, &o, dir.c_str()) != MBX_OK) die(ctx, kFormats[f].name);
            const double s = since(e0);
            per_body[f].push_back(s / double(n));
            std::printf(" %10.3f %7.2f", s, s / translate_s);
            std::filesystem::remove_all(dir);
        }
        std::printf("\n");
        mbx_mechanism_destroy(mech);
        mbx_context_destroy(ctx);
    }
    std::filesystem::remove_all(root);
    if (sizes.size() > 1) {
        std::printf("per-body time ratio, largest/smallest assembly (1.0 = linear):");
        for (size_t f = 0; f < kFormatCount; ++f)
            std::printf(" %s %.2f", kFormats[f].name, per_body[f].back() / per_body[f].front());
        std::printf("\n");
    }
    return 0;
}
