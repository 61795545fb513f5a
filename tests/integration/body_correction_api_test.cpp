// A body's inertia corrected through the C API (ABI 10) and the description
// file's <body mass_scale com_shift inertia_change>, as `mbx calibrate`
// writes it: a pendulum's mechanism body, its joint-space inertia and its
// gravity torque against the closed forms of the corrected body (mass times
// the scale, centre moved, inertia about it scaled plus the change), and the
// refusals that name the body.
#include <doctest/doctest.h>

#include <cmath>
#include <cstddef>
#include <fstream>
#include <string>

#include "apps/stub_host/assemblies/builder.h"
#include "support/plugin_fixture.h"
#include "support/temp_dir.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace itest;

namespace {

using namespace mbx_stub::build;

constexpr double kMass = 2, kLength = 0.4, kG = 9.81;

// A link hanging from a hinge about y at the origin, its centre kLength below.
mbx_stub::Assembly pendulum() {
    mbx_stub::Assembly a;
    a.name = "pendulum";
    const mbx_units si{1, 1, 1};
    Builder b(a, "pendulum", si, si);
    const Mat3 I = Mat3::Identity();
    b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, I, Vec3::Zero(), Vec3::Zero(), box_inertia(1.0, 0.1, 0.1, 0.1));
    b.body("link", "Link", 0, kMass, I, Vec3::Zero(), Vec3(0, 0, -kLength), box_inertia(kMass, 0.05, 0.05, 0.8));
    b.joint("hinge", "ground", "link", Vec3::Zero(), I, {revolute(Vec3::UnitY())}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    return a;
}

struct Description {
    const mbx_api* a = &api();
    mbx_mechatronics* m = nullptr;
    ~Description() { a->mechatronics_destroy(m); }
};

// Joint-space inertia and the torque that holds the link still at the CAD pose.
struct Dynamics {
    double inertia = 0, holding = 0;
};

Dynamics dynamics(Run& run) {
    const mbx_api& a = api();
    mbx_sim_options o{};
    o.struct_size = sizeof o;
    mbx_sim_model* model = nullptr;
    mbx_sim_data* data = nullptr;
    REQUIRE(a.sim_model_create(run.context.get(), run.get(), &o, &model) == MBX_OK);
    REQUIRE(a.sim_data_create(run.context.get(), model, &data) == MBX_OK);
    REQUIRE(a.sim_initialize(run.context.get(), data, nullptr, 0) == MBX_OK);
    Dynamics d;
    const double zero = 0;
    CHECK(a.sim_mass_matrix(run.context.get(), data, &d.inertia) == MBX_OK);
    CHECK(a.sim_inverse_dynamics(run.context.get(), data, &zero, &d.holding) == MBX_OK);
    a.sim_data_destroy(data);
    a.sim_model_destroy(model);
    return d;
}

mbx_rigid_body_info link_body(const Run& run) {
    return rigid_body(run.get(), find_part(run.get(), "pendulum/link"));
}

mbx_body_correction_desc correction(double scale, double dx, double dz, double d_yy) {
    mbx_body_correction_desc c{};
    c.struct_size = sizeof c;
    c.body_id = "pendulum/link";
    c.mass_scale = scale;
    c.com_shift[0] = dx, c.com_shift[2] = dz;
    c.inertia_change[0] = c.inertia_change[1] = d_yy;  // material spread along the link: a real body
    return c;
}

}  // namespace

TEST_CASE("body correction API: the table carries the ABI 10 entry") {
    const mbx_api& a = api();
    CHECK(a.abi_version >= 10);
    CHECK(a.struct_size >= offsetof(mbx_api, mechatronics_set_body_correction) + sizeof(void*));
    CHECK(bool(a.mechatronics_set_body_correction));
}

TEST_CASE("body correction API: mass, centre and inertia corrected, in the mechanism and the simulator") {
    Run run = translate(pendulum());
    REQUIRE(run.status == MBX_OK);
    const mbx_rigid_body_info cad = link_body(run);
    REQUIRE(cad.mass == mbx_test::relative(kMass, 1e-6));
    const double cad_yy = cad.inertia[4];
    const Dynamics before = dynamics(run);
    CHECK(before.inertia == mbx_test::relative(cad_yy + kMass * kLength * kLength, 1e-6));
    CHECK(std::abs(before.holding) < 1e-12);  // hanging straight down

    const double scale = 1.25, dx = 0.02, dz = 0.05, d_yy = 0.01;
    Description d;
    REQUIRE(d.a->mechatronics_create(run.context.get(), &d.m) == MBX_OK);
    // A first correction for the same body is replaced, not compounded.
    const mbx_body_correction_desc first = correction(3, 0, 0, 0);
    REQUIRE(d.a->mechatronics_set_body_correction(run.context.get(), d.m, &first) == MBX_OK);
    const mbx_body_correction_desc c = correction(scale, dx, dz, d_yy);
    REQUIRE(d.a->mechatronics_set_body_correction(run.context.get(), d.m, &c) == MBX_OK);
    const mbx_status attached = d.a->mechanism_set_mechatronics(run.context.get(), run.get(), d.m);
    REQUIRE_MESSAGE(attached == MBX_OK, std::string(api().context_last_error(run.context.get())));

    const mbx_rigid_body_info now = link_body(run);
    CHECK(now.mass == mbx_test::relative(scale * kMass, 1e-6));
    CHECK(now.com[0] == mbx_test::relative(cad.com[0] + dx, 1e-6));
    CHECK(now.com[2] == mbx_test::relative(cad.com[2] + dz, 1e-6));
    CHECK(now.inertia[4] == mbx_test::relative(scale * cad_yy + d_yy, 1e-6));
    CHECK(now.inertia[8] == mbx_test::relative(scale * cad.inertia[8], 1e-6));

    // The centre now at (dx, -(L - dz)): the hinge's inertia by the parallel
    // axis theorem, and gravity's lever dx at the CAD pose.
    const Dynamics after = dynamics(run);
    const double m = scale * kMass, lever2 = dx * dx + (kLength - dz) * (kLength - dz);
    CHECK(after.inertia == mbx_test::relative(scale * cad_yy + d_yy + m * lever2, 1e-12));
    CHECK(std::abs(after.holding) == mbx_test::relative(m * kG * dx, 1e-12));

    // Detached: back to the CAD body.
    REQUIRE(d.a->mechanism_set_mechatronics(run.context.get(), run.get(), nullptr) == MBX_OK);
    CHECK(link_body(run).mass == mbx_test::relative(kMass, 1e-6));
    CHECK(link_body(run).com[0] == mbx_test::within(cad.com[0], 1e-12, "the CAD centre restored: metres, to rounding"));
    CHECK(dynamics(run).inertia == mbx_test::relative(before.inertia, 1e-12));
}

