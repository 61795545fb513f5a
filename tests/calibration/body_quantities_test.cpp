// Body quantities in the experiment file (calibration/body_quantities.h):
// a body point's world position, the body's orientation and velocities,
// checked against the two-link arm's analytic kinematics, against MuJoCo's
// xpos/xquat along its own motion, and replayed in the free, effort and
// closed-loop modes.
#include <doctest/doctest.h>
#include <mujoco/mujoco.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "calibration/records/body_quantities.h"
#include "calibration/calibrate.h"
#include "calibration/outputs/calibration_files.h"
#include "core/finding.h"
#include "tests/export/drives_support.h"
#include "tests/export/export_fixture.h"
#include "hidden_effects.h"
#include "sim/build_model.h"
#include "sim/simulation.h"
#include "temp_dir.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"

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

// The arm of hidden_effects.h: shoulder 1 m up, upper link 0.30 m to the
// elbow, forearm 0.25 m to the tip, both hinges about +y, hanging at q = 0.
// The forearm's frame sits at the elbow, unrotated at q = 0.
Eigen::Vector3d arm_elbow(double q1) { return {-0.30 * std::sin(q1), 0, 1.0 - 0.30 * std::cos(q1)}; }
Eigen::Vector3d arm_tip(double q1, double q2) {
    return arm_elbow(q1) + Eigen::Vector3d(-0.25 * std::sin(q1 + q2), 0, -0.25 * std::cos(q1 + q2));
}
Eigen::Vector3d arm_tip_velocity(double q1, double q2, double v1, double v2) {
    return Eigen::Vector3d(-0.30 * std::cos(q1) * v1, 0, 0.30 * std::sin(q1) * v1) +
           Eigen::Vector3d(-0.25 * std::cos(q1 + q2) * (v1 + v2), 0, 0.25 * std::sin(q1 + q2) * (v1 + v2));
}

int dof_of(const sim::Model& m, const char* name) {
    const int j = sim::find_joint(m, name);
    REQUIRE(j >= 0);
    return m.joints[size_t(j)].v_index;
}

int body_index(const sim::Model& m, const std::string& key) { return body_of_key(m, key, "test", 0); }

}  // namespace

TEST_CASE("body quantities: the arm's tip, forearm turn and rates are the analytic kinematics") {
    auto t = mbx_test::open_mechanism("two_link_arm");
    const sim::Model m = sim::build_model(*t->mechanism);
    const int forearm = body_index(m, "two_link_arm/forearm");
    CHECK(body_index(m, m.bodies[size_t(forearm)].name) == forearm);
    const int s = dof_of(m, "two_link_arm/shoulder"), e = dof_of(m, "two_link_arm/elbow");
    BodyKinematics kin(m);
    sim::Data d(m);
    const Eigen::Vector3d tip(0, 0, -0.25);
    for (const auto& [q1, q2, v1, v2] : std::vector<std::array<double, 4>>{{0, 0, 0, 0}, {0.7, -1.2, 0.4, 2.0}, {-2.5, 2.9, -3, 1}}) {
        d.q[s] = q1, d.q[e] = q2, d.v[s] = v1, d.v[e] = v2;
        kin.update(d);
        for (int k = 0; k < 3; ++k) {
            CHECK(kin.value(Quantity::Position, forearm, k, tip) == mbx_test::relative_to(arm_tip(q1, q2)[k], arm_tip(q1, q2).norm(), 1e-12));
            CHECK(kin.value(Quantity::Position, forearm, k, Eigen::Vector3d::Zero()) ==
                  mbx_test::relative_to(arm_elbow(q1)[k], arm_elbow(q1).norm(), 1e-12));
            CHECK(kin.value(Quantity::Velocity, forearm, k, tip) ==
                  mbx_test::relative_to(arm_tip_velocity(q1, q2, v1, v2)[k], arm_tip_velocity(q1, q2, v1, v2).norm() + 1.0, 1e-12));
        }
        // A turn by q1 + q2 about +y: (cos(a/2), 0, sin(a/2), 0), w >= 0 when nothing measured says otherwise.
        const double a = q1 + q2, sign = std::cos(a / 2) < 0 ? -1 : 1;
        CHECK(kin.value(Quantity::Orientation, forearm, 0, {}) == mbx_test::relative_to(sign * std::cos(a / 2), 1.0, 1e-12));
        CHECK(std::abs(kin.value(Quantity::Orientation, forearm, 1, {})) < 1e-12);
        CHECK(kin.value(Quantity::Orientation, forearm, 2, {}) == mbx_test::relative_to(sign * std::sin(a / 2), 1.0, 1e-12));  // a unit quaternion
        CHECK(kin.value(Quantity::AngularVelocity, forearm, 1, {}) == mbx_test::relative_to(v1 + v2, std::abs(v1) + std::abs(v2) + 1.0, 1e-12));
        CHECK(std::abs(kin.value(Quantity::AngularVelocity, forearm, 0, {})) < 1e-12);
    }
}

