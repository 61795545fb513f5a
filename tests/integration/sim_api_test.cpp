// The simulation C API (ABI 6) through the plugin table, as a CAD host uses
// it: a model built from a translated mechanism, data objects, initial state,
// stepping, dynamics queries, runs writing their files, joint dynamics set by
// the host, and every refusal with its status and the subject it names.
// Numbers come from closed forms of a compound pendulum built here.
#include <doctest/doctest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/stub_host/assemblies/builder.h"
#include "support/plugin_fixture.h"
#include "support/temp_dir.h"
#include "../common/file_text.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace itest;
namespace fs = std::filesystem;

namespace {

using namespace mbx_stub::build;

constexpr double kG = 9.81;

// A compound pendulum about world y through (0, 0, 1): mass m, centre of
// mass d below the pivot, inertia about its centre Iyy. Host units mm and g.
struct Pendulum {
    double m = 2.0, d = 0.5, Iyy = 0.02;
    double pivot_inertia() const { return Iyy + m * d * d; }

    mbx_stub::Assembly assembly() const {
        mbx_stub::Assembly a;
        a.name = "pendulum";
        const mbx_units mm{0.001, 0.001, 1e-9};  // length m per unit, mass kg per unit, inertia kg m^2 per unit
        Builder b(a, "pendulum", mm, mm);
        const Mat3 I = Mat3::Identity();
        b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, I, Vec3::Zero(), Vec3::Zero(), box_inertia(1.0, 0.1, 0.1, 0.1));
        Mat3 inertia = Mat3::Zero();
        inertia.diagonal() << 0.01, Iyy, 0.015;
        b.body("bob", "Bob", 0, m, I, Vec3(0, 0, 1 - d), Vec3(0, 0, 1 - d), inertia);
        b.joint("hinge", "ground", "bob", Vec3(0, 0, 1), I, {revolute(Vec3::UnitY())}, MBX_FRAME_IN_WORLD,
                MBX_FRAME_IN_WORLD);
        return a;
    }
};

struct SimHandles {
    const mbx_api* a = &api();
    mbx_sim_model* model = nullptr;
    mbx_sim_data* data = nullptr;
    ~SimHandles() {
        a->sim_data_destroy(data);
        a->sim_model_destroy(model);
    }
};

void make_sim(Run& run, SimHandles& s, const mbx_sim_options* options = nullptr) {
    REQUIRE(run.status == MBX_OK);
    REQUIRE(s.a->sim_model_create(run.context.get(), run.get(), options, &s.model) == MBX_OK);
    REQUIRE(s.a->sim_data_create(run.context.get(), s.model, &s.data) == MBX_OK);
}

mbx_error_info last_error(const Run& run) {
    mbx_error_info info{};
    info.struct_size = sizeof info;
    REQUIRE(api().context_last_error_info(run.context.get(), &info) == MBX_OK);
    return info;
}

}  // namespace

TEST_CASE("sim API: the table and the header agree on ABI 6") {
    const mbx_api& a = api();
    CHECK(a.abi_version >= 6);
    CHECK(a.struct_size >= offsetof(mbx_api, mechatronics_set_joint_dynamics) + sizeof(void*));
    CHECK((a.sim_run != nullptr && a.mechatronics_set_joint_dynamics != nullptr));
    CHECK(std::string(a.status_name(MBX_ERROR_SIMULATION)) == "MBX_ERROR_SIMULATION");
}

