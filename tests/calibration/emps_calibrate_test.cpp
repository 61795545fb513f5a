// The whole loop on the EMPS rig (../shared/data/measured/emps): from the
// naive model (the rig's drive and controller, no friction) the calibration
// names friction and the offset, writes them into the joint's dynamics and
// replays both records in closed loop through the rig's own controller.
// The figures: closed-loop force error <= 7 % on the training
// record and <= 10 % on the test record (the rig's authors published
// 5.85 % and 8.94 % for their simulation; the naive model is about 70 % off).
#include <doctest/doctest.h>

#include "calibration/calibrate.h"
#include "tests/export/drives_support.h"
#include "tests/export/export_fixture.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::calibration;

TEST_CASE("calibration: EMPS closed-loop replay before and after calibration") {
    auto t = xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/emps_axis/emps_axis.xml");
    const Mechanism& mech = *t->mechanism;
    sim::BuildOptions base;
    base.drives = xtest::resolve_drive_file(mech, std::string(MBX_SAMPLES_DIR) + "/mechatronics/emps_axis_drives.xml");
    const Experiment e = load_experiment(std::string(MBX_SAMPLES_DIR) + "/calibration/emps.xml");
    int calls = 0;
    CalibrateOptions options;
    options.progress = [&](const char*, double f) {
        CHECK(f >= 0);
        CHECK(f <= 1);
        ++calls;
        return true;
    };
    const CalibrationResult r = calibrate(mech, base, e, options);
    CHECK(calls > 3);
    REQUIRE(r.identification.causes.size() == 3);
    REQUIRE(r.steps.size() == 4);
    const StepErrors& b = r.baseline();
    const StepErrors& f = r.final_step();
    for (const StepErrors& s : r.steps)
        MESSAGE(s.label << ": IDIM " << s.fit_error << " / " << s.validation_error << " %, closed loop " << s.simulated_fit
                        << " / " << s.simulated_validation << " %");
    // One compared signal (the force) per record.
    REQUIRE(b.simulated.size() == 2);
    // The goal (7 % / 10 %), at the figures docs/calibration.md states
    // to their last digit: 69.8 / 66.8 % before, 5.6 / 8.5 % after.
    const char* kStated = "docs/calibration.md's figure, to its last digit";
    CHECK(b.simulated_fit == mbx_test::within(69.8, 0.05, kStated));
    CHECK(b.simulated_validation == mbx_test::within(66.8, 0.05, kStated));
    CHECK(f.simulated_fit <= 7);
    CHECK(f.simulated_validation <= 10);
    CHECK(f.simulated_fit == mbx_test::within(5.6, 0.05, kStated));
    CHECK(f.simulated_validation == mbx_test::within(8.5, 0.05, kStated));
    // Every step makes the replay better.
    for (size_t i = 1; i < r.steps.size(); ++i) CHECK(r.steps[i].simulated_validation < r.steps[i - 1].simulated_validation);

    // The joint now carries what was identified, in the description's terms.
    REQUIRE(r.joints.size() == 1);
    const JointUpdate& u = r.joints[0];
    CHECK(u.constraint_id == "40:-:41");
    CHECK(u.linear);
    CHECK(u.before.damping == 0);
    CHECK(u.after.damping == mbx_test::relative(203.5, 0.15));
    // The dry friction each way of motion, whichever way it was named (an
    // offset shifts both directions alike; the authors' values give 17.23 N
    // forward and 23.55 N backward).
    const double forward = u.after.coulomb + u.after.offset;
    const double backward = (u.after.asymmetric ? u.after.coulomb_negative : u.after.coulomb) - u.after.offset;
    CHECK(forward == mbx_test::relative(20.39 - 3.16, 0.05));
    CHECK(backward == mbx_test::relative(20.39 + 3.16, 0.05));
    CHECK(u.after.coulomb_velocity > 0);
    CHECK(r.unwritten.empty());
    CHECK(r.drives.empty());

    // Plots: a trace per record, measured and both replays, thinned.
    REQUIRE(r.traces.size() == 2);
    for (const Trace& tr : r.traces) {
        CHECK(tr.t.size() > 500);
        CHECK(tr.t.size() <= 1600);
        CHECK(tr.calibrated.size() == tr.t.size());
        CHECK(relative_error(tr.measured, tr.calibrated) < relative_error(tr.measured, tr.baseline));
    }
    REQUIRE(r.residuals.size() == 1);
    // The residual after calibration is what the friction law no longer leaves.
    double before = 0, after = 0;
    for (size_t k = 0; k < r.residuals[0].before.size(); ++k)
        before += r.residuals[0].before[k] * r.residuals[0].before[k], after += r.residuals[0].after[k] * r.residuals[0].after[k];
    CHECK(after < 0.05 * before);
    MESSAGE("wall time " << r.wall_time << " s");
}
}  // namespace MBX_UNITY_ID
