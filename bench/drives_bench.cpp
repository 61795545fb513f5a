// Drive hot paths. (1) Drive descriptions at scale: generated assemblies of
// 1k, 10k and 100k parts get one drive per revolute/prismatic tree joint
// (KRS-784ICS servo on revolutes, RE40-class motor + ball screw on
// prismatics, PD controller, 5-point smooth motion), then load_drive_text and
// resolve_drives are timed apart, best of a few runs, against a bare pugixml
// parse of the same text. Per-drive times at each size show whether cost
// grows linearly. (2) MotionProfile::at on a long smooth profile and
// DriveController::update in three forms, per call, against an inline clamped
// PD law (the floor of a controller step).
//
//   bench_drives [max_parts]   (default 100000)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "core/assembly/host_reader.h"
#include "core/mechatronics/drive.h"
#include "core/mechatronics/drive_controller.h"
#include "core/mechatronics/drive_file.h"
#include "apps/stub_host/assemblies/stub_assembly.h"
#include "core/translator/translate.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

const char* const kServo = "628F99AAAA7444D5A2A36A6FA1175594";      // KRS-784ICS
const char* const kRe40 = "5B0E3C1F7A2D4E8C9F61A4B2C3D5E7F9";       // RE40-class 150 W 48 V
const char* const kBallScrew = "3E8F2A1B6C4D4E9F8A7B0C1D2E3F4A5B";  // Ball screw 16x5

// One drive per prismatic/revolute tree joint of `m`, keyed by constraint id
// and primitive index (universal joints are two revolutes of one constraint).
std::string drive_text(const mbx::Mechanism& m, size_t& drives, size_t& prismatics) {
    std::string t = "<?xml version=\"1.0\"?>\n<mechatronics version=\"1\">\n  <library file=\"" MBX_SOURCE_DIR
                    "/samples/library/mbx_object_library.xml\"/>\n";
    drives = prismatics = 0;
    char buf[768];
    for (const mbx::Joint& j : m.joints) {
        const bool linear = j.type == MBX_PRIMITIVE_PRISMATIC;
        if (j.cut || j.constraint < 0 || !(linear || j.type == MBX_PRIMITIVE_REVOLUTE)) continue;
        const double a = double(int(drives % 90) - 45);  // deg or mm, varied so the text is not one line repeated
        std::snprintf(buf, sizeof buf,
                      "  <drive constraint=\"%s\" primitive=\"%d\" motor=\"%s\"%s%s%s>\n"
                      "    <amplifier mode=\"voltage\"/>\n"
                      "    <controller kp=\"%g\" kd=\"%g\" output_limit=\"%g\"/>\n"
                      "    <motion interpolation=\"smooth\" unit=\"%s\">\n"
                      "      <point t=\"0\" q=\"0\"/> <point t=\"0.5\" q=\"0\"/> <point t=\"1.5\" q=\"%g\"/>"
                      " <point t=\"3\" q=\"%g\"/> <point t=\"4\" q=\"0\"/>\n"
                      "    </motion>\n  </drive>\n",
                      m.assembly.constraints[size_t(j.constraint)].id.c_str(), j.primitive_index,
                      linear ? kRe40 : kServo, linear ? " transmission=\"" : "", linear ? kBallScrew : "",
                      linear ? "\"" : "", linear ? 160.0 : 50.0, linear ? 0.0 : 0.1, linear ? 10.0 : 8.0,
                      linear ? "mm" : "deg", a, a / 2);
        t += buf;
        ++drives;
        prismatics += linear;
    }
    return t + "</mechatronics>\n";
}

volatile double g_sink;  // keeps the timed loops from being optimised away

template <class F>
double ns_per_call(size_t calls, F f) {
    double best = 1e30;
    for (int run = 0; run < 5; ++run) {
        double sum = 0;
        const auto t0 = Clock::now();
        for (size_t i = 0; i < calls; ++i) sum += f(i);
        best = std::min(best, since(t0));
        g_sink = sum;
    }
    return best * 1e9 / double(calls);
}

}  // namespace

