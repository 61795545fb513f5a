// The EMPS rig (../shared/data/measured/emps) in mbx's own simulator: the
// emps_axis sample's carriage plus the library's motor and ball screw from
// samples/mechatronics/emps_axis_drives.xml, closed by the rig's own discrete
// controller (sim/drive_loop.h) and driven by the rig's recorded reference.
// The same check the MuJoCo test (tests/export/drives_emps_test.cpp) makes:
// with the authors' identified friction as joint dynamics the force is
// reproduced to a few percent, without it the force error is ~70 %.
#include <charconv>
#include <cmath>
#include <fstream>

#include "tests/export/drives_support.h"
#include "tests/common/emps_record.h"
#include "tests/export/export_fixture.h"
#include "sim/build_model.h"
#include "sim/integrator.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using mbx_test::EmpsRecord;
using mbx_test::read_emps;
using mbx_test::relative_error;

namespace {

struct Result {
    double position_error = 0, force_error = 0;  // percent
};

// Closed loop over the record: the drive's target is the recorded reference
// at each 1 ms sample; the simulated force is the drive's effort during it.
Result closed_loop(const sim::Model& model, const EmpsRecord& rec, double offset_effort) {
    sim::Data d(model);
    d.effort[0] = offset_effort;
    sim::IntegratorSettings settings;
    settings.kind = sim::IntegratorKind::RK4;
    settings.step = 0.5e-3;
    std::vector<double> q_sim, force_sim;
    q_sim.reserve(rec.t.size());
    force_sim.reserve(rec.t.size());
    for (size_t k = 0; k < rec.t.size(); ++k) {
        d.drives.target_override[0] = rec.q_ref[k];
        q_sim.push_back(d.q[0]);
        sim::advance(model, d, settings, rec.t[k] + 1e-3);
        force_sim.push_back(d.drives.signals[0].effort);
    }
    return {relative_error(rec.q, q_sim), relative_error(rec.force, force_sim)};
}

}  // namespace

TEST_CASE("sim: the EMPS axis in mbx's simulator reproduces the rig's closed loop") {
    auto t = xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/emps_axis/emps_axis.xml");
    const Mechanism& m = *t->mechanism;
    const std::vector<Drive> drives =
        xtest::resolve_drive_file(m, std::string(MBX_SAMPLES_DIR) + "/mechatronics/emps_axis_drives.xml");
    REQUIRE(drives.size() == 1);
    const EmpsRecord rec = read_emps(mbx_test::shared_data("measured/emps/emps_train.csv"));
    REQUIRE(rec.t.size() == 24841);
    REQUIRE(rec.t[0] == 0);

    sim::BuildOptions without;
    without.drives = drives;
    const sim::Model bare = sim::build_model(m, without);
    REQUIRE(bare.nv == 1);
    // The screw and rotor at the joint: the ~95 kg the rig's authors identified.
    sim::Data d(bare);
    sim::update_positions(bare, d);
    sim::mass_matrix(bare, d);
    CHECK(d.M(0, 0) == mbx_test::relative(95.11, 0.005));

    // The authors' identified friction (NOTES.md, IDIM-LS): viscous 203.5 N s/m,
    // Coulomb 20.39 N (sign smoothed over 0.1 mm/s, as the MuJoCo test does)
    // and a constant offset of -3.16 N, which acts as a constant effort.
    sim::BuildOptions with = without;
    sim::JointDynamics friction;
    friction.damping = 203.5;
    friction.coulomb = 20.39;
    friction.coulomb_velocity = 1e-4;
    with.joint_dynamics[bare.joints[0].source] = friction;
    const sim::Model rig = sim::build_model(m, with);

    const Result r_with = closed_loop(rig, rec, 3.16);
    INFO("with friction: position " << r_with.position_error << " %, force " << r_with.force_error << " %");
    // The authors published 0.0138 % and 5.85 % for their own simulation; MuJoCo's 6.8 %.
    CHECK(r_with.position_error < 0.05);
    CHECK(r_with.force_error < 7.5);  // measured 6.86 %
    const Result r_without = closed_loop(bare, rec, 0);
    INFO("without friction: position " << r_without.position_error << " %, force " << r_without.force_error << " %");
    CHECK(r_without.position_error < 0.5);
    // Friction is what the CAD model misses: 69.9 %, as MuJoCo on the same
    // export (tests/export/drives_emps_test.cpp) gives to three digits.
    CHECK(r_without.force_error > 65);
    CHECK(r_without.force_error < 75);
    CHECK(r_without.force_error > 3 * r_with.force_error);
}
}  // namespace MBX_UNITY_ID
