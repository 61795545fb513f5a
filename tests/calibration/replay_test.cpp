// Replays of measured records in mbx's simulator (calibration/replay.h),
// checked against an analytic free motion and against MuJoCo's motion under
// the recorded effort (records from the hidden-effect generator, which runs
// MuJoCo on mbx's MJCF export).
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "calibration/calibrate.h"
#include "calibration/simulation/model_extension.h"
#include "calibration/simulation/replay.h"
#include "hidden_effects.h"
#include "sim/build_model.h"
#include "sim/dynamics.h"
#include "temp_dir.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::calibration;

namespace {

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// The experiment of a generated case, driven `mode` and comparing positions too.
Experiment with_positions(const mbx_test::GeneratedCase& c, const char* mode) {
    std::string x = read_text(c.experiment_path);
    std::string more;
    for (const std::string& id : c.joint_ids) more += "  <compare joint=\"" + id + "\" quantity=\"position\"/>\n";
    x.replace(x.find("</experiment>"), 13, more + "</experiment>");
    x.replace(x.find("mode=\"effort\""), 13, std::string("mode=\"") + mode + "\"");
    return parse_experiment(x, c.experiment_path);
}

}  // namespace

TEST_CASE("calibration replay: a free slider with damping coasts as the analytic solution") {
    // The EMPS carriage (without the drive's rotor) launched at 0.2 m/s: with damping c, q = q0 + v0 m/c (1 - exp(-c t/m)).
    auto t = mbx_test::open_mechanism("emps_axis");
    const Mechanism& mech = *t->mechanism;
    sim::BuildOptions damped;
    sim::JointDynamics jd;
    jd.damping = 30;
    damped.joint_dynamics[0] = jd;
    const sim::Model model = sim::build_model(mech, damped);
    REQUIRE(model.nv == 1);
    sim::Data d(model);
    sim::update_positions(model, d);
    sim::mass_matrix(model, d);
    const double m = d.M(0, 0);
    mbx_test::TempDir dir("mbx_replay");
    std::string csv = "t,q\n";
    const double v0 = 0.2, q0 = 0.05;
    for (int k = 0; k <= 2000; ++k) {
        const double tk = k * 1e-3;
        char line[96];
        std::snprintf(line, sizeof line, "%.4f,%.12g\n", tk, q0 + v0 * m / jd.damping * (1 - std::exp(-jd.damping * tk / m)));
        csv += line;
    }
    write_text(dir.file("free.csv"), csv);
    const std::string joint = model.joints[0].constraint_id;
    const std::string xml = "<experiment version=\"1\"><record file=\"free.csv\" role=\"fit\"/>"
                            "<record file=\"free.csv\" role=\"validation\"/><time column=\"t\"/>"
                            "<column name=\"q\" joint=\"" + joint + "\" quantity=\"position\" unit=\"m\"/>"
                            "<drive mode=\"free\"/><compare joint=\"" + joint + "\" quantity=\"position\"/></experiment>";
    write_text(dir.file("free.xml"), xml);
    const Experiment e = load_experiment(dir.file("free.xml"));
    const std::vector<Record> records = load_records(e, model);
    const std::vector<ComparedSignal> compared = compared_signals(e, model);
    const std::vector<std::vector<double>> sim = replay(model, e, records[0], compared, ReplayAdjustments(model.nv));
    const std::vector<double>& meas = records[0].find(Quantity::Position, 0)->values;
    const std::vector<double> ref = error_reference(e, records[0], compared[0], meas);
    // The reference is the motion since the start, not the position itself.
    CHECK(ref.front() == 0);
    CHECK(ref.back() == mbx_test::relative(meas.back() - q0, 1e-6));
    // The start velocity comes from the filtered record; the coast follows the law.
    double err = 0, norm = 0;
    for (size_t k = 0; k < meas.size(); ++k) err += std::pow(meas[k] - sim[0][k], 2), norm += ref[k] * ref[k];
    CHECK(100 * std::sqrt(err / norm) < 0.5);
    // Without the damping the carriage coasts on: far off the record.
    const sim::Model undamped = sim::build_model(mech, {});
    const std::vector<std::vector<double>> coast = replay(undamped, e, records[0], compared, ReplayAdjustments(model.nv));
    double err2 = 0;
    for (size_t k = 0; k < meas.size(); ++k) err2 += std::pow(meas[k] - coast[0][k], 2);
    CHECK(100 * std::sqrt(err2 / norm) > 20);
}