int main(int argc, char** argv) {
    const size_t max_parts = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 100000;

    std::printf("== drive descriptions (best of runs; us/drive = load + resolve)\n");
    std::printf("%7s %7s %5s %8s | %9s %9s %9s | %9s %9s %9s | %7s\n", "parts", "drives", "pri", "text MB",
                "pugixml", "load ms", "resolve", "load us/d", "res us/d", "total us", "load/pugi");
    std::vector<double> load_per, resolve_per;
    for (size_t n : {1000u, 10000u, 100000u}) {
        if (n > max_parts) continue;
        mbx_stub::Host host(mbx_stub::generate_assembly(n, 42));
        mbx::Progress progress(nullptr, nullptr);
        mbx::Findings findings;
        mbx::Assembly assembly = mbx::read_host(host.table(), mbx::HostReadOptions{}, progress, findings);
        const auto m =
            mbx::translate_assembly(std::move(assembly), std::move(findings), mbx::TranslateOptions{}, progress);
        size_t drives = 0, prismatics = 0;
        const std::string text = drive_text(*m, drives, prismatics);

        const int runs = n >= 100000 ? 3 : 7;
        double parse_s = 1e30, load_s = 1e30, resolve_s = 1e30;
        for (int run = 0; run < runs; ++run) {
            {
                pugi::xml_document doc;
                const auto t0 = Clock::now();
                const bool ok = doc.load_buffer(text.data(), text.size(), pugi::parse_default);
                parse_s = std::min(parse_s, since(t0));
                if (!ok) return std::fprintf(stderr, "pugixml cannot parse the drive text\n"), 1;
            }
            mbx::MechatronicSpec spec;
            std::vector<mbx::DriveError> errors;
            auto t0 = Clock::now();
            mbx::load_drive_text(text, "bench_drives.xml", "", spec, errors);
            load_s = std::min(load_s, since(t0));
            t0 = Clock::now();
            const std::vector<mbx::Drive> resolved = mbx::resolve_drives(spec, *m, errors);
            resolve_s = std::min(resolve_s, since(t0));
            if (!errors.empty() || !spec.library.ok() || resolved.size() != drives) {
                std::fprintf(stderr, "%zu parts: %zu of %zu drives resolved, %zu errors%s%s\n", n, resolved.size(),
                             drives, errors.size(), errors.empty() ? "" : "; first: ",
                             errors.empty() ? "" : errors.front().text().c_str());
                return 1;
            }
        }
        const double d = double(drives);
        load_per.push_back(load_s / d);
        resolve_per.push_back(resolve_s / d);
        std::printf("%7zu %7zu %5zu %8.2f | %9.2f %9.2f %9.2f | %9.3f %9.3f %9.3f | %7.2f\n", n, drives, prismatics,
                    double(text.size()) / 1048576.0, parse_s * 1e3, load_s * 1e3, resolve_s * 1e3, load_s / d * 1e6,
                    resolve_s / d * 1e6, (load_s + resolve_s) / d * 1e6, load_s / parse_s);
    }
    if (load_per.size() > 1)
        std::printf("per-drive time, largest/smallest assembly (1.0 = linear): load %.2f, resolve %.2f\n",
                    load_per.back() / load_per.front(), resolve_per.back() / resolve_per.front());

    // Motion and controller steps.
    const size_t kCalls = 1u << 20;
    std::mt19937_64 rng(7);
    std::vector<mbx::MotionPoint> points(10000);
    std::uniform_real_distribution<double> value(-1.5, 1.5), dt(0.05, 0.5);
    double t = 0;
    for (mbx::MotionPoint& p : points) p = {t += dt(rng), value(rng)};
    const mbx::MotionProfile profile(points, mbx::Interpolation::Smooth);
    std::uniform_real_distribution<double> when(0, t);
    std::vector<double> times(kCalls), r(kCalls), q(kCalls), qd(kCalls);
    for (size_t i = 0; i < kCalls; ++i) {
        times[i] = when(rng);
        r[i] = value(rng);
        q[i] = value(rng);
        qd[i] = value(rng);
    }
    std::vector<double> sequential(times);
    std::sort(sequential.begin(), sequential.end());

    std::printf("\n== steps (ns per call, best of 5 x %zu calls)\n", kCalls);
    const double at_random = ns_per_call(kCalls, [&](size_t i) { return profile.at(times[i]).position; });
    const double at_sorted = ns_per_call(kCalls, [&](size_t i) { return profile.at(sequential[i]).position; });
    const double kp = 50, kd = 0.1, limit = 8;
    const double pd = ns_per_call(kCalls, [&](size_t i) {
        return std::clamp(kp * (r[i] - q[i]) - kd * qd[i], -limit, limit);
    });
    std::printf("%-62s %8s %9s\n", "", "ns/call", "x PD law");
    auto row = [pd](const char* what, double ns) { std::printf("%-62s %8.2f %9.1f\n", what, ns, ns / pd); };
    row("MotionProfile::at, 10k smooth points, random times", at_random);
    row("MotionProfile::at, 10k smooth points, increasing times", at_sorted);
    row("inline PD law u = clamp(kp(r-q) - kd qd, +-8) (peer)", pd);

    // Inputs are random (|r - q| up to 3), so the controllers saturate with a
    // random sign, as the PD law does. Each update needs a later time than
    // the last (across runs too): a continuous controller steps at 10 kHz,
    // the discrete one is called once per sample (1 kHz), so every call
    // samples -- its dearest case.
    mbx::ControllerSpec continuous_pd;
    continuous_pd.kp = kp;
    continuous_pd.kd = kd;
    continuous_pd.output_limit = limit;
    mbx::ControllerSpec cascade = continuous_pd;
    cascade.ki = 20;
    cascade.kv = 240;
    cascade.kvi = 50;
    cascade.output_limit = 10;
    mbx::ControllerSpec discrete;  // the EMPS rig (docs/mechatronics.md)
    discrete.kp = 160.18;
    discrete.kv = 243.45;
    discrete.sample_period = discrete.delay = 1e-3;
    discrete.output_limit = 10;
    discrete.velocity_estimate = mbx::VelocityEstimate::FilteredDifference;
    const struct {
        const char* what;
        const mbx::ControllerSpec& spec;
        double step;
    } forms[] = {{"DriveController::update, continuous PD", continuous_pd, 1e-4},
                 {"DriveController::update, continuous cascade + integral", cascade, 1e-4},
                 {"DriveController::update, 1 kHz, filtered diff., 1-sample delay", discrete, 1e-3}};
    for (const auto& f : forms) {
        try {
            mbx::DriveController c(f.spec);
            size_t step = 0;
            row(f.what, ns_per_call(kCalls, [&](size_t i) {
                    return c.update(double(step++) * f.step, r[i], q[i], qd[i]);
                }));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s: %s\n", f.what, e.what());
            return 1;
        }
    }
    return 0;
}
