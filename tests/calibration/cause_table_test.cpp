// The table of causes (calibration/cause_table.h): each entry is found by
// its name and id, the catalogue offers exactly the table's causes on their
// subjects, a cause's regression column is its law (checked against the
// records' own speeds, accelerations and efforts), its physical check refuses
// what no such effect can be, and its extension changes the model as the
// cause says, or says why the description file cannot hold it.
#include <doctest/doctest.h>

#include <map>
#include <set>

#include "calibration/cause_table.h"
#include "calibration/identification/identify.h"
#include "calibration/identification/regression_rows.h"
#include "calibration/simulation/model_extension.h"
#include "calibration/simulation/nonlinear_fit.h"
#include "core/finding.h"
#include "hidden_effects.h"
#include "sim/build_model.h"
#include "temp_dir.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::calibration;

namespace {

struct Arm {
    std::unique_ptr<xtest::Translated> opened;
    sim::Model model;
    RegressionRows rows;
};

Arm two_link_arm(const mbx_test::TempDir& dir) {
    mbx_test::CaseSpec spec;
    spec.name = "arm";
    spec.mechanism = "two_link_arm";
    spec.seed = 5;
    spec.fit_seconds = 2, spec.validation_seconds = 1;
    const mbx_test::GeneratedCase g = mbx_test::generate_case(spec, dir.file(spec.name));
    Arm a;
    a.opened = mbx_test::open_mechanism(spec.mechanism);
    a.model = sim::build_model(*a.opened->mechanism);
    const std::vector<Record> records = load_records(load_experiment(g.experiment_path), a.model);
    std::vector<const Record*> fit;
    for (const Record& r : records)
        if (r.role == Role::Fit) fit.push_back(&r);
    a.rows = regression_rows(a.model, fit, IdentifyOptions());
    return a;
}

const Candidate& find(const std::vector<Candidate>& all, const char* cause, int dof) {
    for (const Candidate& c : all)
        if (c.cause == cause && c.dof == dof) return c;
    FAIL("no candidate " << cause << " on coordinate " << dof);
    return all.front();
}

SelectedCause selected(const Candidate& c, std::vector<Estimate> parameters) {
    SelectedCause s;
    s.candidate = c;
    s.parameters = std::move(parameters);
    return s;
}

}  // namespace

TEST_CASE("calibration: every cause of the table is found by its name and by its id") {
    std::set<std::string> names;
    for (size_t i = 0; i < cause_table().size(); ++i) {
        const CauseKind& k = cause_table()[i];
        CAPTURE(k.name);
        CHECK(size_t(k.id) == i);
        CHECK(names.insert(k.name).second);
        CHECK(&cause_kind(k.name) == &k);
        CHECK(std::string(cause_name(k.id)) == k.name);
        CHECK(!k.parameters.empty());
        CHECK(bool(k.columns));
        CHECK(bool(k.extend));
        CHECK((k.candidates != nullptr) == (k.subject != CauseSubject::Transmission));
        CHECK(simulation_supports(k.name) == k.simulated);
    }
    CHECK(names.size() == 14);
    try {
        cause_kind("gearbox_whine");
        FAIL("an unknown cause was found");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("'gearbox_whine'") != std::string::npos);
    }
}

