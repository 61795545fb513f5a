// The embedded simulator against MuJoCo on the same mechanism. (1) Steps per
// second at a 1 ms fixed step, RK4 and Euler, for serial chains of 7, 30 and
// 100 revolute bodies (axes turning z, y, x so the chain is spatial) and the
// built-ins (loops: fourbar, double_cardan, planar_sixbar; the six_axis_arm
// tree): mbx steps its own simulation model (sim::fixed_step, loops closed
// after each step), MuJoCo steps mbx's MJCF export of the same translation
// (mj_step, contacts off: neither side has any), both from the assembly pose
// at rest under the same tilted gravity, each for a fixed wall time. Per-body
// step time of the 100-body chain over the 7-body one shows whether cost
// grows linearly. (2) Microseconds per call of the dynamics algorithms on the
// 7-body chain (7 DoF) at a random state, next to MuJoCo's nearest call.
// Published anchors at 7 DoF: Pinocchio without code generation ~1 us RNEA,
// ~3 us ABA.
//
//   bench_sim [seconds_per_run] [model] [rk4|euler]   (default 0.3 s, every
//   model, both integrators; one integrator alone is for profiling)
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "core/assembly/host_reader.h"
#include "core/assembly/shape_loader.h"
#include "apps/stub_host/assemblies/builder.h"
#include "export/common/export_model.h"
#include "export/common/names.h"
#include "export/export_files.h"
#include "export/mjcf/mjcf_layout.h"
#include "sim/build_model.h"
#include "sim/integrator.h"
#include "apps/stub_host/assemblies/stub_assembly.h"
#include "core/translator/translate.h"
#include "mujoco_case.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
volatile double g_sink;

using namespace mbx_bench;

// Steps per second of each engine from the assembly pose at rest; the
// state restarts every 1000 steps so long runs stay in the same regime. The
// engines take turns in five slices and each keeps its best slice, so that
// other load on the machine hits both alike and is mostly filtered out.
struct Rates {
    double mbx = 0, mujoco = 0;
    double ratio() const { return mujoco > 0 ? mbx / mujoco : 0; }  // 0: not run
};
Rates step_rates(Case& c, mbx::sim::IntegratorKind kind, double seconds) {
    if (seconds <= 0) return {};
    const long long restart = 1000;
    const int slices = 5;
    Rates r;
    mbx::sim::IntegratorSettings settings;
    settings.kind = kind;
    settings.step = 1e-3;
    mbx::sim::Data d(c.model);
    const Eigen::VectorXd q0 = d.q, v0 = d.v;
    c.mm->opt.integrator = kind == mbx::sim::IntegratorKind::RK4 ? mjINT_RK4 : mjINT_EULER;
    long long mbx_steps = 0, mj_steps = 0;
    for (int slice = 0; slice < slices; ++slice) {
        long long n = 0;
        auto t0 = Clock::now();
        do {
            for (int k = 0; k < 100; ++k, ++n, ++mbx_steps) {
                if (mbx_steps % restart == 0) d.q = q0, d.v = v0, d.time = 0;
                mbx::sim::fixed_step(c.model, d, settings);
            }
        } while (since(t0) < seconds / slices);
        r.mbx = std::max(r.mbx, double(n) / since(t0));
        n = 0;
        t0 = Clock::now();
        do {
            for (int k = 0; k < 100; ++k, ++n, ++mj_steps) {
                if (mj_steps % restart == 0) to_mujoco(c, q0, v0);
                mj_step(c.mm.get(), c.md.get());
            }
        } while (since(t0) < seconds / slices);
        r.mujoco = std::max(r.mujoco, double(n) / since(t0));
    }
    return r;
}

// Best-of-5 microseconds per call of f.
template <class F> double us_per_call(double seconds, F f) {
    long long calls = 1;
    for (auto t0 = Clock::now(); since(t0) < seconds / 10; calls *= 2)
        for (long long i = 0; i < calls; ++i) f();
    double best = 1e30;
    for (int run = 0; run < 5; ++run) {
        const auto t0 = Clock::now();
        for (long long i = 0; i < calls; ++i) f();
        best = std::min(best, since(t0) / double(calls));
    }
    return best * 1e6;
}

