// The excitation design's wall time (calibration/excitation): a two-link
// chain, the four-bar (its crank actuated, the loop closed at every sample)
// and a 7-DoF chain, 6 harmonics, a 10 s period, the default causes and the
// default search (2400 evaluations of the criterion in four searches). Its peer is MuJoCo computing inverse
// dynamics (mj_inverse) at every 1 kHz sample of the designed record, on
// mbx's MJCF export of the same translation: the design costs that many of
// MuJoCo's passes along the motion it designs. The predicted standard errors'
// gain over a random multi-sine within the same limits is printed beside it.
//
//   bench_excitation [evaluations]   (default: the design's, 2400)
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "calibration/excitation/excitation.h"
#include "mujoco_case.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
volatile double g_sink;

}  // namespace

int main(int argc, char** argv) {
    using namespace mbx_bench;
    namespace cal = mbx::calibration;
    const int evaluations = argc > 1 ? std::max(1, std::atoi(argv[1])) : cal::ExcitationOptions{}.evaluations;
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("mbx_bench_excitation_" + std::to_string(::getpid()));
    try {
        std::vector<std::pair<std::string, mbx_stub::Assembly>> inputs;
        inputs.emplace_back("chain2", chain(2));
        mbx_stub::Assembly fourbar;
        if (!mbx_stub::builtin_assembly("fourbar", fourbar)) throw std::runtime_error("no built-in fourbar");
        inputs.emplace_back("fourbar", std::move(fourbar));
        inputs.emplace_back("chain7", chain(7));
        std::printf("excitation design: 6 harmonics, 10 s period, 2 periods, %d evaluations; peer: MuJoCo's mj_inverse at "
                    "every 1 kHz sample of the design\n",
                    evaluations);
        std::printf("%-8s %3s %6s | %9s %11s %8s | %12s %9s\n", "model", "nv", "params", "design s", "mujoco ms", "ratio",
                    "criterion", "gain");
        for (auto& [label, assembly] : inputs) {
            Case c = make_case(label, std::move(assembly), dir);
            // The actuated coordinates: every joint of a chain, the first
            // (the crank) of the four-bar.
            std::vector<int> dofs;
            for (const auto& j : c.model.joints)
                if (j.nv() == 1 && (label != "fourbar" || dofs.empty())) dofs.push_back(j.v_index);
            std::vector<cal::ExcitationLimits> limits(dofs.size());
            for (cal::ExcitationLimits& L : limits) L.lower = -1, L.upper = 1, L.velocity = 3, L.acceleration = 30, L.effort = 50;
            cal::ExcitationOptions o;
            o.harmonics = 6, o.period = 10, o.periods = 2, o.evaluations = evaluations;
            const auto t0 = Clock::now();
            const cal::ExcitationDesign d = cal::design_excitation(c.model, dofs, limits, o);
            const double design = since(t0);

            // MuJoCo: inverse dynamics at every 1 kHz sample of the design.
            const cal::SampledMotion mo = cal::sample_design(d, 1000);
            mjModel* mm = c.mm.get();
            mjData* md = c.md.get();
            const auto t1 = Clock::now();
            for (size_t k = 0; k < mo.t.size(); ++k) {
                for (size_t i = 0; i < dofs.size(); ++i) {
                    const auto& j = c.model.joints[size_t(c.model.dof_joint[size_t(dofs[i])])];
                    if (c.qpos_of_q[size_t(j.q_index)] >= 0) md->qpos[c.qpos_of_q[size_t(j.q_index)]] = mo.q(Eigen::Index(k), Eigen::Index(i));
                    if (c.dof_of_v[size_t(dofs[i])] >= 0) {
                        md->qvel[c.dof_of_v[size_t(dofs[i])]] = mo.qd(Eigen::Index(k), Eigen::Index(i));
                        md->qacc[c.dof_of_v[size_t(dofs[i])]] = mo.qdd(Eigen::Index(k), Eigen::Index(i));
                    }
                }
                mj_inverse(mm, md);
                g_sink = md->qfrc_inverse[0];
            }
            const double mujoco = since(t1);
            const double gain = std::pow(10.0, d.reference.criterion - d.predicted.criterion);
            std::printf("%-8s %3zu %6zu | %9.2f %11.2f %8.0f | %12.3f %8.2fx\n", label.c_str(), dofs.size(),
                        d.predicted.names.size(), design, 1e3 * mujoco, design / mujoco, d.predicted.criterion, gain);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_excitation: %s\n", e.what());
        std::filesystem::remove_all(dir);
        return 1;
    }
    std::filesystem::remove_all(dir);
    std::printf("(gain: the geometric mean of the predicted standard errors along a random multi-sine within the same "
                "limits over the design's)\n");
    return 0;
}