TEST_CASE("calibration: the catalogue offers the table's causes on their subjects, and each column is its law") {
    mbx_test::TempDir dir("mbx_cause_table");
    const Arm arm = two_link_arm(dir);
    const sim::Model& m = arm.model;
    const RegressionRows& rows = arm.rows;
    REQUIRE(rows.actuated.size() == 2);
    const std::vector<Candidate> all = catalogue(m, rows);

    // Per actuated joint every joint cause; per coordinate a sensor offset;
    // per moving body at least its mass; nothing of a transmission.
    std::map<std::string, int> count;
    for (const Candidate& c : all) ++count[c.cause];
    const int A = int(rows.actuated.size());
    CHECK(count["viscous_friction"] == A);
    CHECK(count["asymmetric_friction"] == 2 * A);  // Coulomb alone, and with damping
    CHECK(count["stribeck_friction"] == 5 * A);    // the grid of speeds
    CHECK(count["sensor_offset"] == m.nv);
    CHECK(count["mass_error"] >= 2);
    CHECK(count.count("compliance") == 0);
    CHECK(count.count("backlash") == 0);
    // The arm swings about y: a mounting turned about y is seen, one about x
    // (out of its plane) moves no joint, so the tilt is offered about y alone.
    REQUIRE(count["mounting_tilt"] == 1);
    const Candidate& tilt = find(all, "mounting_tilt", -1);
    CHECK(tilt.parameters == std::vector<std::string>{"tilt_y"});
    {
        // Its column is the effort change per radian of gravity turned about
        // y: the model's own inverse dynamics under a gravity turned by a
        // small angle, differenced, at every row.
        const Eigen::MatrixXd column = tilt.columns(rows);
        sim::Model turned = m;
        const double h = 1e-6;
        turned.gravity = Eigen::AngleAxisd(h, Eigen::Vector3d::UnitY()) * m.gravity;
        sim::Data d0(m), d1(turned);
        Eigen::VectorXd tau0, tau1;
        int compared = 0;
        for (Eigen::Index s = 0; s < rows.samples; s += 11) {
            for (sim::Data* d : {&d0, &d1}) d->q = rows.q.row(s).transpose(), d->v = rows.qd.row(s).transpose();
            sim::update_kinematics(m, d0), sim::update_kinematics(turned, d1);
            const Eigen::VectorXd qdd = rows.qdd.row(s).transpose();
            sim::inverse_dynamics(m, d0, qdd, tau0);
            sim::inverse_dynamics(turned, d1, qdd, tau1);
            for (Eigen::Index a = 0; a < Eigen::Index(rows.actuated.size()); ++a) {
                const double expected = rows.weight[size_t(a)] * (tau1 - tau0)[rows.actuated[size_t(a)]] / h;
                CHECK(column(s * Eigen::Index(rows.actuated.size()) + a, 0) == mbx_test::within(expected, 1e-5 * (1 + std::abs(expected)), "a difference quotient of 1e-6 rad"));
                ++compared;
            }
        }
        CHECK(compared > 20);
        CHECK(tilt.physical(Eigen::VectorXd::Constant(1, 0.05)));
        CHECK_FALSE(tilt.physical(Eigen::VectorXd::Constant(1, 0.3)));
    }
    // In the table's order (the order breaks ties between equal columns).
    int last = -1;
    for (const Candidate& c : all) {
        if (c.dof != rows.actuated[0] || c.kind().subject != CauseSubject::ActuatedJoint) continue;
        CHECK(int(c.kind().id) >= last);
        last = int(c.kind().id);
    }

    // Columns: the row of (sample s, actuated a) is weight[a] times the law on
    // the cause's own joint, zero on the other.
    const int dof = rows.actuated[1];
    const Eigen::Index S = rows.samples;
    auto law_column = [&](const char* cause) { return find(all, cause, dof).columns(rows); };
    const Eigen::MatrixXd viscous = law_column("viscous_friction"), offset = law_column("effort_offset"),
                          armature = law_column("armature"), gain = law_column("actuator_gain");
    for (Eigen::Index s = 0; s < S; s += 97) {
        CAPTURE(s);
        const double w = rows.weight[1];
        CHECK(viscous(s * A + 1, 0) == mbx_test::relative(w * rows.qd(s, dof), 1e-12));
        CHECK(offset(s * A + 1, 0) == mbx_test::relative(w, 1e-12));
        CHECK(armature(s * A + 1, 0) == mbx_test::relative(w * rows.qdd(s, dof), 1e-12));
        CHECK(gain(s * A + 1, 0) == mbx_test::relative(w * rows.effort(s, 1), 1e-12));
        CHECK(viscous(s * A, 0) == 0);
        CHECK(armature(s * A, 0) == 0);
    }
    // Coulomb's law is a sign smoothed at low speed and filtered as the
    // effort was: where the joint moves fast its column has the speed's sign
    // and, but for the filter's overshoot after a reversal, unit size.
    const Eigen::MatrixXd coulomb = law_column("coulomb_friction");
    const double fast = 20 * sign_speed(rows, dof);
    int checked = 0;
    double size = 0;
    for (Eigen::Index s = 0; s < S; ++s)
        if (std::abs(rows.qd(s, dof)) > fast) {
            CHECK(coulomb(s * A + 1, 0) * rows.qd(s, dof) > 0);
            CHECK(std::abs(coulomb(s * A + 1, 0)) < 1.1 * rows.weight[1]);
            size += std::abs(coulomb(s * A + 1, 0)) / rows.weight[1];
            ++checked;
        }
    REQUIRE(checked > 100);
    CHECK(size / checked == mbx_test::relative(1, 0.03));

    // Physical checks: friction dissipates, a gain deficit leaves an actuator.
    const Eigen::VectorXd minus = Eigen::VectorXd::Constant(1, -0.1), plus = Eigen::VectorXd::Constant(1, 0.1);
    CHECK_FALSE(find(all, "viscous_friction", dof).physical(minus));
    CHECK(find(all, "viscous_friction", dof).physical(plus));
    CHECK_FALSE(find(all, "actuator_gain", dof).physical(Eigen::VectorXd::Constant(1, 0.95)));
    CHECK(find(all, "effort_offset", dof).physical(minus));
}

