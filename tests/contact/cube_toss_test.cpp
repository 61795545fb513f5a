// The ContactNets cube tosses (../shared/data/measured/contactnets_cube, 570
// real tosses of a 0.1048 m, 0.37 kg wooden cube onto a board, tracked at
// 148 Hz): every toss rolled out from its first measured state, by mbx
// (box manifold on the board, Hunt-Crossley normal force with the authors'
// restitution 0.125, friction spring with their mu 0.18) and in the same run
// by MuJoCo with its default contact and with the parameters a published
// study fitted to these tosses (solref -3294 -45.1, friction 0.218). Scores:
// position error (% of the cube's edge) and rotation error (degrees) over
// each toss, and the final drift of the resting cube.
#include <doctest/doctest.h>

#include "cube_tosses.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::sim::contact;
using namespace mbx_test;
using calibration::PoseRecord;

namespace {

double deepest_corner(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
    double low = 0;
    for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d c = kCubeEdge / 2 * Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1);
        low = std::min(low, (p + q * c).z());
    }
    return -low;
}

}  // namespace

TEST_CASE("contact: the ContactNets cube tosses rolled out by mbx and by MuJoCo, scored against the measured poses") {
    const std::vector<PoseRecord> tosses = calibration::read_pose_records(cube_tosses_path());
    REQUIRE(tosses.size() == 570);
    const CubeScene cube;
    calibration::ContactModel nominal;
    nominal.settings = nominal_cube_contact();
    auto mj_default = mujoco_cube("");
    auto mj_fitted = mujoco_cube("solref=\"-3294 -45.1\" friction=\"0.218 0.005 0.0001\"");

    // Every tenth toss: 57 of them.
    calibration::PoseError mbx_sum, def_sum, fit_sum;
    int n = 0, at_rest = 0, moving_at_end = 0;
    double deepest = 0;
    for (const PoseRecord& toss : tosses) {
        if (toss.trial % 10 != 0) continue;
        const calibration::Rollout a = calibration::roll_out(cube.scene, nominal, toss, 2.0);
        const calibration::PoseError b = mujoco_toss_error(mj_default.get(), toss), c = mujoco_toss_error(mj_fitted.get(), toss);
        REQUIRE_FALSE(a.diverged);
        mbx_sum.position += a.error.position, mbx_sum.rotation += a.error.rotation;
        def_sum.position += b.position, def_sum.rotation += b.rotation;
        fit_sum.position += c.position, fit_sum.rotation += c.rotation;
        // The real cube has stopped by the end of every toss.
        const size_t last = toss.samples.size() - 1;
        moving_at_end += (a.positions[last] - a.positions[last - 1]).norm() /
                             (toss.samples[last].t - toss.samples[last - 1].t) > 0.01;
        at_rest += a.rest_speed < 1e-4 && a.rest_drift < 1e-6;
        for (size_t k = 0; k < a.positions.size(); ++k) deepest = std::max(deepest, deepest_corner(a.positions[k], a.orientations[k]));
        ++n;
    }
    MESSAGE(n << " tosses, mean position error (% of edge) / rotation error (deg): mbx nominal "
              << mbx_sum.position / n << " / " << mbx_sum.rotation / n << "; MuJoCo default " << def_sum.position / n
              << " / " << def_sum.rotation / n << "; MuJoCo fitted (published) " << fit_sum.position / n << " / "
              << fit_sum.rotation / n << "; mbx still moving (> 1 cm/s) where the real cube has stopped in " << moving_at_end
              << ", at rest without drift 1.5-2 s later in " << at_rest << "; deepest corner " << deepest * 1e3 << " mm");
    CHECK(n == 57);
    // A physical rollout: the cube stays on the board (penetration of a
    // stiff contact, millimetres at most); left lying there it comes to rest
    // and the friction spring holds it without drift (< 1 um in 0.5 s).
    CHECK(deepest < 0.005);
    CHECK(at_rest == n);
    // With the authors' nominal parameters, mbx is no worse than MuJoCo's default contact.
    CHECK(mbx_sum.position <= def_sum.position * 1.1);
}
}  // namespace MBX_UNITY_ID