TEST_CASE("sim API: a pendulum's mass matrix, inverse dynamics, energy and period are the closed forms") {
    const Pendulum p;
    Run run = translate(p.assembly());
    SimHandles s;
    make_sim(run, s);
    const mbx_api& a = *s.a;
    mbx_context* ctx = run.context.get();

    mbx_sim_model_info info{};
    info.struct_size = sizeof info;
    REQUIRE(a.sim_model_get_info(s.model, &info) == MBX_OK);
    CHECK(info.nq == 1);
    CHECK(info.nv == 1);
    CHECK(info.joint_count == 1);
    CHECK(info.loop_closure_count == 0);
    CHECK(info.gravity[2] == -kG);
    mbx_sim_joint_info j{};
    j.struct_size = sizeof j;
    REQUIRE(a.sim_model_get_joint(s.model, 0, &j) == MBX_OK);
    CHECK(j.kind == MBX_SIM_JOINT_REVOLUTE);
    CHECK(std::string(j.constraint_id) == "pendulum/hinge");
    uint32_t found = 99;
    CHECK(a.sim_model_find_joint(s.model, "pendulum/hinge", &found) == MBX_OK);
    CHECK(found == 0);
    CHECK(a.sim_model_find_joint(s.model, "nothing", &found) == MBX_ERROR_INVALID_ARGUMENT);

    // At any angle: M = I_pivot; holding it still takes m g d sin(theta);
    // the potential is m g z_com with z_com = 1 - d cos(theta).
    for (double theta : {0.0, 0.4, -1.1, 2.5}) {
        CAPTURE(theta);
        const double zero = 0;
        REQUIRE(a.sim_set_joint_state(ctx, s.data, 0, &theta, &zero) == MBX_OK);
        double M = 0, tau = 0;
        REQUIRE(a.sim_mass_matrix(ctx, s.data, &M) == MBX_OK);
        CHECK(M == mbx_test::relative(p.pivot_inertia(), 1e-12));
        REQUIRE(a.sim_inverse_dynamics(ctx, s.data, &zero, &tau) == MBX_OK);
        CHECK(tau == mbx_test::relative_to(p.m * kG * p.d * std::sin(theta), p.m * kG * p.d, 1e-12));
        double qacc = 0;
        REQUIRE(a.sim_forward_dynamics(ctx, s.data, &qacc) == MBX_OK);
        CHECK(qacc == mbx_test::relative_to(-p.m * kG * p.d * std::sin(theta) / p.pivot_inertia(), p.m * kG * p.d / p.pivot_inertia(), 1e-12));
        mbx_sim_energy e{};
        e.struct_size = sizeof e;
        REQUIRE(a.sim_get_energy(ctx, s.data, &e) == MBX_OK);
        CHECK(e.gravity == mbx_test::relative(p.m * kG * (1 - p.d * std::cos(theta)), 1e-12));
        CHECK(e.kinetic == 0);
    }

    // Released from theta0, the period with the finite-amplitude correction.
    const double theta0 = 0.05;
    mbx_sim_fixed_value start{0, 0, 0, theta0};
    REQUIRE(a.sim_initialize(ctx, s.data, &start, 1) == MBX_OK);
    const double T0 = 2 * M_PI * std::sqrt(p.pivot_inertia() / (p.m * kG * p.d));
    const double expected = T0 * (1 + theta0 * theta0 / 16 + 11 * std::pow(theta0, 4) / 3072);
    std::vector<double> crossings;
    double previous = theta0, t_prev = 0;
    while (crossings.size() < 5) {
        REQUIRE(a.sim_step(ctx, s.data, 1) == MBX_OK);
        double t = 0, q = 0;
        REQUIRE(a.sim_get_state(s.data, &t, &q, nullptr) == MBX_OK);
        if (previous < 0 && q >= 0) crossings.push_back(t_prev + (t - t_prev) * (-previous) / (q - previous));
        previous = q;
        t_prev = t;
        REQUIRE(t < 10 * T0);
    }
    const double measured = (crossings.back() - crossings.front()) / 4;
    CHECK(std::fabs(measured - expected) < 1e-6 * expected);  // RK4 at 1 ms: phase error ~1e-11
    mbx_sim_stats stats{};
    stats.struct_size = sizeof stats;
    REQUIRE(a.sim_get_stats(s.data, &stats) == MBX_OK);
    CHECK(stats.evaluations == 4 * stats.steps);  // RK4

    // Two data objects on one model are independent rollouts.
    mbx_sim_data* other = nullptr;
    REQUIRE(a.sim_data_create(ctx, s.model, &other) == MBX_OK);
    REQUIRE(a.sim_initialize(ctx, other, &start, 1) == MBX_OK);
    REQUIRE(a.sim_integrate(ctx, other, 0.75) == MBX_OK);
    double t_other = 0, q_other = 0;
    a.sim_get_state(other, &t_other, &q_other, nullptr);
    CHECK(t_other == 0.75);
    REQUIRE(a.sim_initialize(ctx, s.data, &start, 1) == MBX_OK);
    REQUIRE(a.sim_step(ctx, s.data, 750) == MBX_OK);
    double t_mine = 0, q_mine = 0;
    a.sim_get_state(s.data, &t_mine, &q_mine, nullptr);
    CHECK(q_mine == q_other);
    a.sim_data_destroy(other);
}