TEST_CASE("calibration: a cause's extension changes the model as the cause says, or says why the file cannot hold it") {
    mbx_test::TempDir dir("mbx_cause_extend");
    const Arm arm = two_link_arm(dir);
    const sim::Model& m = arm.model;
    const std::vector<Candidate> all = catalogue(m, arm.rows);
    const int dof = arm.rows.actuated[1];
    const int joint = m.dof_joint[size_t(dof)];
    Identification id;
    id.causes.push_back(selected(find(all, "viscous_friction", dof), {{"damping", 0.3, 0}}));
    id.causes.push_back(selected(find(all, "armature", dof), {{"armature", 0.02, 0}}));
    id.causes.push_back(selected(find(all, "sensor_offset", dof), {{"offset", 0.01, 0}}));
    id.causes.push_back(selected(find(all, "position_dependent_effort", dof), {{"stiffness", -5.0, 0}}));
    id.causes.push_back(selected(find(all, "actuator_gain", dof), {{"gain_deficit", 0.2, 0}}));
    const sim::BuildOptions base;
    const ModelExtension ext = extend(*arm.opened->mechanism, base, m, id, id.causes.size(), arm.rows);

    REQUIRE(ext.joints.size() == 1);
    const JointUpdate& u = ext.joints[0];
    CHECK(u.sim_joint == joint);
    CHECK(u.after.damping == mbx_test::relative(u.before.damping + 0.3, 1e-6));
    CHECK(u.after.armature == mbx_test::relative(u.before.armature + 0.02, 1e-6));
    CHECK(u.after.stiffness == u.before.stiffness);  // a negative spring is not written...
    CHECK(u.causes == std::vector<std::string>{"viscous_friction", "armature"});
    CHECK(ext.options.joint_dynamics.at(m.joints[size_t(joint)].source).damping == mbx_test::relative(u.after.damping, 1e-6));
    // ...nor are a sensor's offset and a gain: the replays apply them, the report says why.
    CHECK(ext.adjust.sensor_offset[size_t(dof)] == mbx_test::relative(0.01, 1e-6));
    CHECK(ext.adjust.effort_gain[size_t(dof)] == mbx_test::relative(0.8, 1e-6));
    REQUIRE(ext.unwritten.size() == 3);
    CHECK(ext.unwritten[0].cause == 2);
    CHECK(ext.unwritten[0].reason.find("measurement") != std::string::npos);
    CHECK(ext.unwritten[1].cause == 3);
    CHECK(ext.unwritten[1].reason.find("negative stiffness") != std::string::npos);
    CHECK(ext.unwritten[2].cause == 4);
    CHECK(ext.unwritten[2].reason.find("0.8") != std::string::npos);
    // The first two causes alone: nothing unwritten, no stiffness asked for.
    const ModelExtension first = extend(*arm.opened->mechanism, base, m, id, 2, arm.rows);
    CHECK(first.unwritten.empty());
    CHECK(first.adjust.sensor_offset[size_t(dof)] == 0);
}
}  // namespace MBX_UNITY_ID