TEST_CASE("body quantities: a free swing of the arm replayed, its tip compared in the world") {
    // The arm let go at (0.9, -0.6) rad swings under gravity. mbx's own run
    // gives the joint angles; the tip and the forearm's quaternion in the
    // record are the analytic kinematics of those angles, in mm. A free
    // replay from the measured start must reproduce them; one that read the
    // tip in the wrong frame or at a stale state would not.
    auto t = mbx_test::open_mechanism("two_link_arm");
    const sim::Model m = sim::build_model(*t->mechanism);
    const int s = dof_of(m, "two_link_arm/shoulder"), e = dof_of(m, "two_link_arm/elbow");
    sim::Data d(m);
    sim::initial_state(m, d, {{sim::find_joint(m, "two_link_arm/shoulder"), 0, false, 0.9},
                              {sim::find_joint(m, "two_link_arm/elbow"), 0, false, -0.6}});
    sim::IntegratorSettings rk4;
    rk4.kind = sim::IntegratorKind::RK4, rk4.step = 2.5e-4;
    std::string csv = "t,q1,q2,tip_x_mm,tip_z_mm,tip_vx,quat_w,quat_y\n";
    for (int k = 0; k <= 1500; ++k) {
        const double tk = k * 1e-3;
        if (k > 0) sim::advance(m, d, rk4, tk);
        const double q1 = d.q[s], q2 = d.q[e];
        const Eigen::Vector3d tip = arm_tip(q1, q2), vel = arm_tip_velocity(q1, q2, d.v[s], d.v[e]);
        char line[256];
        std::snprintf(line, sizeof line, "%.3f,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g\n", tk, q1, q2, tip.x() * 1e3,
                      tip.z() * 1e3, vel.x(), std::cos((q1 + q2) / 2), std::sin((q1 + q2) / 2));
        csv += line;
    }
    mbx_test::TempDir dir("mbx_body_free");
    write_text(dir.file("swing.csv"), csv);
    const std::string columns =
        "<column name=\"q1\" joint=\"two_link_arm/shoulder\" quantity=\"position\" unit=\"rad\"/>"
        "<column name=\"q2\" joint=\"two_link_arm/elbow\" quantity=\"position\" unit=\"rad\"/>"
        "<column name=\"tip_x_mm\" body=\"two_link_arm/forearm\" quantity=\"position\" axis=\"x\" point=\"0 0 -0.25\" unit=\"mm\"/>"
        "<column name=\"tip_z_mm\" body=\"two_link_arm/forearm\" quantity=\"position\" axis=\"z\" point=\"0 0 -0.25\" unit=\"mm\"/>"
        "<column name=\"tip_vx\" body=\"two_link_arm/forearm\" quantity=\"velocity\" axis=\"x\" point=\"0 0 -0.25\" unit=\"m/s\"/>"
        "<column name=\"quat_w\" body=\"two_link_arm/forearm\" quantity=\"orientation\" component=\"w\"/>"
        "<column name=\"quat_y\" body=\"two_link_arm/forearm\" quantity=\"orientation\" component=\"y\"/>";
    const std::string compares =
        "<compare body=\"two_link_arm/forearm\" quantity=\"position\" axis=\"x\" point=\"0 0 -0.25\"/>"
        "<compare body=\"two_link_arm/forearm\" quantity=\"position\" axis=\"z\" point=\"0 0 -0.25\"/>"
        "<compare body=\"two_link_arm/forearm\" quantity=\"velocity\" axis=\"x\" point=\"0 0 -0.25\"/>"
        "<compare body=\"two_link_arm/forearm\" quantity=\"orientation\" component=\"w\"/>"
        "<compare body=\"two_link_arm/forearm\" quantity=\"orientation\" component=\"y\"/>";
    write_text(dir.file("swing.xml"), "<experiment version=\"1\"><record file=\"swing.csv\" role=\"fit\"/>"
                                      "<record file=\"swing.csv\" role=\"validation\"/><time column=\"t\"/>" +
                                          columns + "<drive mode=\"free\"/>" + compares + "</experiment>");
    const Experiment ex = load_experiment(dir.file("swing.xml"));
    const std::vector<Record> records = load_records(ex, m);
    REQUIRE(records[0].body_signals.size() == 5);
    // mm to m on the way in.
    CHECK(records[0].body_signals[0].values[0] == mbx_test::relative(arm_tip(0.9, -0.6).x(), 1e-9));
    const std::vector<ComparedSignal> compared = compared_signals(ex, m);
    const std::vector<std::vector<double>> sim = replay(m, ex, records[0], compared, ReplayAdjustments(m.nv));
    for (size_t c = 0; c < compared.size(); ++c) {
        const std::vector<double>& meas = *measured_values(records[0], compared[c]);
        const std::vector<double> ref = error_reference(ex, records[0], compared[c], meas);
        double err = 0, norm = 0, worst = 0;
        for (size_t k = 0; k < meas.size(); ++k) {
            err += std::pow(meas[k] - sim[c][k], 2), norm += ref[k] * ref[k];
            worst = std::max(worst, std::abs(meas[k] - sim[c][k]));
        }
        MESSAGE(std::string(quantity_name(compared[c].quantity)) << " " << compared[c].component << ": " << 100 * std::sqrt(err / norm)
                                                    << " % of the motion, worst " << worst);
        // The start velocity comes from a local fit of the measured angles;
        // the rest is the same simulation.
        CHECK(100 * std::sqrt(err / norm) < 0.5);
    }

}

