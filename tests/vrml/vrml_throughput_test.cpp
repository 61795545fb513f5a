// Throughput on a generated CAD-like file: parts of a tessellated surface,
// each in a Transform. Prints MB/s; asserts only a loose bound so slow
// machines and sanitizer builds pass. MBX_VRML_BENCH_MB sets the size.
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include <doctest/doctest.h>

#include "vrml_test_support.h"

namespace MBX_UNITY_ID {

using mbx_files::read_vrml;
using mbx_files::VrmlScene;
using vrml_test::TempDir;

namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr double default_megabytes = 5;
#else
constexpr double default_megabytes = 20;
#endif

// One part: a grid x grid patch of points, two triangles per cell.
void append_part(std::string& out, int index, int grid) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "DEF PART_%d Transform { translation %d 0 0 rotation 0 0 1 0.25 children [\n", index,
                  index);
    out += buf;
    out += " Shape { geometry IndexedFaceSet {\n  coord Coordinate { point [\n";
    for (int i = 0; i < grid; ++i)
        for (int j = 0; j < grid; ++j) {
            std::snprintf(buf, sizeof buf, "   %.6f %.6f %.6f,\n", i * 0.013, j * 0.017, (i * j % 97) * 0.0031);
            out += buf;
        }
    out += "  ] }\n  coordIndex [\n";
    for (int i = 0; i + 1 < grid; ++i)
        for (int j = 0; j + 1 < grid; ++j) {
            const int a = i * grid + j, b = a + 1, c = a + grid, d = c + 1;
            std::snprintf(buf, sizeof buf, "   %d %d %d -1 %d %d %d -1\n", a, b, d, a, d, c);
            out += buf;
        }
    out += "  ] } }\n] }\n";
}

}  // namespace

TEST_CASE("throughput: a generated multi-megabyte IndexedFaceSet file") {
    double megabytes = default_megabytes;
    if (const char* env = std::getenv("MBX_VRML_BENCH_MB")) megabytes = std::atof(env);
    const int grid = 150;
    std::string text = "#VRML V2.0 utf8\n";
    text.reserve(static_cast<size_t>(megabytes * 1.05e6));
    int parts = 0;
    while (text.size() < megabytes * 1e6) append_part(text, parts++, grid);
    const TempDir dir;
    const std::string path = dir.write("bench.wrl", text);

    const auto start = std::chrono::steady_clock::now();
    const VrmlScene scene = read_vrml(path);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    size_t triangles = 0;
    for (const auto& n : scene.nodes)
        for (const auto& m : n.meshes) triangles += m.triangles.size() / 3;
    const size_t expected = static_cast<size_t>(parts) * 2 * (grid - 1) * (grid - 1);
    CHECK(scene.nodes.size() == static_cast<size_t>(parts));
    CHECK(triangles == expected);
    MESSAGE("read " << text.size() / 1e6 << " MB (" << triangles << " triangles, " << parts << " parts) in " << seconds
                    << " s: " << text.size() / 1e6 / seconds << " MB/s");
    CHECK(seconds < 20);
}
}  // namespace MBX_UNITY_ID