TEST_CASE("sim API: joint dynamics set by the host damp the pendulum at b / (2 I)") {
    const Pendulum p;
    Run run = translate(p.assembly());
    const mbx_api& a = api();
    mbx_context* ctx = run.context.get();
    mbx_mechatronics* mech = nullptr;
    REQUIRE(a.mechatronics_create(ctx, &mech) == MBX_OK);
    mbx_joint_dynamics_desc jd{};
    jd.struct_size = sizeof jd;
    jd.constraint_id = "pendulum/hinge";
    jd.primitive_index = -1;
    jd.damping = 0.2;
    // Refused before anything is stored: a negative coefficient.
    jd.damping = -1;
    CHECK(a.mechatronics_set_joint_dynamics(ctx, mech, &jd) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(a.context_last_error(ctx)).find("damping") != std::string::npos);
    jd.damping = 0.2;
    REQUIRE(a.mechatronics_set_joint_dynamics(ctx, mech, &jd) == MBX_OK);
    REQUIRE(a.mechanism_set_mechatronics(ctx, run.get(), mech) == MBX_OK);
    a.mechatronics_destroy(mech);

    SimHandles s;
    make_sim(run, s);
    mbx_sim_fixed_value start{0, 0, 0, 0.02};
    REQUIRE(a.sim_initialize(ctx, s.data, &start, 1) == MBX_OK);
    // Amplitude envelope exp(-b t / (2 I)): compare successive maxima one period apart.
    const double rate = jd.damping / (2 * p.pivot_inertia());
    std::vector<std::pair<double, double>> peaks;
    double q_prev2 = 0, q_prev = 0.02, t_prev = 0;
    for (int k = 0; k < 8000 && peaks.size() < 4; ++k) {
        REQUIRE(a.sim_step(ctx, s.data, 1) == MBX_OK);
        double t = 0, q = 0;
        a.sim_get_state(s.data, &t, &q, nullptr);
        if (k > 1 && q_prev > q_prev2 && q_prev >= q && q_prev > 0) peaks.emplace_back(t_prev, q_prev);
        q_prev2 = q_prev, q_prev = q, t_prev = t;
    }
    REQUIRE(peaks.size() == 4);
    const double measured = std::log(peaks[0].second / peaks[3].second) / (peaks[3].first - peaks[0].first);
    CHECK(measured == mbx_test::relative(rate, 2e-3));  // peak sampling at 1 ms
}