TEST_CASE("body quantities: MuJoCo's forearm pose along its motion, and the effort replay of it") {
    mbx_test::TempDir dir("mbx_body_mujoco");
    mbx_test::CaseSpec spec;
    spec.name = "clean", spec.mechanism = "two_link_arm", spec.seed = 3;
    spec.fit_seconds = 3, spec.validation_seconds = 2;
    std::vector<mbx_test::TrueMotion> motion;
    const mbx_test::GeneratedCase c = mbx_test::generate_case(spec, dir.file("case"), &motion);
    REQUIRE(motion.size() == 2);
    auto t = mbx_test::open_mechanism("two_link_arm");
    const sim::Model m = sim::build_model(*t->mechanism);
    const int forearm = body_index(m, "two_link_arm/forearm");

    char error[1024] = "";
    mjModel* mm = mj_loadXML((dir.file("case") + "/mjcf/two_link_arm.xml").c_str(), nullptr, error, sizeof error);
    REQUIRE_MESSAGE(mm, error);
    mjData* md = mj_makeData(mm);
    int mj_forearm = -1;
    for (int b = 0; b < mm->nbody; ++b)
        if (const char* name = mj_id2name(mm, mjOBJ_BODY, b)) {
            std::string lower(name);
            for (char& ch : lower) ch = char(std::tolower(static_cast<unsigned char>(ch)));
            if (lower.find("forearm") != std::string::npos) mj_forearm = b;
        }
    REQUIRE(mj_forearm > 0);

    // Per record: MuJoCo's tip (the forearm's frame plus 0.25 m down it, by
    // its xmat) and xquat at its true motion, appended as columns.
    BodyKinematics kin(m);
    sim::Data d(m);
    double worst_p = 0, worst_q = 0;
    const std::string paths[2] = {c.fit_csv, c.validation_csv};
    for (size_t r = 0; r < 2; ++r) {
        std::istringstream in(read_text(paths[r]));
        std::string line, out;
        std::getline(in, line);
        out = line + ",tip_x,tip_z,qw,qy\n";
        size_t k = 0;
        while (std::getline(in, line)) {
            REQUIRE(k < motion[r].t.size());
            for (int i = 0; i < mm->nq; ++i) md->qpos[i] = motion[r].q(Eigen::Index(k), i);
            mj_kinematics(mm, md);
            const double* xm = md->xmat + 9 * mj_forearm;
            const Eigen::Vector3d origin(md->xpos[3 * mj_forearm], md->xpos[3 * mj_forearm + 1], md->xpos[3 * mj_forearm + 2]);
            const Eigen::Vector3d tip = origin - 0.25 * Eigen::Vector3d(xm[2], xm[5], xm[8]);
            const double* xq = md->xquat + 4 * mj_forearm;
            char cells[160];
            std::snprintf(cells, sizeof cells, ",%.12g,%.12g,%.12g,%.12g\n", tip.x(), tip.z(), xq[0], xq[2]);
            out += line + cells;
            // mbx's forward kinematics at MuJoCo's state: the same pose.
            d.q = motion[r].q.row(Eigen::Index(k)).transpose();
            kin.update(d);
            worst_p = std::max(worst_p, (kin.position(forearm, Eigen::Vector3d(0, 0, -0.25)) - tip).norm());
            const Eigen::Quaterniond mq(xq[0], xq[1], xq[2], xq[3]);
            worst_q = std::max(worst_q, 1 - std::abs(kin.orientation(forearm).dot(mq)));
            ++k;
        }
        CHECK(k == motion[r].t.size());
        write_text(paths[r], out);
    }
    mj_deleteData(md);
    mj_deleteModel(mm);
    MESSAGE("mbx vs MuJoCo forearm: tip within " << worst_p << " m, orientation 1 - |dot| " << worst_q);
    CHECK(worst_p < 1e-9);
    CHECK(worst_q < 1e-12);

    // The recorded effort replayed over 0.5 s windows: the tip and the
    // forearm's turn follow MuJoCo's as closely as the joint angles do.
    std::string x = read_text(c.experiment_path);
    const std::string more =
        "  <column name=\"tip_x\" body=\"two_link_arm/forearm\" quantity=\"position\" axis=\"x\" point=\"0 0 -0.25\" unit=\"m\"/>\n"
        "  <column name=\"tip_z\" body=\"two_link_arm/forearm\" quantity=\"position\" axis=\"z\" point=\"0 0 -0.25\" unit=\"m\"/>\n"
        "  <column name=\"qw\" body=\"two_link_arm/forearm\" quantity=\"orientation\" component=\"w\"/>\n"
        "  <column name=\"qy\" body=\"two_link_arm/forearm\" quantity=\"orientation\" component=\"y\"/>\n";
    x.replace(x.find("  <drive"), 0, more);
    std::string compares;
    for (const std::string& id : c.joint_ids) compares += "  <compare joint=\"" + id + "\" quantity=\"position\"/>\n";
    compares += "  <compare body=\"two_link_arm/forearm\" quantity=\"position\" axis=\"x\" point=\"0 0 -0.25\"/>\n"
                "  <compare body=\"two_link_arm/forearm\" quantity=\"orientation\" component=\"y\"/>\n";
    x.replace(x.find("</experiment>"), 0, compares);
    write_text(c.experiment_path, x);
    const Experiment ex = load_experiment(c.experiment_path);
    const CalibrationResult r = calibrate(*t->mechanism, {}, ex);
    double joint_worst = 0;
    for (const SignalError& se : r.baseline().simulated)
        if (se.quantity == Quantity::Position && se.body < 0) joint_worst = std::max(joint_worst, se.relative);
    for (const SignalError& se : r.baseline().simulated) {
        MESSAGE((se.body >= 0 ? "body " : "joint ") << std::string(quantity_name(se.quantity)) << " record " << se.record << ": "
                                                    << se.relative << " %, RMS " << se.rms);
        if (se.body >= 0) CHECK(se.relative < std::max(5.0, 1.5 * joint_worst));
    }
    // Errors and traces name the body, its axis or component and point, in
    // the JSON file and on the page.
    const int n = int(r.baseline().simulated.size());
    CHECK(n == 2 * 6);
    int body_errors = 0;
    for (const SignalError& se : r.final_step().simulated) body_errors += se.body == forearm;
    CHECK(body_errors == 4);
    int body_traces = 0;
    for (const Trace& tr : r.traces)
        if (tr.body == forearm) {
            ++body_traces;
            CHECK(tr.t.size() == tr.calibrated.size());
            if (tr.quantity == Quantity::Position) CHECK(tr.point.z() == mbx_test::relative(-0.25, 1e-6));
        }
    CHECK(body_traces == 4);
    const std::string json = calibration_json(m, ex, r);
    CHECK(json.find("\"body\": {\"id\": \"two_link_arm/forearm\"") != std::string::npos);
    CHECK(json.find("\"axis\": \"x\", \"point\": [0, 0, -0.25]") != std::string::npos);
    CHECK(json.find("\"component\": \"y\"") != std::string::npos);
    const std::string html = calibration_html(m, ex, r);
    CHECK(html.find("x at (0, 0, -0.25) m") != std::string::npos);
}

