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

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
volatile double g_sink;

using namespace mbx_stub::build;

// n links of 0.1 m along x; joint k turns about z, y, x in turn.
mbx_stub::Assembly chain(int n) {
    mbx_stub::Assembly a;
    a.name = "chain" + std::to_string(n);
    const mbx_units si{1, 1, 1};
    Builder b(a, a.name, si, si);
    const Mat3 I = Mat3::Identity();
    b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, I, Vec3::Zero(), Vec3::Zero(), box_inertia(1.0, 0.1, 0.1, 0.1));
    const Vec3 axes[3] = {Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitX()};
    std::string prev = "ground";
    for (int k = 0; k < n; ++k) {
        const std::string name = "l" + std::to_string(k);
        const Vec3 at(0.1 * k, 0, 1);
        b.body(name, "Link " + std::to_string(k), 0, 1.0, I, at, at + Vec3(0.05, 0.01, 0), box_inertia(1.0, 0.1, 0.03, 0.02));
        b.joint("j" + std::to_string(k), prev, name, at, I, {revolute(axes[k % 3])}, MBX_FRAME_IN_WORLD,
                MBX_FRAME_IN_WORLD);
        prev = name;
    }
    return a;
}

struct MjDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
    void operator()(mjData* d) const { mj_deleteData(d); }
};

// Both engines' models of one translated assembly, and the map from mbx's
// velocity coordinates to MuJoCo's (hinges and slides; other kinds stay at rest).
struct Case {
    std::string label;
    mbx::sim::Model model;
    std::unique_ptr<mjModel, MjDeleter> mm;
    std::unique_ptr<mjData, MjDeleter> md;
    std::vector<int> qpos_of_q, dof_of_v;  // -1: no counterpart
};

std::string read_text(const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

// MuJoCo 2.2's XML parser stops at 100 nested elements, fewer than a chain
// of 100 bodies needs; an <include> is parsed as a document of its own and
// then copied in, so the inner half of the chain goes to a second file.
// `cut` is the body (1-based, in nesting order) whose content moves.
void split_nesting(const std::filesystem::path& dir, const std::string& file, int cut, int bodies) {
    const std::string xml = read_text(dir / file);
    size_t open = 0;
    for (int k = 0; k < cut; ++k) open = xml.find("<body", open) + 1;
    const size_t begin = xml.find('>', open) + 1;
    size_t close = 0;
    for (int k = 0; k < bodies + 1 - cut; ++k) close = xml.find("</body>", close) + 1;
    const size_t end = close - 1;
    if (open == 0 || close == 0 || end < begin) throw std::runtime_error("cannot split " + file);
    std::ofstream(dir / ("inner_" + file)) << "<mujoco>" << xml.substr(begin, end - begin) << "</mujoco>\n";
    std::ofstream(dir / file) << xml.substr(0, begin) << "<include file=\"inner_" << file << "\"/>" << xml.substr(end);
}

Case make_case(const std::string& label, mbx_stub::Assembly assembly, const std::filesystem::path& dir) {
    Case c;
    c.label = label;
    mbx_stub::Host host(std::move(assembly));
    mbx::Progress progress(nullptr, nullptr);
    mbx::Findings findings;
    mbx::Assembly a = mbx::read_host(host.table(), mbx::HostReadOptions{}, progress, findings);
    auto m = mbx::translate_assembly(std::move(a), std::move(findings), mbx::TranslateOptions{}, progress);
    c.model = mbx::sim::build_model(*m);
    std::vector<std::vector<mbx::Mesh>> shapes(m->bodies.size());
    for (size_t b = 0; b < m->bodies.size(); ++b) shapes[b] = mbx::load_body_shapes(*host.table(), *m, int(b));
    const mbx::BodyShapes fetch = [&shapes](int b) -> const std::vector<mbx::Mesh>& { return shapes[size_t(b)]; };
    mbx::ExportSettings settings;
    settings.model_name = "bench";
    mbx::ExportModel em(*m, fetch, settings);
    const mbx::MjcfLayout layout = mbx::build_mjcf_layout(em);
    const std::filesystem::path out = dir / label;
    mbx::write_output_files(out.string(), mbx::export_files(em, MBX_EXPORT_MJCF));
    const int bodies = int(m->bodies.size()) - 1;
    if (bodies > 90) split_nesting(out / "mjcf", "bench.xml", bodies / 2, bodies);
    char error[1024] = "";
    c.mm.reset(mj_loadXML((out / "mjcf/bench.xml").c_str(), nullptr, error, sizeof error));
    if (!c.mm) throw std::runtime_error(label + ": MuJoCo refused the export: " + error);
    c.md.reset(mj_makeData(c.mm.get()));
    c.qpos_of_q.assign(size_t(c.model.nq), -1);
    c.dof_of_v.assign(size_t(c.model.nv), -1);
    for (const auto& j : c.model.joints) {
        if (j.source < 0 || j.nv() != 1) continue;
        for (const mbx::MjcfBody& b : layout.bodies)
            for (const mbx::MjcfJoint& mj : b.joints)
                if (mj.joint == j.source) {
                    const int id = mj_name2id(c.mm.get(), mjOBJ_JOINT, mj.name.c_str());
                    if (id < 0) continue;
                    c.qpos_of_q[size_t(j.q_index)] = c.mm->jnt_qposadr[id];
                    c.dof_of_v[size_t(j.v_index)] = c.mm->jnt_dofadr[id];
                }
    }
    // Same gravity on both, tilted so that planar loops lying flat move too.
    const Eigen::Vector3d g = 9.81 * Eigen::Vector3d(0.3, -0.5, -0.8).normalized();
    c.model.gravity = g;
    for (int k = 0; k < 3; ++k) c.mm->opt.gravity[k] = g[k];
    c.mm->opt.timestep = 1e-3;
    c.mm->opt.disableflags |= mjDSBL_CONTACT;
    return c;
}

void to_mujoco(Case& c, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    mj_resetData(c.mm.get(), c.md.get());
    for (size_t k = 0; k < c.qpos_of_q.size(); ++k)
        if (c.qpos_of_q[k] >= 0) c.md->qpos[c.qpos_of_q[k]] = q[Eigen::Index(k)];
    for (size_t k = 0; k < c.dof_of_v.size(); ++k)
        if (c.dof_of_v[k] >= 0) c.md->qvel[c.dof_of_v[k]] = v[Eigen::Index(k)];
}

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
