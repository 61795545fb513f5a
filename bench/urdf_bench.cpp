// The URDF adapter against the floor set by a bare pugixml parse of the same
// file (load_file): generated robots of 1k and 10k links (arguments choose
// others), written as robot exporters write them: a link with an inertial, a
// visual box and a collision cylinder, and a joint to the link before it
// (revolute with limits and dynamics, every fifth fixed), branching every
// hundred links. Printed per size, best of five runs each in a child process
// of its own: the bare parse, read_urdf, UrdfAdapter::open (reader, tree,
// primitives meshed, the file's description) and open + mbx_translate (`mbx
// translate robot.urdf --format none` before its report), as wall and CPU
// milliseconds and peak memory, as ratios to the bare parse, and as CPU
// microseconds per link.
//
//   bench_urdf [links ...]   (default: 1000 10000)
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "child_process.h"
#include "host_adapters/urdf/urdf_adapter.h"
#include "host_adapters/urdf/urdf_reader.h"
#include "mbx/mbx.h"
#include "peak_memory.h"

namespace {

[[noreturn]] void die(const char* what, const char* why) {
    std::fprintf(stderr, "%s: %s\n", what, why);
    std::exit(1);
}

std::string generate(int links) {
    std::string out = "<?xml version=\"1.0\"?>\n<robot name=\"generated\">\n";
    char buffer[1024];
    for (int k = 0; k < links; ++k) {
        std::snprintf(buffer, sizeof buffer,
                      "  <link name=\"link_%d\">\n"
                      "    <inertial><origin xyz=\"0.05 0.001 0.002\" rpy=\"0 0 0.1\"/><mass value=\"%.6g\"/>\n"
                      "      <inertia ixx=\"1e-4\" ixy=\"1e-6\" ixz=\"0\" iyy=\"2e-4\" iyz=\"0\" izz=\"1.5e-4\"/></inertial>\n"
                      "    <visual><origin xyz=\"0.05 0 0\"/><geometry><box size=\"0.1 0.02 0.02\"/></geometry>\n"
                      "      <material name=\"grey\"><color rgba=\"0.6 0.6 0.6 1\"/></material></visual>\n"
                      "    <collision><geometry><cylinder radius=\"0.01\" length=\"0.1\"/></geometry></collision>\n"
                      "  </link>\n",
                      k, 0.1 + 0.001 * (k % 100));
        out += buffer;
        if (k == 0) continue;
        const int parent = k % 100 == 0 ? k - 50 : k - 1;
        if (k % 5 == 0) {
            std::snprintf(buffer, sizeof buffer,
                          "  <joint name=\"joint_%d\" type=\"fixed\"><parent link=\"link_%d\"/><child link=\"link_%d\"/>"
                          "<origin xyz=\"0.1 0 0\" rpy=\"0 0 0\"/></joint>\n",
                          k, parent, k);
        } else {
            std::snprintf(buffer, sizeof buffer,
                          "  <joint name=\"joint_%d\" type=\"revolute\">\n    <parent link=\"link_%d\"/><child link=\"link_%d\"/>\n"
                          "    <origin xyz=\"0.1 0 0\" rpy=\"0 %.3f 0\"/><axis xyz=\"0 0 1\"/>\n"
                          "    <limit lower=\"-1.5\" upper=\"1.5\" effort=\"10\" velocity=\"2\"/><dynamics damping=\"0.01\" friction=\"0.02\"/>\n"
                          "  </joint>\n",
                          k, parent, k, 0.01 * (k % 7));
        }
        out += buffer;
    }
    return out + "</robot>\n";
}

enum class Stage { pugixml, reader, open, translate };

struct Figures {
    double wall = 0, cpu = 0, peak_mb = 0;
    unsigned rigid_bodies = 0;
};

Figures measure(Stage stage, const std::string& path) {
    Figures f;
    const long start_kb = mbx_bench::status_kb("VmRSS:");
    mbx_bench::reset_peak();
    const mbx_bench::Timer t;
    if (stage == Stage::pugixml) {
        pugi::xml_document doc;
        if (!doc.load_file(path.c_str())) die("pugixml", "cannot parse");
        t.stop(f.wall, f.cpu);
    } else if (stage == Stage::reader) {
        const mbx_files::UrdfModel m = mbx_files::read_urdf(path);
        t.stop(f.wall, f.cpu);
    } else {
        const auto adapter = mbx_files::UrdfAdapter::open(path);
        if (stage == Stage::open) {
            t.stop(f.wall, f.cpu);
        } else {
            mbx_context* ctx = nullptr;
            mbx_context_create(&ctx);
            mbx_translate_options o{};
            o.struct_size = sizeof o;
            mbx_mechanism* mech = nullptr;
            if (mbx_translate(ctx, adapter->table(), &o, &mech) != MBX_OK) die("translation", mbx_context_last_error(ctx));
            t.stop(f.wall, f.cpu);
            mbx_mechanism_summary s{};
            s.struct_size = sizeof s;
            mbx_mechanism_get_summary(mech, &s);
            f.rigid_bodies = s.rigid_body_count;
            mbx_mechanism_destroy(mech);
            mbx_context_destroy(ctx);
        }
    }
    f.peak_mb = double(mbx_bench::status_kb("VmHWM:") - start_kb) / 1024.0;
    return f;
}

void run(int links) {
    char dir[] = "/tmp/mbx_bench_urdf_XXXXXX";
    if (!mkdtemp(dir)) die("bench", "no temporary directory");
    const std::string path = std::string(dir) + "/robot.urdf";
    std::ofstream(path, std::ios::binary) << generate(links);
    const double mb = double(std::filesystem::file_size(path)) / 1e6;
    Figures best[4];
    for (int stage = 0; stage < 4; ++stage)
        for (int repeat = 0; repeat < 5; ++repeat) {
            Figures f;
            if (!mbx_bench::in_child([&] { return measure(Stage(stage), path); }, f)) die("bench", "a stage failed");
            Figures& b = best[stage];
            if (repeat == 0) {
                b = f;
                continue;
            }
            b.wall = std::min(b.wall, f.wall);
            b.cpu = std::min(b.cpu, f.cpu);
            b.peak_mb = std::min(b.peak_mb, f.peak_mb);
        }
    std::filesystem::remove_all(dir);
    const Figures& floor = best[0];
    std::printf("%d links, %.1f MB, %u rigid bodies after welds\n", links, mb, best[3].rigid_bodies);
    std::printf("  %-30s %9s %7s %9s %7s %13s %9s %7s\n", "stage", "wall ms", "ratio", "cpu ms", "ratio", "cpu us/link",
                "peak MB", "ratio");
    const char* names[] = {"pugixml load_file (floor)", "read_urdf", "UrdfAdapter::open", "open + mbx_translate"};
    for (int stage = 0; stage < 4; ++stage) {
        const Figures& f = best[stage];
        std::printf("  %-30s %9.1f %7.2f %9.1f %7.2f %13.2f %9.1f %7.2f\n", names[stage], 1e3 * f.wall, f.wall / floor.wall,
                    1e3 * f.cpu, f.cpu / floor.cpu, 1e6 * f.cpu / links, f.peak_mb, f.peak_mb / floor.peak_mb);
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes;
    for (int k = 1; k < argc; ++k) sizes.push_back(std::atoi(argv[k]));
    if (sizes.empty()) sizes = {1000, 10000};
    for (int n : sizes) {
        if (n < 2 || n > 10000000) die("bench_urdf", "a size from 2 to 10 000 000 links");
        run(n);
    }
    return 0;
}