TEST_CASE("body quantities: the EMPS carriage's position in closed loop is the slide's") {
    // The rig's own controller drives the carriage along the recorded
    // reference; the carriage's origin moves along the slide axis by the
    // joint coordinate, at every sample of the closed-loop run.
    auto t = xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/emps_axis/emps_axis.xml");
    const Mechanism& mech = *t->mechanism;
    sim::BuildOptions base;
    base.drives = xtest::resolve_drive_file(mech, std::string(MBX_SAMPLES_DIR) + "/mechatronics/emps_axis_drives.xml");
    const sim::Model m = sim::build_model(mech, base);
    REQUIRE(m.nv == 1);
    int carriage = -1;
    for (size_t b = 1; b < m.bodies.size(); ++b) carriage = int(b);
    BodyKinematics kin(m);
    sim::Data d(m);
    d.q[0] = 0;
    kin.update(d);
    const Eigen::Vector3d p0 = kin.position(carriage, Eigen::Vector3d::Zero());
    d.q[0] = 0.1;
    kin.update(d);
    const Eigen::Vector3d axis = (kin.position(carriage, Eigen::Vector3d::Zero()) - p0) / 0.1;
    CHECK(axis.norm() == mbx_test::relative(1, 1e-12));
    int along = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(axis[k]) > std::abs(axis[along])) along = k;
    const char* axis_name[] = {"x", "y", "z"};

    // The training record's first 3 s, with the carriage's position along
    // that world axis as a body column.
    const Table train = read_csv(mbx_test::shared_data("measured/emps/emps_train.csv"));
    std::string csv = "t_s,q_meas_m,q_ref_m,force_N,carriage\n";
    for (size_t k = 0; k < train.columns[0].size() && train.columns[size_t(train.column("t_s"))][k] <= 3.0; ++k) {
        const double q = train.columns[size_t(train.column("q_meas_m"))][k];
        char line[256];
        std::snprintf(line, sizeof line, "%.6f,%.12g,%.12g,%.12g,%.12g\n", train.columns[size_t(train.column("t_s"))][k], q,
                      train.columns[size_t(train.column("q_ref_m"))][k], train.columns[size_t(train.column("force_N"))][k],
                      p0[along] + q * axis[along]);
        csv += line;
    }
    mbx_test::TempDir dir("mbx_body_emps");
    write_text(dir.file("train.csv"), csv);
    const std::string body = m.bodies[size_t(carriage)].id;
    write_text(dir.file("emps.xml"),
               "<experiment version=\"1\"><record file=\"train.csv\" role=\"fit\"/><record file=\"train.csv\" role=\"validation\"/>"
               "<time column=\"t_s\"/><column name=\"q_meas_m\" joint=\"40:-:41\" quantity=\"position\" unit=\"m\"/>"
               "<column name=\"force_N\" joint=\"40:-:41\" quantity=\"effort\" unit=\"N\"/>"
               "<column name=\"q_ref_m\" joint=\"40:-:41\" quantity=\"reference\" unit=\"m\"/>"
               "<column name=\"carriage\" body=\"" + body + "\" quantity=\"position\" axis=\"" + axis_name[along] +
                   "\" unit=\"m\"/><drive mode=\"closed_loop\"/><compare joint=\"40:-:41\" quantity=\"position\"/>"
                   "<compare body=\"" + body + "\" quantity=\"position\" axis=\"" + axis_name[along] + "\"/></experiment>");
    const Experiment ex = load_experiment(dir.file("emps.xml"));
    const std::vector<Record> records = load_records(ex, m);
    const std::vector<ComparedSignal> compared = compared_signals(ex, m);
    const std::vector<std::vector<double>> sim = replay(m, ex, records[0], compared, ReplayAdjustments(m.nv));
    double worst = 0, moved = 0;
    for (size_t k = 0; k < records[0].t.size(); ++k) {
        worst = std::max(worst, std::abs(sim[1][k] - (p0[along] + sim[0][k] * axis[along])));
        moved = std::max(moved, std::abs(sim[0][k] - sim[0][0]));
    }
    CHECK(moved > 0.01);
    CHECK(worst < 1e-12);
    // Measured against simulated: the same error as the joint's.
    CHECK(relative_error(*measured_values(records[0], compared[1]), sim[1]) ==
          mbx_test::relative(relative_error(*measured_values(records[0], compared[0]), sim[0]) *
                          std::sqrt([&] {
                              double a = 0, b = 0;
                              for (size_t k = 0; k < records[0].t.size(); ++k) {
                                  const double q = records[0].signals[0].values[k];
                                  a += q * q;
                                  b += std::pow(p0[along] + q * axis[along], 2);
                              }
                              return a / b;
                          }()), 1e-6));
}