TEST_CASE("sim API: ABI 7 joint dynamics (offset, asymmetric Coulomb) act as -offset and c+ / c-, ABI 6 callers keep the old law") {
    // The hanging pendulum at rest at q = 0 feels no gravity torque: the
    // joint acceleration is the joint dynamics' effort over the pivot inertia.
    const Pendulum p;
    const mbx_api& a = api();
    REQUIRE(a.abi_version >= 7u);
    const double offset = 0.3, cp = 0.5, cn = 0.2;
    auto qacc_at = [&](uint32_t struct_size, double qd) {
        Run run = translate(p.assembly());
        mbx_context* ctx = run.context.get();
        mbx_mechatronics* mech = nullptr;
        REQUIRE(a.mechatronics_create(ctx, &mech) == MBX_OK);
        mbx_joint_dynamics_desc jd;
        std::memset(&jd, 0, sizeof jd);
        jd.struct_size = struct_size;
        jd.constraint_id = "pendulum/hinge";
        jd.primitive_index = -1;
        jd.coulomb = cp;
        jd.coulomb_velocity = 1e-3;
        // Beyond an ABI 6 caller's struct_size these are not its fields.
        jd.offset = offset;
        jd.coulomb_negative = cn;
        jd.asymmetric = 1;
        REQUIRE(a.mechatronics_set_joint_dynamics(ctx, mech, &jd) == MBX_OK);
        REQUIRE(a.mechanism_set_mechatronics(ctx, run.get(), mech) == MBX_OK);
        a.mechatronics_destroy(mech);
        SimHandles s;
        make_sim(run, s);
        const double q = 0;
        REQUIRE(a.sim_set_state(ctx, s.data, 0, &q, &qd) == MBX_OK);
        double qacc = 0;
        REQUIRE(a.sim_forward_dynamics(ctx, s.data, &qacc) == MBX_OK);
        return qacc;
    };
    const double I = p.pivot_inertia();
    const uint32_t v6 = uint32_t(offsetof(mbx_joint_dynamics_desc, offset));
    CHECK(qacc_at(sizeof(mbx_joint_dynamics_desc), 2.0) == mbx_test::relative((-offset - cp) / I, 1e-9));
    CHECK(qacc_at(sizeof(mbx_joint_dynamics_desc), -2.0) == mbx_test::relative((-offset + cn) / I, 1e-9));
    CHECK(qacc_at(v6, 2.0) == mbx_test::relative(-cp / I, 1e-9));
    CHECK(qacc_at(v6, -2.0) == mbx_test::relative(cp / I, 1e-9));

    // A Stribeck peak without its decay speed is refused, naming it.
    Run run = translate(p.assembly());
    mbx_context* ctx = run.context.get();
    mbx_mechatronics* mech = nullptr;
    REQUIRE(a.mechatronics_create(ctx, &mech) == MBX_OK);
    mbx_joint_dynamics_desc bad{};
    bad.struct_size = sizeof bad;
    bad.constraint_id = "pendulum/hinge";
    bad.primitive_index = -1;
    bad.stribeck = 0.1;
    CHECK(a.mechatronics_set_joint_dynamics(ctx, mech, &bad) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(a.context_last_error(ctx)).find("stribeck_velocity") != std::string::npos);
    bad.stribeck = 0;
    bad.offset = NAN;
    CHECK(a.mechatronics_set_joint_dynamics(ctx, mech, &bad) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(a.context_last_error(ctx)).find("offset must be finite") != std::string::npos);
    bad.offset = 0;
    bad.asymmetric = 1;
    bad.damping_negative = -1;
    CHECK(a.mechatronics_set_joint_dynamics(ctx, mech, &bad) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(a.context_last_error(ctx)).find("damping_negative") != std::string::npos);
    a.mechatronics_destroy(mech);
}