TEST_CASE("body correction API: the description file's <body> gives the same body") {
    Run api_run = translate(pendulum()), file_run = translate(pendulum());
    Description by_api, by_file;
    REQUIRE(by_api.a->mechatronics_create(api_run.context.get(), &by_api.m) == MBX_OK);
    const mbx_body_correction_desc c = correction(0.8, -0.03, 0.01, 0.004);
    REQUIRE(by_api.a->mechatronics_set_body_correction(api_run.context.get(), by_api.m, &c) == MBX_OK);
    REQUIRE(by_api.a->mechanism_set_mechatronics(api_run.context.get(), api_run.get(), by_api.m) == MBX_OK);

    TempDir dir("body_correction");
    const std::string path = dir.file("description.xml");
    std::ofstream(path) << "<mechatronics version=\"1\">\n"
                           "  <body id=\"pendulum/link\" mass_scale=\"0.8\" com_shift=\"-0.03 0 0.01\"\n"
                           "        inertia_change=\"0.004 0.004 0 0 0 0\"/>\n"
                           "</mechatronics>\n";
    REQUIRE(by_file.a->mechatronics_create(file_run.context.get(), &by_file.m) == MBX_OK);
    REQUIRE(by_file.a->mechatronics_load_drives(file_run.context.get(), by_file.m, path.c_str()) == MBX_OK);
    REQUIRE(by_file.a->mechanism_set_mechatronics(file_run.context.get(), file_run.get(), by_file.m) == MBX_OK);

    const Dynamics x = dynamics(api_run), y = dynamics(file_run);
    CHECK(x.inertia == y.inertia);
    CHECK(x.holding == y.holding);
    CHECK(std::abs(x.holding) > 0);
}

TEST_CASE("body correction API: refusals name the body") {
    Run run = translate(pendulum());
    Description d;
    REQUIRE(d.a->mechatronics_create(run.context.get(), &d.m) == MBX_OK);
    mbx_context* ctx = run.context.get();

    CHECK(d.a->mechatronics_set_body_correction(ctx, d.m, nullptr) == MBX_ERROR_INVALID_ARGUMENT);
    mbx_body_correction_desc c = correction(1, 0, 0, 0);
    c.struct_size = 4;
    CHECK(d.a->mechatronics_set_body_correction(ctx, d.m, &c) == MBX_ERROR_INVALID_ARGUMENT);
    c = correction(-1, 0, 0, 0);
    CHECK(d.a->mechatronics_set_body_correction(ctx, d.m, &c) == MBX_ERROR_INVALID_INPUT);
    c = correction(1, NAN, 0, 0);
    CHECK(d.a->mechatronics_set_body_correction(ctx, d.m, &c) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(api().context_last_error(ctx)).find("pendulum/link") != std::string::npos);
    c = correction(1, 0, 0, 0);
    c.body_id = "";
    CHECK(d.a->mechatronics_set_body_correction(ctx, d.m, &c) == MBX_ERROR_INVALID_INPUT);

    // Checked against the mechanism when attached: an unknown body, and an
    // inertia no rigid body has (one moment above the sum of the other two).
    c = correction(1, 0, 0, 0);
    c.body_id = "pendulum/nothing";
    REQUIRE(d.a->mechatronics_set_body_correction(ctx, d.m, &c) == MBX_OK);
    CHECK(d.a->mechanism_set_mechatronics(ctx, run.get(), d.m) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(api().context_last_error(ctx)).find("pendulum/nothing") != std::string::npos);

    Description d2;
    REQUIRE(d2.a->mechatronics_create(ctx, &d2.m) == MBX_OK);
    c = correction(1, 0, 0, 0);
    c.inertia_change[1] = 0.05;  // about y alone: 0.16 against 0.107 + 0.0008 kg m^2
    REQUIRE(d2.a->mechatronics_set_body_correction(ctx, d2.m, &c) == MBX_OK);
    CHECK(d2.a->mechanism_set_mechatronics(ctx, run.get(), d2.m) == MBX_ERROR_INVALID_INPUT);
    const std::string why = api().context_last_error(ctx);
    CHECK(why.find("pendulum/link") != std::string::npos);
    CHECK(why.find("exceeds the sum of the other two") != std::string::npos);
    mbx_error_info info{};
    info.struct_size = sizeof info;
    REQUIRE(api().context_last_error_info(ctx, &info) == MBX_OK);
    CHECK(info.subject_kind == MBX_SUBJECT_BODY);
    CHECK(link_body(run).mass == mbx_test::relative(kMass, 1e-6));  // nothing attached
}
}  // namespace MBX_UNITY_ID