TEST_CASE("body quantities: the experiment file refuses what it cannot bind, with the file and line") {
    auto t = mbx_test::open_mechanism("two_link_arm");
    const sim::Model m = sim::build_model(*t->mechanism);
    auto parse = [](const std::string& body) {
        return parse_experiment("<experiment version=\"1\">\n<record file=\"a.csv\" role=\"fit\"/>\n"
                                "<record file=\"b.csv\" role=\"validation\"/>\n<time column=\"t\"/>\n" +
                                    body + "\n<compare joint=\"j\" quantity=\"position\"/>\n</experiment>",
                                "x.xml");
    };
    auto refused = [&](const std::string& body, const std::string& message) {
        CHECK_THROWS_WITH_AS(parse(body), doctest::Contains(message.c_str()), Error);
    };
    refused("<column name=\"a\" body=\"b\" quantity=\"position\" unit=\"m\"/>", "x.xml:5: <column>: axis must be x, y or z (got '')");
    refused("<column name=\"a\" body=\"b\" quantity=\"position\" axis=\"q\" unit=\"m\"/>", "axis must be x, y or z (got 'q')");
    refused("<column name=\"a\" body=\"b\" quantity=\"position\" axis=\"x\" unit=\"rad\"/>",
            "x.xml:5: unit 'rad' is not one of a body's position's units");
    refused("<column name=\"a\" body=\"b\" quantity=\"effort\" unit=\"N\"/>", "a body's effort is not measured");
    refused("<column name=\"a\" body=\"b\" quantity=\"orientation\" component=\"v\"/>",
            "orientation component must be w, x, y or z (got 'v')");
    refused("<column name=\"a\" body=\"b\" quantity=\"orientation\" axis=\"x\" component=\"w\"/>",
            "an orientation has a component (w, x, y or z), not an axis");
    refused("<column name=\"a\" body=\"b\" quantity=\"orientation\" component=\"w\" point=\"0 0 1\"/>",
            "an orientation is the body's, not a point's");
    refused("<column name=\"a\" body=\"b\" quantity=\"position\" axis=\"x\" point=\"0 1\" unit=\"m\"/>",
            "point must be three finite numbers");
    refused("<column name=\"a\" body=\"b\" quantity=\"position\" axis=\"x\" point=\"0 nan 1\" unit=\"m\"/>",
            "point must be three finite numbers");
    refused("<column name=\"a\" joint=\"j\" quantity=\"position\" axis=\"x\" unit=\"m\"/>",
            "axis, component and point describe a body quantity, not a joint's");
    refused("<column name=\"a\" joint=\"j\" quantity=\"orientation\"/>", "a joint has no orientation (give a body)");

    mbx_test::TempDir dir("mbx_body_refused");
    write_text(dir.file("r.csv"), [] {
        std::string s = "t,q1,tx\n";
        for (int k = 0; k < 60; ++k) s += std::to_string(k * 1e-3) + ",0,0\n";
        return s;
    }());
    auto load = [&](const std::string& body, std::string compare) {
        if (compare.empty()) compare = "<compare joint=\"two_link_arm/shoulder\" quantity=\"position\"/>";
        write_text(dir.file("e.xml"), "<experiment version=\"1\">\n<record file=\"r.csv\" role=\"fit\"/>\n"
                                      "<record file=\"r.csv\" role=\"validation\"/>\n<time column=\"t\"/>\n"
                                      "<column name=\"q1\" joint=\"two_link_arm/shoulder\" quantity=\"position\" unit=\"rad\"/>\n" +
                                          body + "\n<drive mode=\"free\"/>\n" + compare + "\n</experiment>");
        const Experiment e = load_experiment(dir.file("e.xml"));
        const std::vector<Record> records = load_records(e, m);
        replay(m, e, records[0], compared_signals(e, m), ReplayAdjustments(m.nv));
    };
    CHECK_THROWS_WITH_AS(load("<column name=\"tx\" body=\"elbow_link\" quantity=\"position\" axis=\"x\" unit=\"m\"/>", ""),
                         doctest::Contains("e.xml:6: no body 'elbow_link' in the model"), Error);
    CHECK_THROWS_WITH_AS(load("<column name=\"tx\" body=\"" + m.bodies[0].id + "\" quantity=\"position\" axis=\"x\" unit=\"m\"/>", ""),
                         doctest::Contains("is the world, which does not move"), Error);
    // A compare of a point no column measures.
    CHECK_THROWS_WITH_AS(
        load("<column name=\"tx\" body=\"two_link_arm/forearm\" quantity=\"position\" axis=\"x\" unit=\"m\"/>",
             "<compare body=\"two_link_arm/forearm\" quantity=\"position\" axis=\"x\" point=\"0 0 -0.25\"/>"),
        doctest::Contains("no measured position of body"), Error);
}

