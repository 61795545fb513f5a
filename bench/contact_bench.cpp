// Contact against MuJoCo on the same scene: a pile of N boxes (10 cm, 1 kg)
// dropped in layers onto a ground plane, stepped at 1 ms for a fixed wall
// time by mbx (sim/contact: FCL detection, box manifolds, penalty normal
// force, friction springs, semi-implicit Euler) and by MuJoCo (its default
// soft contact, Euler). Prints steps per second and the ratio (goal >= 0.5).
// Then the real ContactNets cube tosses (../shared/data/measured) rolled out
// as contact calibration does (mbx: Hunt-Crossley, friction spring, Euler at
// 0.1 ms; MuJoCo: its contact at 0.5 ms, the step its published fit used):
// steps per second and wall time per toss, mbx's over MuJoCo's; with --fit,
// the contact calibration of the tests (12 training, 45 validation tosses).
//
//   bench_contact [seconds_per_run] [--fit]   (default 0.5)
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "calibration/simulation/contact_fit.h"
#include "tests/contact/contact_scenes.h"
#include "tests/contact/cube_tosses.h"
#include "host_adapters/memory/memory_host.h"
#include "core/assembly/host_reader.h"
#include "core/progress.h"
#include "sim/build_model.h"
#include "sim/contact/contact_step.h"
#include "core/translator/translate.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr double kSide = 0.1, kMass = 1.0;

// Box k of the pile: a 4 x 4 grid per layer, 2 mm gaps, each layer 12 cm up.
Eigen::Vector3d place(int k) {
    const int layer = k / 16, i = (k % 16) / 4, j = k % 4;
    return Eigen::Vector3d((i - 1.5) * (kSide + 0.002), (j - 1.5) * (kSide + 0.002), kSide / 2 + 0.001 + layer * 0.12);
}

double mbx_rate(int n, double seconds) {
    std::vector<mbx_test::FreePart> parts;
    for (int k = 0; k < n; ++k) parts.push_back({kMass, mbx_stub::build::box_inertia(kMass, kSide, kSide, kSide), place(k)});
    mbx_memory::Assembly a = mbx_test::free_parts("pile", parts);
    mbx_memory::Host host(std::move(a));
    mbx::Progress progress(nullptr, nullptr);
    mbx::Findings findings;
    mbx::Assembly assembly = mbx::read_host(host.table(), mbx::HostReadOptions{}, progress, findings);
    auto mech = mbx::translate_assembly(std::move(assembly), std::move(findings), mbx::TranslateOptions{}, progress);
    const mbx::sim::Model model = mbx::sim::build_model(*mech);
    std::vector<mbx::sim::contact::Shape> shapes{mbx_test::ground_plane()};
    for (int body = 1; body < model.body_count(); ++body) shapes.push_back(mbx_test::box_shape(body, kSide));
    // Per-corner springs sized so that the explicit step stays stable at
    // 1 ms for the box's rocking and twisting modes too (their damping, four
    // corners at the half side, is what limits the step): half-critical.
    const mbx::sim::contact::ContactSettings cs = mbx_test::corner_contact(kMass, 5e4, 1e4, 0.5);
    mbx::sim::contact::ContactWorld world(model, shapes, cs);
    mbx::sim::Data d(model);
    d.q = model.q_reference;
    mbx::sim::IntegratorSettings settings;
    settings.kind = mbx::sim::IntegratorKind::Euler, settings.step = 1e-3;
    long steps = 0;
    const auto t0 = Clock::now();
    while (since(t0) < seconds) {
        for (int k = 0; k < 50; ++k) world.step(model, d, settings);
        steps += 50;
    }
    const double rate = double(steps) / since(t0);
    // A sanity figure beside the speed: where the boxes ended up (a pile
    // that exploded or sank would be fast for the wrong reason).
    double low = 1e9, high = -1e9;
    for (int j = 0; j < int(model.joints.size()); ++j) {
        const double z = d.q[model.joints[size_t(j)].q_index + 2];
        low = std::min(low, z), high = std::max(high, z);
    }
    std::printf("        mbx after %.2f s of simulated time: box centres from z = %.4f to %.4f m (q0 %s)\n", steps * 1e-3, low, high,
                [&] { std::ostringstream o; o << d.q.head<7>().transpose(); return o.str(); }().c_str());
    return rate;
}

