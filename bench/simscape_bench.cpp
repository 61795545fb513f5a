// The Simscape Multibody adapter against the floor set by a bare pugixml
// parse of the same file (load_file): generated exports of 1k and 10k
// instances (arguments choose others). Each instance is a part instance
// (the parts shared ten to one); every tenth is hinged to the one before by a
// revolute joint, the others are welded to it as fasteners are, and every
// hundred instances sit in a sub-assembly of their own. Printed per size,
// best of five runs, each in a child process of its own: the bare parse,
// read_simscape, SimscapeAdapter::open (reader + host assembly; STEP files
// load only when shapes are asked for) and open + mbx_translate (what `mbx
// translate export.xml --format none` does before its report), each as wall
// and CPU milliseconds and peak memory, as ratios to the bare parse, and as
// CPU microseconds per instance.
//
//   bench_simscape [instances ...]   (default: 1000 10000)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "host_adapters/simscape/simscape_adapter.h"
#include "host_adapters/simscape/simscape_reader.h"
#include "mbx/mbx.h"
#include "child_process.h"
#include "peak_memory.h"
#include "samples/tools/simscape_document.h"

namespace {

[[noreturn]] void die(const char* what, const char* why) {
    std::fprintf(stderr, "%s: %s\n", what, why);
    std::exit(1);
}

mbx_samples::SimscapeXmlDocument generate(int instances) {
    mbx_samples::SimscapeXmlDocument d;
    d.root_name = "generated";
    d.root_uid = "ROOT";
    d.digits = 9;  // as exporters print
    const int parts = std::max(1, instances / 10);
    for (int p = 0; p < parts; ++p) {
        mbx_samples::SimscapeXmlPart part;
        part.uid = "P" + std::to_string(p);
        part.name = "part_" + std::to_string(p);
        part.mass = 0.1 + 0.001 * p;
        part.com = Eigen::Vector3d(0.01, 0.002, 0.005);
        part.inertia = Eigen::Vector3d(1e-4, 2e-4, 1.5e-4).asDiagonal();
        part.geometry_file = part.name + ".step";
        d.parts.push_back(part);
    }
    size_t group = 0;
    std::vector<std::string> path_of(static_cast<size_t>(instances));
    for (int i = 0; i < instances; ++i) {
        if (i % 100 == 0) {
            mbx_samples::SimscapeXmlInstance g;
            g.uid = "G" + std::to_string(i / 100);
            g.name = "group <" + std::to_string(i / 100) + ">";
            g.entity_uid = "A-group";
            g.local.translation() = Eigen::Vector3d(0.05 * (i / 100), 0, 0);
            group = d.instances.size();
            d.instances.push_back(g);
        }
        mbx_samples::SimscapeXmlInstance in;
        in.uid = "M" + std::to_string(i);
        in.name = "part_" + std::to_string(i % parts) + " <" + std::to_string(i) + ">";
        in.entity_uid = "P" + std::to_string(i % parts);
        in.local.linear() = Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        in.local.translation() = Eigen::Vector3d(0, 0.001 * (i % 100), 0.002 * (i % 7));
        in.grounded = i == 0;
        d.instances[group].children.push_back(in);
        path_of[size_t(i)] = d.instances[group].uid + "/" + in.uid;
    }
    auto path = [&](int i) {
        const std::string& p = path_of[size_t(i)];
        const size_t slash = p.find('/');
        return std::vector<std::string>{p.substr(0, slash), p.substr(slash + 1)};
    };
    for (int i = 1; i < instances; ++i) {
        mbx_samples::SimscapeXmlJoint j;
        j.type = i % 10 == 0 ? "Revolute" : "Weld";
        j.name = j.type + std::to_string(i);
        j.base.path = path(i - 1);
        j.follower.path = path(i);
        // Both frames at the follower's origin.
        const auto& g0 = d.instances[size_t((i - 1) / 100)];
        const auto& g1 = d.instances[size_t(i / 100)];
        const Eigen::Isometry3d w0 = g0.local * g0.children[size_t((i - 1) % 100)].local;
        const Eigen::Isometry3d w1 = g1.local * g1.children[size_t(i % 100)].local;
        j.base.transform = w0.inverse() * w1;
        j.follower.transform = Eigen::Isometry3d::Identity();
        d.joints.push_back(j);
    }
    return d;
}

enum class Stage { pugixml, reader, open, translate };

// What one child reports.
struct Figures {
    double wall = 0, cpu = 0, peak_mb = 0;
    unsigned rigid_bodies = 0;
};

Figures measure(Stage stage, const std::string& xml) {
    Figures f;
    const long start_kb = mbx_bench::status_kb("VmRSS:");
    mbx_bench::reset_peak();
    const mbx_bench::Timer t;
    if (stage == Stage::pugixml) {
        pugi::xml_document doc;
        if (!doc.load_file(xml.c_str())) die("pugixml", "cannot parse");
        t.stop(f.wall, f.cpu);
    } else if (stage == Stage::reader) {
        const mbx_files::SimscapeModel m = mbx_files::read_simscape(xml);
        t.stop(f.wall, f.cpu);
    } else {
        const auto adapter = mbx_files::SimscapeAdapter::open(xml);
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

// Each stage in children of its own (best of five: this 2-CPU VM's
// times vary by a fifth from run to run): the floor pays for its
// fresh pages as the reader does, and no stage inherits another's heap.
void run(int instances) {
    char dir[] = "/tmp/mbx_bench_simscape_XXXXXX";
    if (!mkdtemp(dir)) die("bench", "no temporary directory");
    const std::string xml = std::string(dir) + "/export.xml";
    mbx_samples::write_simscape_xml(xml, generate(instances));
    const double mb = double(std::filesystem::file_size(xml)) / 1e6;
    Figures best[4];
    for (int stage = 0; stage < 4; ++stage)
        for (int repeat = 0; repeat < 5; ++repeat) {
            Figures f;
            if (!mbx_bench::in_child([&] { return measure(Stage(stage), xml); }, f)) die("bench", "a stage failed");
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
    std::printf("%d instances, %.1f MB, %u rigid bodies after welds\n", instances, mb, best[3].rigid_bodies);
    std::printf("  %-30s %9s %7s %9s %7s %13s %9s %7s\n", "stage", "wall ms", "ratio", "cpu ms", "ratio", "cpu us/inst",
                "peak MB", "ratio");
    const char* names[] = {"pugixml load_file (floor)", "read_simscape", "SimscapeAdapter::open", "open + mbx_translate"};
    for (int stage = 0; stage < 4; ++stage) {
        const Figures& f = best[stage];
        std::printf("  %-30s %9.1f %7.2f %9.1f %7.2f %13.2f %9.1f %7.2f\n", names[stage], 1e3 * f.wall, f.wall / floor.wall,
                    1e3 * f.cpu, f.cpu / floor.cpu, 1e6 * f.cpu / instances, f.peak_mb, f.peak_mb / floor.peak_mb);
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes;
    for (int k = 1; k < argc; ++k) sizes.push_back(std::atoi(argv[k]));
    if (sizes.empty()) sizes = {1000, 10000};
    for (int n : sizes) run(n);
    return 0;
}