TEST_CASE("body quantities: a free body's start velocities from its measured pose, whatever the quaternion's sign") {
    // A body turning at a constant rate w_b about a fixed axis of its own
    // frame from a tilted start, q(t) = q0 exp(w_b t / 2), its origin on a
    // parabola; the tracker gives q or -q at random. The local quadratic fit
    // over 10 ms must give w_b in the body frame and the origin's velocity.
    const Eigen::Vector3d w_b(3.0, -1.5, 2.0), v0(1.2, -0.4, 2.5), p0(0.1, 0.2, 0.5);
    const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, 2, -1).normalized()));
    Record r;
    r.path = "synthetic";
    const double dt = 1 / 148.0;
    std::vector<std::vector<double>> p(3), q(4);
    unsigned flip = 12345;
    for (int k = 0; k < 60; ++k) {
        const double t = k * dt;
        r.t.push_back(t);
        const Eigen::Vector3d pos = p0 + v0 * t + 0.5 * Eigen::Vector3d(0, 0, -9.81) * t * t;
        const Eigen::Quaterniond turn(Eigen::AngleAxisd(w_b.norm() * t, w_b.normalized()));
        Eigen::Quaterniond qt = q0 * turn;
        flip = flip * 1103515245u + 12345u;
        if ((flip >> 16) & 1) qt.coeffs() = -qt.coeffs();
        for (int c = 0; c < 3; ++c) p[size_t(c)].push_back(pos[c]);
        const double comp[4] = {qt.w(), qt.x(), qt.y(), qt.z()};
        for (int c = 0; c < 4; ++c) q[size_t(c)].push_back(comp[c]);
    }
    for (int c = 0; c < 3; ++c) r.body_signals.push_back({Quantity::Position, 1, c, Eigen::Vector3d::Zero(), "p", p[size_t(c)]});
    for (int c = 0; c < 4; ++c) r.body_signals.push_back({Quantity::Orientation, 1, c, Eigen::Vector3d::Zero(), "q", q[size_t(c)]});
    for (size_t k : {size_t(0), size_t(30), size_t(59)}) {
        const PoseSample s = measured_pose(r, 1, k);
        const double t = r.t[k];
        const Eigen::Vector3d v = v0 + Eigen::Vector3d(0, 0, -9.81) * t;
        CAPTURE(k);
        CHECK((s.v - v).norm() < 1e-9);
        // A quadratic over 7 samples of a turn at 3.9 rad/s: the rate within 0.2 %.
        CHECK((s.w - w_b).norm() < 2e-3 * w_b.norm());
        CHECK(std::abs(std::abs(s.q.dot(q0 * Eigen::Quaterniond(Eigen::AngleAxisd(w_b.norm() * t, w_b.normalized())))) - 1) < 1e-12);
    }
}