// Microseconds per dynamics call on the 7-DoF chain at a random state.
void per_call(Case& c, double seconds) {
    // Per call on the 7-DoF chain at a random state.
    mbx::sim::Data d(c.model);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int k = 0; k < c.model.nv; ++k) d.q[k] = u(rng), d.v[k] = 2 * u(rng), d.qfrc_total[k] = u(rng);
    Eigen::VectorXd qacc = Eigen::VectorXd::Zero(c.model.nv), tau(c.model.nv);
    for (int k = 0; k < c.model.nv; ++k) qacc[k] = u(rng);
    to_mujoco(c, d.q, d.v);
    mjModel* mm = c.mm.get();
    mjData* md = c.md.get();
    for (int k = 0; k < c.model.nv; ++k) md->qfrc_applied[c.dof_of_v[size_t(k)]] = d.qfrc_total[k];
    mj_forward(mm, md);
    for (int k = 0; k < c.model.nv; ++k) md->qacc[c.dof_of_v[size_t(k)]] = qacc[k];
    std::vector<mjtNum> rne(size_t(mm->nv));
    const double t = seconds / 2;
    mbx::sim::update_kinematics(c.model, d);
    const double rnea = us_per_call(t, [&] { mbx::sim::inverse_dynamics(c.model, d, qacc, tau); g_sink = tau[0]; });
    const double mj_rnea = us_per_call(t, [&] { mj_rne(mm, md, 1, rne.data()); g_sink = rne[0]; });
    const double rnea_k = us_per_call(t, [&] {
        mbx::sim::update_kinematics(c.model, d);
        mbx::sim::inverse_dynamics(c.model, d, qacc, tau);
        g_sink = tau[0];
    });
    const double mj_rnea_k = us_per_call(t, [&] {
        mj_kinematics(mm, md);
        mj_comPos(mm, md);
        mj_comVel(mm, md);
        mj_rne(mm, md, 1, rne.data());
        g_sink = rne[0];
    });
    const double aba = us_per_call(t, [&] { mbx::sim::articulated_body(c.model, d, d.qfrc_total, d.qacc); g_sink = d.qacc[0]; });
    const double crba = us_per_call(t, [&] { mbx::sim::mass_matrix(c.model, d); g_sink = d.M(0, 0); });
    const double mj_crba = us_per_call(t, [&] { mj_crb(mm, md); g_sink = md->qM[0]; });
    const double mj_crba_f = us_per_call(t, [&] { mj_crb(mm, md); mj_factorM(mm, md); g_sink = md->qLD[0]; });
    const double fd = us_per_call(t, [&] { mbx::sim::forward_dynamics(c.model, d); g_sink = d.qacc[0]; });
    const double mj_fd = us_per_call(t, [&] { mj_forward(mm, md); g_sink = md->qacc[0]; });
    std::printf("microseconds per call, 7-DoF chain (anchors: Pinocchio without code generation ~1 RNEA, ~3 ABA)\n");
    std::printf("%-44s %8s | %-40s %8s %6s\n", "mbx", "us", "MuJoCo", "us", "ratio");
    auto row = [](const char* a, double x, const char* b, double y) {
        std::printf("%-44s %8.3f | %-40s %8.3f %6.2f\n", a, x, b, y, x / y);
    };
    row("inverse_dynamics (RNEA)", rnea, "mj_rne", mj_rnea);
    row("update_kinematics + inverse_dynamics", rnea_k, "mj_kinematics+comPos+comVel+rne", mj_rnea_k);
    row("mass_matrix (CRBA)", crba, "mj_crb", mj_crba);
    row("mass_matrix (CRBA)", crba, "mj_crb + mj_factorM", mj_crba_f);
    row("articulated_body (ABA, kinematics done)", aba, "mj_forward", mj_fd);
    row("forward_dynamics (kinematics + ABA)", fd, "mj_forward", mj_fd);
}

}  // namespace

int main(int argc, char** argv) {
    const double seconds = argc > 1 ? std::atof(argv[1]) : 0.3;
    const std::string only = argc > 2 ? argv[2] : "";
    const std::string integrator = argc > 3 ? argv[3] : "";
    if (!integrator.empty() && integrator != "rk4" && integrator != "euler") {
        std::fprintf(stderr, "bench_sim: integrator is rk4 or euler, not '%s'\n", integrator.c_str());
        return 2;
    }
    const double rk4_seconds = integrator == "euler" ? 0 : seconds, euler_seconds = integrator == "rk4" ? 0 : seconds;
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("mbx_bench_sim_" + std::to_string(::getpid()));
    try {
        std::vector<std::pair<std::string, mbx_stub::Assembly>> inputs;
        for (int n : {7, 30, 100}) inputs.emplace_back("chain" + std::to_string(n), chain(n));
        for (const char* name : {"six_axis_arm", "fourbar", "double_cardan", "planar_sixbar"}) {
            mbx_stub::Assembly a;
            if (!mbx_stub::builtin_assembly(name, a)) throw std::runtime_error(std::string("no built-in ") + name);
            inputs.emplace_back(name, std::move(a));
        }
        std::vector<Case> cases;
        for (auto& [label, a] : inputs) cases.push_back(make_case(label, std::move(a), dir));

        std::printf("steps per second at a 1 ms step (ratio = mbx / MuJoCo; %.2f s of wall time per engine and "
                    "integrator, best of 5 interleaved slices)\n", seconds);
        std::printf("%-14s %4s %5s | %10s %10s %6s | %10s %10s %6s\n", "model", "nv", "loops", "rk4 mbx", "mujoco",
                    "ratio", "euler mbx", "mujoco", "ratio");
        double per_body_first = 0, per_body_last = 0;
        for (Case& c : cases) {
            if (!only.empty() && c.label != only) continue;
            const Rates rk4 = step_rates(c, mbx::sim::IntegratorKind::RK4, rk4_seconds);
            const Rates euler = step_rates(c, mbx::sim::IntegratorKind::Euler, euler_seconds);
            std::printf("%-14s %4d %5zu | %10.0f %10.0f %6.2f | %10.0f %10.0f %6.2f\n", c.label.c_str(), c.model.nv,
                        c.model.closures.size(), rk4.mbx, rk4.mujoco, rk4.ratio(), euler.mbx, euler.mujoco,
                        euler.ratio());
            const double per_body = rk4.mbx > 0 ? 1.0 / (rk4.mbx * (c.model.body_count() - 1)) : 0;
            if (c.label == "chain7") per_body_first = per_body;
            if (c.label == "chain100") per_body_last = per_body;
        }
        if (per_body_first > 0 && per_body_last > 0)
            std::printf("per-body RK4 step time, chain100 / chain7 (1.0 = linear): %.2f\n", per_body_last / per_body_first);
        std::printf("\n");
        if ((only.empty() || only == "chain7") && integrator.empty()) per_call(cases[0], seconds);

    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_sim failed: %s\n", e.what());
        std::filesystem::remove_all(dir);
        return 1;
    }
    std::filesystem::remove_all(dir);
    return 0;
}