double mujoco_rate(int n, double seconds) {
    std::ostringstream x;
    x << "<mujoco><option timestep=\"0.001\" integrator=\"Euler\"/><size nconmax=\"1000\" njmax=\"5000\"/><worldbody>"
      << "<geom type=\"plane\" size=\"0 0 1\" friction=\"0.5 0.005 0.0001\"/>";
    for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d p = place(k);
        x << "<body pos=\"" << p.x() << " " << p.y() << " " << p.z() << "\"><freejoint/>"
          << "<geom type=\"box\" size=\"0.05 0.05 0.05\" mass=\"" << kMass << "\" friction=\"0.5 0.005 0.0001\"/></body>";
    }
    x << "</worldbody></mujoco>";
    char error[1000] = "";
    mjVFS vfs;
    mj_defaultVFS(&vfs);
    const std::string text = x.str();
    mj_makeEmptyFileVFS(&vfs, "pile.xml", int(text.size()));
    std::memcpy(vfs.filedata[vfs.nfile - 1], text.data(), text.size());
    mjModel* m = mj_loadXML("pile.xml", &vfs, error, sizeof error);
    mj_deleteVFS(&vfs);
    if (!m) {
        std::fprintf(stderr, "MuJoCo: %s\n", error);
        std::exit(1);
    }
    mjData* d = mj_makeData(m);
    long steps = 0;
    const auto t0 = Clock::now();
    while (since(t0) < seconds) {
        for (int k = 0; k < 50; ++k) mj_step(m, d);
        steps += 50;
    }
    const double rate = double(steps) / since(t0);
    mj_deleteData(d);
    mj_deleteModel(m);
    return rate;
}

// Every tenth toss rolled out until `seconds` of wall time have passed, by
// mbx and by MuJoCo with the published fit's contact: steps per second and
// seconds per toss of each.
void cube_tosses(double seconds, bool fit) {
    using mbx::calibration::PoseRecord;
    const std::vector<PoseRecord> all = mbx::calibration::read_pose_records(mbx_test::cube_tosses_path());
    std::vector<PoseRecord> tosses, training, validation;
    for (const PoseRecord& r : all) {
        if (r.trial % 10 == 0) tosses.push_back(r);
        if (r.trial % 50 == 0) training.push_back(r);
        else if (r.trial % 10 == 0) validation.push_back(r);
    }
    const mbx_test::CubeScene cube;
    mbx::calibration::ContactModel nominal;
    nominal.settings = mbx_test::nominal_cube_contact();
    auto mj = mbx_test::mujoco_cube("solref=\"-3294 -45.1\" friction=\"0.218 0.005 0.0001\"");
    auto rate = [&](auto&& roll, double step) {
        long rolled = 0;
        double simulated = 0;
        const auto t0 = Clock::now();
        while (since(t0) < seconds)
            for (const PoseRecord& r : tosses) {
                roll(r);
                ++rolled, simulated += r.samples.back().t - r.samples.front().t;
                if (since(t0) >= seconds) break;
            }
        const double wall = since(t0);
        return std::pair<double, double>(simulated / step / wall, wall / double(rolled));
    };
    const auto a = rate([&](const PoseRecord& r) { mbx::calibration::roll_out(cube.scene, nominal, r); }, cube.scene.integrator.step);
    const auto b = rate([&](const PoseRecord& r) { mbx_test::mujoco_toss_error(mj.get(), r); }, mj->opt.timestep);
    std::printf("\nContactNets cube tosses (ratio = mbx / MuJoCo)\n");
    std::printf("%18s | %12s %12s %6s\n", "", "mbx", "MuJoCo", "ratio");
    std::printf("%18s | %12.0f %12.0f %6.2f\n", "steps/s", a.first, b.first, a.first / b.first);
    // The per-toss ratio is the one a calibration feels: speed (MuJoCo's
    // time over mbx's), each at the step its contact needs.
    std::printf("%18s | %12.2f %12.2f %6.2f   (steps: mbx %.2f ms, MuJoCo %.2f ms)\n", "ms per toss",
                a.second * 1e3, b.second * 1e3, b.second / a.second, cube.scene.integrator.step * 1e3,
                mj->opt.timestep * 1e3);
    if (!fit) return;
    mbx::calibration::ContactModel start = nominal;
    start.settings.normal.damping = mbx::sim::contact::damping_for_restitution(start.settings.normal, mbx_test::kCubeMass / 4, 1.0, 0.5);
    start.settings.friction.mu_static = start.settings.friction.mu_kinetic = 0.5;
    const auto t0 = Clock::now();
    const auto result = mbx::calibration::fit_contact(cube.scene, start, training, validation);
    std::printf("contact calibration (%zu training, %zu validation tosses): %.1f s wall, %d toss rollouts, %zu causes named\n",
                training.size(), validation.size(), since(t0), result.rollouts, result.steps.size());
}

}  // namespace

int main(int argc, char** argv) {
    const double seconds = argc > 1 && argv[1][0] != '-' ? std::atof(argv[1]) : 0.5;
    bool fit = false;
    for (int k = 1; k < argc; ++k) fit = fit || std::string(argv[k]) == "--fit";
    std::printf("a pile of boxes on a plane, 1 ms steps (ratio = mbx / MuJoCo; goal >= 0.5)\n");
    std::printf("%6s | %12s %12s %6s\n", "boxes", "mbx steps/s", "MuJoCo", "ratio");
    for (int n : {1, 16, 64}) {
        const double a = mbx_rate(n, seconds), b = mujoco_rate(n, seconds);
        std::printf("%6d | %12.0f %12.0f %6.2f\n", n, a, b, a / b);
    }
    cube_tosses(seconds, fit);
    return 0;
}