TEST_CASE("body quantities: the start velocities estimated from the tracked poses of real cube tosses") {
    // ContactNets' tosses (148 Hz) come with velocities the authors derived
    // from the same poses; a free replay or the contact stage estimates them
    // when the columns are absent. At the first sample of each toss (a
    // one-sided fit, where a rollout starts) the two agree to a few percent.
    const Table table = read_csv(mbx_test::shared_data("measured/contactnets_cube/cube_tosses.csv"));
    auto col = [&](const char* name) { return &table.columns[size_t(table.column(name))]; };
    const std::vector<double>* id = col("toss_id");
    const char* pos[] = {"x_m", "y_m", "z_m"};
    const char* quat[] = {"qw", "qx", "qy", "qz"};
    const char* vel[] = {"vx_mps", "vy_mps", "vz_mps"};
    const char* rate[] = {"wx_body_radps", "wy_body_radps", "wz_body_radps"};
    double dv = 0, nv = 0, dw = 0, nw = 0;
    int tosses = 0;
    for (size_t row = 0; row < id->size();) {
        size_t end = row;
        while (end < id->size() && (*id)[end] == (*id)[row]) ++end;
        if (int((*id)[row]) % 10 == 0) {
            Record r;
            r.path = "toss";
            for (size_t k = row; k < end; ++k) r.t.push_back((*col("t_s"))[k]);
            for (int c = 0; c < 3; ++c)
                r.body_signals.push_back({Quantity::Position, 1, c, Eigen::Vector3d::Zero(), pos[c],
                                          std::vector<double>(col(pos[c])->begin() + long(row), col(pos[c])->begin() + long(end))});
            for (int c = 0; c < 4; ++c)
                r.body_signals.push_back({Quantity::Orientation, 1, c, Eigen::Vector3d::Zero(), quat[c],
                                          std::vector<double>(col(quat[c])->begin() + long(row), col(quat[c])->begin() + long(end))});
            const PoseSample s = measured_pose(r, 1, 0);
            Eigen::Vector3d v, w;
            for (int c = 0; c < 3; ++c) v[c] = (*col(vel[c]))[row], w[c] = (*col(rate[c]))[row];
            dv += (s.v - v).squaredNorm(), nv += v.squaredNorm();
            dw += (s.w - w).squaredNorm(), nw += w.squaredNorm();
            ++tosses;
        }
        row = end;
    }
    MESSAGE(tosses << " tosses: estimated start velocity off by " << 100 * std::sqrt(dv / nv) << " %, angular velocity by "
                   << 100 * std::sqrt(dw / nw) << " % (RMS over the published ones)");
    CHECK(tosses == 57);
    CHECK(std::sqrt(dv / nv) < 0.05);
    CHECK(std::sqrt(dw / nw) < 0.08);
}
}  // namespace MBX_UNITY_ID