TEST_CASE("sim API: a run writes trajectory.csv and simulation.json, a failed one writes nothing") {
    Run run = translate_builtin("fourbar");
    SimHandles s;
    make_sim(run, s);
    const mbx_api& a = *s.a;
    mbx_context* ctx = run.context.get();
    REQUIRE(a.sim_initialize(ctx, s.data, nullptr, 0) == MBX_OK);
    mbx_test::TempDir dir("mbx_sim_api_run");
    mbx_sim_run_options o{};
    o.struct_size = sizeof o;
    o.stop_time = 0.5;
    o.output_step = 0.0105;  // not a whole number of 1 ms steps
    const std::string out = dir.file("bad");
    CHECK(a.sim_run(ctx, s.data, &o, out.c_str()) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(a.context_last_error(ctx)).find("whole number of steps") != std::string::npos);
    CHECK(!fs::exists(out + "/trajectory.csv"));

    // Cancelled by the host's progress callback: nothing written either.
    a.context_set_progress(ctx, [](void*, const char*, double f) { return f > 0.5 ? 1 : 0; }, nullptr);
    o.output_step = 0.01;
    CHECK(a.sim_run(ctx, s.data, &o, out.c_str()) == MBX_ERROR_CANCELLED);
    CHECK(!fs::exists(out + "/simulation.json"));
    a.context_set_progress(ctx, nullptr, nullptr);

    const std::string good = dir.file("good");
    REQUIRE(a.sim_run(ctx, s.data, &o, good.c_str()) == MBX_OK);
    const std::string csv = mbx_test::read_file(good + "/trajectory.csv");
    CHECK(csv.rfind("time,", 0) == 0);
    size_t rows = 0;
    for (char c : csv) rows += c == '\n';
    CHECK(rows == 1 + 51);  // header, t = 0 .. 0.5 every 10 ms
    const std::string json = mbx_test::read_file(good + "/simulation.json");
    CHECK(json.find("\"integrator\": \"rk4\"") != std::string::npos);
    CHECK(json.find("\"steps\": 500") != std::string::npos);
    double t = 0;
    a.sim_get_state(s.data, &t, nullptr, nullptr);
    CHECK(t == mbx_test::relative(0.5, 1e-6));
}