TEST_CASE("calibration replay: MuJoCo's arm under its recorded effort, and the gain of a hidden damping") {
    mbx_test::TempDir dir("mbx_replay_arm");
    mbx_test::CaseSpec clean;
    clean.name = "clean", clean.mechanism = "two_link_arm", clean.seed = 7;
    const mbx_test::GeneratedCase cc = mbx_test::generate_case(clean, dir.file("clean"));
    mbx_test::CaseSpec damped = clean;
    damped.name = "damped";
    damped.effects = {{"viscous_friction", "two_link_arm/elbow", 0.15, 0.15}};
    const mbx_test::GeneratedCase dc = mbx_test::generate_case(damped, dir.file("damped"));

    auto t = mbx_test::open_mechanism("two_link_arm");
    const Mechanism& mech = *t->mechanism;

    // Clean: the recorded effort moves mbx's arm as it moved MuJoCo's.
    const Experiment e = with_positions(cc, "effort");
    const CalibrationResult rc = calibrate(mech, {}, e);
    CHECK(rc.identification.causes.empty());
    for (const SignalError& s : rc.baseline().simulated) {
        MESSAGE("clean " << std::string(quantity_name(s.quantity)) << " joint " << s.joint << " record " << s.record << ": " << s.relative << " %");
        // Positions over 0.5 s horizons: a few percent of the motion (noise
        // and quantisation in the start state); efforts: the 1.5 % noise.
        CHECK(s.relative < (s.quantity == Quantity::Position ? 5.0 : 4.0));
    }

    // Damped elbow: named, and both the effort and the motion replays gain.
    const Experiment ed = with_positions(dc, "effort");
    const CalibrationResult rd = calibrate(mech, {}, ed);
    REQUIRE(!rd.identification.causes.empty());
    CHECK(rd.identification.causes[0].candidate.cause == "viscous_friction");
    for (const StepErrors& s : rd.steps) MESSAGE(s.label << ": replay " << s.simulated_fit << " / " << s.simulated_validation << " %");
    CHECK(rd.final_step().simulated_validation < 0.6 * rd.baseline().simulated_validation);
    REQUIRE(rd.joints.size() == 1);
    CHECK(rd.joints[0].name.find("elbow") != std::string::npos);
    CHECK(rd.joints[0].after.damping == mbx_test::relative(0.15, 0.1));
}

TEST_CASE("calibration replay: the four-bar's loops closed along its recorded effort (MuJoCo's motion)") {
    mbx_test::TempDir dir("mbx_replay_fourbar");
    mbx_test::CaseSpec spec;
    spec.name = "fourbar", spec.mechanism = "fourbar", spec.seed = 5;
    spec.effects = {{"viscous_friction", "fourbar/rev_A", 2e-4, 2e-4}};
    const mbx_test::GeneratedCase c = mbx_test::generate_case(spec, dir.file("case"));
    auto t = mbx_test::open_mechanism("fourbar");
    const CalibrationResult r = calibrate(*t->mechanism, {}, with_positions(c, "effort"));
    REQUIRE(!r.identification.causes.empty());
    CHECK(r.identification.causes[0].candidate.cause == "viscous_friction");
    for (const StepErrors& s : r.steps)
        for (const SignalError& e : s.simulated)
            MESSAGE(s.label << " " << std::string(quantity_name(e.quantity)) << " record " << e.record << ": " << e.relative << " %");
    // Efforts by inverse dynamics of the closed chain, positions by the
    // simulator with its loops closed, both better once damped.
    for (size_t k = 0; k < r.final_step().simulated.size(); ++k) {
        const SignalError& before = r.baseline().simulated[k];
        const SignalError& after = r.final_step().simulated[k];
        CHECK(after.relative < before.relative);
        CHECK(after.relative < (after.quantity == Quantity::Position ? 5.0 : 6.0));
    }
}

TEST_CASE("calibration replay: what a mode cannot compare is refused with the file and line") {
    auto t = mbx_test::open_mechanism("two_link_arm");
    const sim::Model model = sim::build_model(*t->mechanism, {});
    const std::string head = "<experiment version=\"1\">\n<record file=\"a.csv\" role=\"fit\"/>\n"
                             "<record file=\"b.csv\" role=\"validation\"/>\n<time column=\"t\"/>\n"
                             "<column name=\"q\" joint=\"two_link_arm/elbow\" quantity=\"position\" unit=\"rad\"/>\n";
    {
        // Closed loop needs a drive to produce the effort.
        const Experiment e = parse_experiment(head + "<drive mode=\"closed_loop\"/>\n"
                                                     "<compare joint=\"two_link_arm/elbow\" quantity=\"effort\"/>\n</experiment>",
                                              "/x/exp.xml");
        try {
            compared_signals(e, model);
            FAIL("accepted");
        } catch (const Error& err) {
            CHECK(std::string(err.what()).find("/x/exp.xml:7") != std::string::npos);
            CHECK(std::string(err.what()).find("no drive") != std::string::npos);
        }
    }
    {
        const Experiment e = parse_experiment(head + "<drive mode=\"free\"/>\n"
                                                     "<compare joint=\"two_link_arm/elbow\" quantity=\"effort\"/>\n</experiment>",
                                              "/x/exp.xml");
        CHECK_THROWS_WITH_AS(compared_signals(e, model), doctest::Contains("free replay"), Error);
    }
    {
        const Experiment e = parse_experiment(head + "<drive mode=\"free\"/>\n"
                                                     "<compare joint=\"nowhere\" quantity=\"position\"/>\n</experiment>",
                                              "/x/exp.xml");
        CHECK_THROWS_WITH_AS(compared_signals(e, model), doctest::Contains("/x/exp.xml:7: no joint 'nowhere'"), Error);
    }
}
}  // namespace MBX_UNITY_ID