TEST_CASE("sim API: bad input is refused with the joint, loop or option named") {
    Run run = translate_builtin("fourbar");
    const mbx_api& a = api();
    mbx_context* ctx = run.context.get();
    SimHandles s;

    mbx_sim_options o{};
    o.struct_size = sizeof o;
    int bad_kind = 7;
    std::memcpy(&o.integrator, &bad_kind, sizeof bad_kind);
    CHECK(a.sim_model_create(ctx, run.get(), &o, &s.model) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(s.model == nullptr);
    o.integrator = MBX_INTEGRATOR_RK4;
    o.step = -1;
    CHECK(a.sim_model_create(ctx, run.get(), &o, &s.model) == MBX_ERROR_INVALID_ARGUMENT);
    o.step = 0;
    o.flags = MBX_SIM_SET_GRAVITY;
    o.gravity[0] = NAN;
    CHECK(a.sim_model_create(ctx, run.get(), &o, &s.model) == MBX_ERROR_INVALID_ARGUMENT);
    o.gravity[0] = 0;
    make_sim(run, s, &o);

    // A NaN coordinate names its joint.
    mbx_sim_joint_info j{};
    j.struct_size = sizeof j;
    REQUIRE(a.sim_model_get_joint(s.model, 1, &j) == MBX_OK);
    const double nan = NAN;
    CHECK(a.sim_set_joint_state(ctx, s.data, 1, &nan, nullptr) == MBX_ERROR_INVALID_INPUT);
    mbx_error_info e = last_error(run);
    CHECK(e.subject_kind == MBX_SUBJECT_CONSTRAINT);
    CHECK(std::string(e.subject_id) == j.constraint_id);
    mbx_sim_fixed_value inf_value{1, 0, 1, INFINITY};
    CHECK(a.sim_initialize(ctx, s.data, &inf_value, 1) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(last_error(run).subject_id) == j.constraint_id);
    CHECK(a.sim_set_joint_state(ctx, s.data, 99, &nan, nullptr) == MBX_ERROR_INVALID_ARGUMENT);

    // A crank angle no four-bar can reach: the error names the loop (its cut joint).
    mbx_sim_model_info info{};
    info.struct_size = sizeof info;
    a.sim_model_get_info(s.model, &info);
    REQUIRE(info.loop_closure_count == 1);
    std::vector<double> q_before(info.nq);
    a.sim_get_state(s.data, nullptr, q_before.data(), nullptr);
    // Fix every tree joint: the loop then has no freedom left to close.
    std::vector<mbx_sim_fixed_value> all;
    for (uint32_t k = 0; k < info.joint_count; ++k) all.push_back({k, 0, 0, 0.7 + 0.3 * k});
    CHECK(a.sim_initialize(ctx, s.data, all.data(), uint32_t(all.size())) == MBX_ERROR_INVALID_INPUT);
    e = last_error(run);
    CHECK(e.subject_kind == MBX_SUBJECT_LOOP);
    CHECK(std::string(e.message).find("cut joint") != std::string::npos);
    std::vector<double> q_after(info.nq);
    a.sim_get_state(s.data, nullptr, q_after.data(), nullptr);
    CHECK(q_after == q_before);  // a failed initialisation changes nothing

    // A run that diverges: an effort no mechanism survives, at a coarse step.
    std::vector<double> effort(info.nv, 0.0);
    effort[0] = 1e300;
    REQUIRE(a.sim_set_effort(ctx, s.data, effort.data()) == MBX_OK);
    double t_before = 0;
    a.sim_get_state(s.data, &t_before, q_before.data(), nullptr);
    const mbx_status st = a.sim_step(ctx, s.data, 50);
    CHECK((st == MBX_ERROR_SIMULATION || st == MBX_ERROR_INVALID_INPUT));
    double t_after = 0;
    a.sim_get_state(s.data, &t_after, q_after.data(), nullptr);
    for (double q : q_after) CHECK(std::isfinite(q));  // the last good state, never NaN
    effort[0] = NAN;
    CHECK(a.sim_set_effort(ctx, s.data, effort.data()) == MBX_ERROR_INVALID_INPUT);
}

TEST_CASE("sim API: a described elastic transmission's motor follows the state the host sets") {
    // The pendulum hung from a motor through a spring: placed by the host at
    // q = 0.3 at rest, the motor is set where the spring carries gravity, so
    // the link starts without acceleration; the rigid pendulum falls at
    // m g l sin(q) / I there.
    const Pendulum p;
    Run run = translate(p.assembly());
    const mbx_api& a = api();
    mbx_context* ctx = run.context.get();
    mbx_test::TempDir dir("mbx_sim_api_transmission");
    const std::string path = dir.file("description.xml");
    std::ofstream(path) << "<mechatronics version=\"1\">\n  <joint constraint=\"pendulum/hinge\">\n"
                           "    <transmission stiffness=\"400\" damping=\"0.5\" motor_inertia=\"0.02\"/>\n  </joint>\n"
                           "</mechatronics>\n";
    mbx_mechatronics* mech = nullptr;
    REQUIRE(a.mechatronics_create(ctx, &mech) == MBX_OK);
    REQUIRE_MESSAGE(a.mechatronics_load_drives(ctx, mech, path.c_str()) == MBX_OK, a.context_last_error(ctx));
    REQUIRE(a.mechanism_set_mechatronics(ctx, run.get(), mech) == MBX_OK);
    a.mechatronics_destroy(mech);
    SimHandles s;
    make_sim(run, s);
    const double q = 0.3, qd = 0;
    REQUIRE(a.sim_set_state(ctx, s.data, 0, &q, &qd) == MBX_OK);
    double qacc = 1;
    REQUIRE(a.sim_forward_dynamics(ctx, s.data, &qacc) == MBX_OK);
    CHECK(std::fabs(qacc) < 1e-9);
    // A second placement moves the motor again.
    const double q2 = -0.2;
    REQUIRE(a.sim_set_state(ctx, s.data, 0, &q2, &qd) == MBX_OK);
    REQUIRE(a.sim_forward_dynamics(ctx, s.data, &qacc) == MBX_OK);
    CHECK(std::fabs(qacc) < 1e-9);
}
}  // namespace MBX_UNITY_ID
