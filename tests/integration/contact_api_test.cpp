// Contact through the C API (ABI 9), as a host uses it: collision shapes and
// contact materials from a description file or added by the host, and the
// simulator running with them. Numbers from closed forms: a resting box sinks
// m g / (4 k) on four corners, a ball on a linear spring m g / k, and a
// Hunt-Crossley ball dropped with restitution e rebounds to e^2 of its height.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "apps/stub_host/assemblies/builder.h"
#include "support/plugin_fixture.h"
#include "support/temp_dir.h"

namespace MBX_UNITY_ID {

using namespace itest;

namespace {

using namespace mbx_stub::build;

constexpr double kG = 9.81;

// |value / expected - 1| < rel (doctest's Approx adds 1 to its scale, which
// makes a relative epsilon absolute for values far below 1).
bool near(double value, double expected, double rel) { return std::abs(value / expected - 1) < rel; }

// A ground and one free part of mass m whose origin is its centre, at
// height z; with a box mesh of side `side` when side > 0.
mbx_stub::Assembly free_part(const std::string& name, double mass, double z, double side = 0) {
    mbx_stub::Assembly a;
    a.name = name;
    const mbx_units si{1, 1, 1};
    Builder b(a, name, si, si);
    const Mat3 I = Mat3::Identity();
    b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, I, Vec3::Zero(), Vec3::Zero(), box_inertia(1.0, 0.1, 0.1, 0.1));
    const double s = side > 0 ? side : 0.1;
    b.body("part", "Part", 0, mass, I, Vec3(0, 0, z), Vec3(0, 0, z), box_inertia(mass, s, s, s));
    if (side > 0) b.mesh("part", box_mesh("part_mesh", Vec3(side, side, side), I, Vec3::Zero()));
    return a;
}

struct Description {
    const mbx_api* a = &api();
    mbx_mechatronics* m = nullptr;
    ~Description() { a->mechatronics_destroy(m); }
};

struct Sim {
    const mbx_api* a = &api();
    mbx_sim_model* model = nullptr;
    mbx_sim_data* data = nullptr;
    ~Sim() {
        a->sim_data_destroy(data);
        a->sim_model_destroy(model);
    }
};

std::string write(const TempDir& dir, const std::string& text) {
    const std::string path = dir.file("description.xml");
    std::ofstream(path) << text;
    return path;
}

// Loads `text` as the description file and attaches it: the status of the
// attach (the load must succeed).
mbx_status attach(Run& run, Description& d, const TempDir& dir, const std::string& text) {
    REQUIRE(run.status == MBX_OK);
    REQUIRE(d.a->mechatronics_create(run.context.get(), &d.m) == MBX_OK);
    const mbx_status loaded = d.a->mechatronics_load_drives(run.context.get(), d.m, write(dir, text).c_str());
    REQUIRE_MESSAGE(loaded == MBX_OK, api().context_last_error(run.context.get()));
    return d.a->mechanism_set_mechatronics(run.context.get(), run.get(), d.m);
}

void make_sim(Run& run, Sim& s, mbx_integrator integrator, double step, double tolerance = 0) {
    mbx_sim_options o{};
    o.struct_size = sizeof o;
    o.integrator = integrator;
    o.step = step;
    o.tolerance = tolerance;
    REQUIRE_MESSAGE(s.a->sim_model_create(run.context.get(), run.get(), &o, &s.model) == MBX_OK,
                    api().context_last_error(run.context.get()));
    REQUIRE(s.a->sim_data_create(run.context.get(), s.model, &s.data) == MBX_OK);
    REQUIRE(s.a->sim_initialize(run.context.get(), s.data, nullptr, 0) == MBX_OK);
}

// The free body's height (its coordinates: x y z qw qx qy qz).
double height(const Sim& s) {
    double q[7];
    REQUIRE(s.a->sim_get_state(s.data, nullptr, q, nullptr) == MBX_OK);
    return q[2];
}

}  // namespace

TEST_CASE("contact API: the table carries the ABI 9 contact entries") {
    const mbx_api& a = api();
    CHECK(a.abi_version >= 9);
    CHECK(a.struct_size >= offsetof(mbx_api, mechanism_collision_shape_count) + sizeof(void*));
    CHECK((a.mechatronics_add_collision_shape && a.mechatronics_set_contact_material && a.mechanism_collision_shape_count));
}

TEST_CASE("contact API: a box from its part's mesh hull rests on the ground at m g / (4 k), level, fixed step and accurate") {
    const double mass = 2, side = 0.1, k = 1e5;
    const double c = 2 * std::sqrt(k * mass / 4);  // critical for a quarter of the mass on each corner
    for (mbx_integrator integrator : {MBX_INTEGRATOR_RK4, MBX_INTEGRATOR_ACCURATE}) {
        CAPTURE(int(integrator));
        Run run = translate(free_part("box", mass, side / 2 + 1e-3, side));
        Description d;
        TempDir dir("contact_api");
        const mbx_status attached = attach(run, d, dir,
            "<mechatronics version=\"1\">\n"
            "  <collision body=\"world\" shape=\"plane\"/>\n"
            "  <collision body=\"box/part\" shape=\"hull\"/>\n"
            "  <contact normal=\"spring_damper\" stiffness=\"1e5\" damping=\"" + std::to_string(c) + "\" mu=\"0.5\"/>\n"
            "</mechatronics>\n");
        REQUIRE_MESSAGE(attached == MBX_OK, api().context_last_error(run.context.get()));
        CHECK(d.a->mechanism_collision_shape_count(run.get()) == 2);
        Sim s;
        make_sim(run, s, integrator, integrator == MBX_INTEGRATOR_ACCURATE ? 1e-3 : 1e-4, 1e-8);
        REQUIRE(s.a->sim_step(run.context.get(), s.data, integrator == MBX_INTEGRATOR_ACCURATE ? 1000 : 10000) == MBX_OK);
        double q[7], v[6];
        REQUIRE(s.a->sim_get_state(s.data, nullptr, q, v) == MBX_OK);
        const double depth = side / 2 - q[2];
        MESSAGE("rest depth " << depth << " m (m g / 4k = " << mass * kG / (4 * k) << ")");
        CHECK(near(depth, mass * kG / (4 * k), 0.01));
        CHECK(std::abs(q[4]) + std::abs(q[5]) + std::abs(q[6]) < 1e-9);  // level: the hull's four corners carry it alike
        CHECK(std::abs(v[2]) < 1e-6);
    }
}

TEST_CASE("contact API: URDF gets <collision>, scene.glb draws the shapes only with MBX_EXPORT_SCENE_COLLISION") {
    Run run = translate(free_part("box", 2, 0.1, 0.1));
    Description d;
    TempDir dir("contact_export");
    REQUIRE(attach(run, d, dir,
                   "<mechatronics version=\"1\"><collision body=\"world\" shape=\"plane\"/>"
                   "<collision body=\"*\" shape=\"hull\"/></mechatronics>") == MBX_OK);
    auto slurp = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    };
    for (const uint32_t formats : {uint32_t(MBX_EXPORT_MESHES | MBX_EXPORT_URDF),
                                   uint32_t(MBX_EXPORT_MESHES | MBX_EXPORT_URDF | MBX_EXPORT_SCENE_COLLISION),
                                   uint32_t(MBX_EXPORT_SCENE_COLLISION)}) {  // the modifier alone: every format
        CAPTURE(formats);
        TempDir out("contact_export_out");
        mbx_export_options o{};
        o.struct_size = sizeof o;
        o.formats = formats;
        o.model_name = "box";
        REQUIRE(api().mechanism_export(run.context.get(), run.get(), &o, out.path.string().c_str()) == MBX_OK);
        const bool drawn = formats & MBX_EXPORT_SCENE_COLLISION;
        CHECK((slurp(out.file("scene.glb")).find("\"name\":\"collision_Part_hull\"") != std::string::npos) == drawn);
        const std::string urdf = slurp(out.file("urdf/box.urdf"));
        CHECK(urdf.find("<collision name=\"Part_hull\">") != std::string::npos);
        CHECK(urdf.find("../meshes/collision/collision_Part_hull.stl") != std::string::npos);
        CHECK(std::filesystem::exists(out.file("meshes/collision/collision_Part_hull.stl")));
        CHECK(std::filesystem::exists(out.file("mjcf/box.xml")) == (formats == MBX_EXPORT_SCENE_COLLISION));
    }
}

TEST_CASE("contact API: a ball dropped on a Hunt-Crossley contact rebounds to e^2 of its height (restitution from the file)") {
    const double mass = 1, radius = 0.05, h0 = 0.5, e = 0.5;
    const double impact = std::sqrt(2 * kG * h0);
    for (mbx_integrator integrator : {MBX_INTEGRATOR_RK4, MBX_INTEGRATOR_ACCURATE}) {
        CAPTURE(int(integrator));
        Run run = translate(free_part("ball", mass, radius + h0));
        Description d;
        TempDir dir("contact_api");
        REQUIRE(attach(run, d, dir,
                       "<mechatronics version=\"1\">\n"
                       "  <collision body=\"world\" shape=\"plane\" material=\"floor\"/>\n"
                       "  <collision body=\"ball/part\" shape=\"sphere\" radius=\"50\" unit=\"mm\" material=\"rubber\"/>\n"
                       "  <contact stiffness=\"1e3\" normal=\"spring\"/>\n"
                       "  <contact a=\"rubber\" b=\"floor\" normal=\"hunt_crossley\" stiffness=\"1e9\" exponent=\"1.5\"\n"
                       "           restitution=\"0.5\" impact_speed=\"" + std::to_string(impact) + "\" mu=\"0.3\"/>\n"
                       "</mechatronics>\n") == MBX_OK);
        Sim s;
        const bool accurate = integrator == MBX_INTEGRATOR_ACCURATE;
        make_sim(run, s, integrator, accurate ? 1e-3 : 2e-5, 1e-9);
        // Past the bounce (t ~ 0.32 s) to beyond the apex (~0.48 s).
        double apex = 0;
        bool bounced = false;
        double previous = height(s);
        for (int k = 0; k < 700; ++k) {
            REQUIRE(s.a->sim_step(run.context.get(), s.data, accurate ? 1 : 50) == MBX_OK);
            const double z = height(s);
            if (z > previous && z > radius) bounced = true;
            if (bounced) apex = std::max(apex, z - radius);
            previous = z;
        }
        REQUIRE(bounced);
        MESSAGE("rebound " << apex / h0 << " of the drop height (e^2 = " << e * e << ")");
        CHECK(near(apex, e * e * h0, 0.02));
    }
}

TEST_CASE("contact API: shapes and materials added by the host, a ball rests at m g / k on a linear spring") {
    const double mass = 1, radius = 0.05, k = 1e5;
    Run run = translate(free_part("ball", mass, radius + 2e-3));
    REQUIRE(run.status == MBX_OK);
    const mbx_api& a = api();
    mbx_context* ctx = run.context.get();
    Description d;
    REQUIRE(a.mechatronics_create(ctx, &d.m) == MBX_OK);
    mbx_collision_shape_desc plane{};
    plane.struct_size = sizeof plane;
    plane.body_id = "world";
    plane.kind = MBX_COLLISION_PLANE;
    REQUIRE(a.mechatronics_add_collision_shape(ctx, d.m, &plane) == MBX_OK);
    mbx_collision_shape_desc ball{};
    ball.struct_size = sizeof ball;
    ball.body_id = "ball/part";
    ball.kind = MBX_COLLISION_SPHERE;
    ball.radius = radius;
    REQUIRE(a.mechatronics_add_collision_shape(ctx, d.m, &ball) == MBX_OK);
    mbx_contact_material_desc material{};
    material.struct_size = sizeof material;
    material.normal_law = MBX_CONTACT_SPRING_DAMPER;
    material.stiffness = k;
    material.damping = 2 * std::sqrt(k * mass);
    material.mu_static = material.mu_kinetic = 0.5;
    material.friction_stiffness = 1e4;
    REQUIRE(a.mechatronics_set_contact_material(ctx, d.m, &material) == MBX_OK);

    // Refusals name what is wrong.
    mbx_collision_shape_desc bad = ball;
    bad.radius = -1;
    CHECK(a.mechatronics_add_collision_shape(ctx, d.m, &bad) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(a.context_last_error(ctx)).find("radius must be a positive number") != std::string::npos);
    bad = ball;
    bad.kind = MBX_COLLISION_PLANE;
    bad.radius = 0;
    bad.kind = (mbx_collision_kind)17;
    CHECK(a.mechatronics_add_collision_shape(ctx, d.m, &bad) == MBX_ERROR_INVALID_INPUT);
    bad.struct_size = 8;
    CHECK(a.mechatronics_add_collision_shape(ctx, d.m, &bad) == MBX_ERROR_INVALID_ARGUMENT);
    mbx_contact_material_desc wrong = material;
    wrong.mu_kinetic = 0.9;
    CHECK(a.mechatronics_set_contact_material(ctx, d.m, &wrong) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(a.context_last_error(ctx)).find("mu_kinetic must not exceed mu_static") != std::string::npos);
    wrong = material;
    wrong.material_a = "steel";
    CHECK(a.mechatronics_set_contact_material(ctx, d.m, &wrong) == MBX_ERROR_INVALID_INPUT);

    REQUIRE(a.mechanism_set_mechatronics(ctx, run.get(), d.m) == MBX_OK);
    CHECK(a.mechanism_collision_shape_count(run.get()) == 2);
    Sim s;
    make_sim(run, s, MBX_INTEGRATOR_RK4, 1e-4);
    REQUIRE(s.a->sim_step(ctx, s.data, 10000) == MBX_OK);
    const double depth = radius - height(s);
    MESSAGE("ball rest depth " << depth << " m (m g / k = " << mass * kG / k << ")");
    CHECK(near(depth, mass * kG / k, 0.01));

    // Detaching the description takes the contact away: the ball falls through.
    REQUIRE(a.mechanism_set_mechatronics(ctx, run.get(), nullptr) == MBX_OK);
    CHECK(a.mechanism_collision_shape_count(run.get()) == 0);
    Sim free;
    make_sim(run, free, MBX_INTEGRATOR_RK4, 1e-3);
    REQUIRE(free.a->sim_step(ctx, free.data, 200) == MBX_OK);
    CHECK(height(free) < 0);
}

TEST_CASE("contact API: description problems name file, line and the id") {
    Run run = translate(free_part("ball", 1, 0.1));
    REQUIRE(run.status == MBX_OK);
    mbx_context* ctx = run.context.get();
    const mbx_api& a = api();
    TempDir dir("contact_api");
    {
        // Form problems fail the load, every one with its line.
        Description d;
        REQUIRE(a.mechatronics_create(ctx, &d.m) == MBX_OK);
        const std::string path = write(dir,
            "<mechatronics version=\"1\">\n"
            "  <collision body=\"ball/part\" shape=\"sphere\"/>\n"
            "  <collision body=\"ball/part\" shape=\"cone\" radius=\"1\"/>\n"
            "  <collision body=\"ball/part\" shape=\"box\" size=\"1 1\" radius=\"2\"/>\n"
            "  <contact stiffness=\"1e5\" damping=\"1\" restitution=\"0.5\" mu_static=\"0.2\" mu_kinetic=\"0.3\"/>\n"
            "  <contact a=\"x\" stiffness=\"-1\" frction=\"spring\"/>\n"
            "</mechatronics>\n");
        CHECK(a.mechatronics_load_drives(ctx, d.m, path.c_str()) == MBX_ERROR_INVALID_INPUT);
        const std::string message = a.context_last_error(ctx);
        CAPTURE(message);
        CHECK(message.find(":2: ball/part: radius must be a positive number") != std::string::npos);
        CHECK(message.find(":3: ball/part: shape 'cone' is not sphere, box, cylinder, capsule, plane or hull") != std::string::npos);
        CHECK(message.find(":4: ball/part: size = '1 1' is not three numbers") != std::string::npos);
        CHECK(message.find(":4: ball/part: a box has no radius") != std::string::npos);
        CHECK(message.find(":5: <contact>: give damping or restitution, not both") != std::string::npos);
        CHECK(message.find(":5: <contact>: mu_kinetic must not exceed mu_static") != std::string::npos);
        CHECK(message.find(":6: x/: unknown attribute 'frction' on <contact>") != std::string::npos);
        CHECK(message.find(":6: x/: a contact names both materials a and b, or neither") != std::string::npos);
        CHECK(a.mechatronics_drive_count(d.m) == 0);
    }
    {
        // Ids the mechanism does not have fail the attach, named.
        Description d;
        REQUIRE(a.mechatronics_create(ctx, &d.m) == MBX_OK);
        const std::string path = write(dir,
            "<mechatronics version=\"1\">\n"
            "  <collision body=\"ball/nothing\" shape=\"sphere\" radius=\"0.1\"/>\n"
            "  <collision body=\"ball/part\" shape=\"plane\"/>\n"
            "  <collision body=\"ball/part\" shape=\"sphere\" radius=\"0.1\" material=\"rubber\"/>\n"
            "  <contact a=\"rubber\" b=\"rubbr\" stiffness=\"1e5\"/>\n"
            "</mechatronics>\n");
        REQUIRE(a.mechatronics_load_drives(ctx, d.m, path.c_str()) == MBX_OK);
        CHECK(a.mechanism_set_mechatronics(ctx, run.get(), d.m) == MBX_ERROR_INVALID_INPUT);
        const std::string message = a.context_last_error(ctx);
        CAPTURE(message);
        CHECK(message.find(":2: ball/nothing: no rigid body or CAD part 'ball/nothing' in the mechanism") != std::string::npos);
        CHECK(message.find(":3: ball/part: a plane is unbounded") != std::string::npos);
        CHECK(message.find(":5: rubber/rubbr: no collision shape is made of material 'rubbr'") != std::string::npos);
        CHECK(a.mechanism_collision_shape_count(run.get()) == 0);
    }
    {
        // A hull asked for by the part's id, which the host has no mesh for,
        // fails when the simulation is built (the body="*" default skips it).
        Description d;
        REQUIRE(a.mechatronics_create(ctx, &d.m) == MBX_OK);
        REQUIRE(a.mechatronics_load_drives(ctx, d.m, write(dir,
            "<mechatronics version=\"1\"><collision body=\"ball/part\" shape=\"hull\"/></mechatronics>").c_str()) == MBX_OK);
        REQUIRE(a.mechanism_set_mechatronics(ctx, run.get(), d.m) == MBX_OK);
        CHECK(a.mechanism_collision_shape_count(run.get()) == 1);
        mbx_sim_model* model = nullptr;
        CHECK(a.sim_model_create(ctx, run.get(), nullptr, &model) == MBX_ERROR_INVALID_INPUT);
        CHECK(std::string(a.context_last_error(ctx)).find("the host gave no mesh for part 'ball/part'") != std::string::npos);
        CHECK(model == nullptr);
    }
    {
        Description d;
        REQUIRE(a.mechatronics_create(ctx, &d.m) == MBX_OK);
        REQUIRE(a.mechatronics_load_drives(ctx, d.m, write(dir,
            "<mechatronics version=\"1\"><collision body=\"*\" shape=\"hull\"/></mechatronics>").c_str()) == MBX_OK);
        REQUIRE(a.mechanism_set_mechatronics(ctx, run.get(), d.m) == MBX_OK);
        mbx_sim_model* model = nullptr;
        CHECK(a.sim_model_create(ctx, run.get(), nullptr, &model) == MBX_OK);
        a.sim_model_destroy(model);
    }
}

TEST_CASE("contact API: a failed run leaves the contact as it was (the friction springs' anchors roll back with the data)") {
    // A box at rest is pushed over the plane by 15 N (beyond mu_s m g) in a
    // run that then fails (its directory cannot be written), dragging its
    // friction springs' anchors along. The failed run must leave nothing
    // behind: without the push the box stays where it is, as a fresh data's
    // does, instead of being pulled towards anchors that no longer exist.
    const double mass = 2, side = 0.1, k = 1e5;
    const double c = 2 * std::sqrt(k * mass / 4);
    Run run = translate(free_part("box", mass, side / 2 - mass * kG / (4 * k), side));
    Description d;
    TempDir dir("contact_api");
    REQUIRE(attach(run, d, dir,
                   "<mechatronics version=\"1\">\n"
                   "  <collision body=\"world\" shape=\"plane\"/>\n"
                   "  <collision body=\"box/part\" shape=\"box\" size=\"0.1 0.1 0.1\"/>\n"
                   "  <contact normal=\"spring_damper\" stiffness=\"1e5\" damping=\"" + std::to_string(c) +
                       "\" mu_static=\"0.5\" mu_kinetic=\"0.4\"/>\n"
                   "</mechatronics>\n") == MBX_OK);
    mbx_context* ctx = run.context.get();
    Sim failed, fresh;
    make_sim(run, failed, MBX_INTEGRATOR_EULER, 1e-4);
    make_sim(run, fresh, MBX_INTEGRATOR_EULER, 1e-4);
    // Both settle first, so their anchors are set where the box rests.
    REQUIRE(failed.a->sim_step(ctx, failed.data, 2000) == MBX_OK);
    REQUIRE(fresh.a->sim_step(ctx, fresh.data, 2000) == MBX_OK);
    const double push[6] = {15, 0, 0, 0, 0, 0}, none[6] = {0, 0, 0, 0, 0, 0};  // free joint: force, then torque
    REQUIRE(failed.a->sim_set_effort(ctx, failed.data, push) == MBX_OK);
    mbx_sim_run_options o{};
    o.struct_size = sizeof o;
    o.stop_time = 0.5;
    o.output_step = 0.01;
    std::ofstream(dir.file("blocker")) << "a file, not a directory";
    CHECK(failed.a->sim_run(ctx, failed.data, &o, (dir.file("blocker") + "/out").c_str()) != MBX_OK);
    REQUIRE(failed.a->sim_set_effort(ctx, failed.data, none) == MBX_OK);
    REQUIRE(failed.a->sim_step(ctx, failed.data, 2000) == MBX_OK);
    REQUIRE(fresh.a->sim_step(ctx, fresh.data, 2000) == MBX_OK);
    double qa[7], qb[7];
    REQUIRE(failed.a->sim_get_state(failed.data, nullptr, qa, nullptr) == MBX_OK);
    REQUIRE(fresh.a->sim_get_state(fresh.data, nullptr, qb, nullptr) == MBX_OK);
    CHECK(std::abs(qb[0]) < 1e-9);
    for (int i = 0; i < 7; ++i) CHECK(qa[i] == qb[i]);
}
}  // namespace MBX_UNITY_ID
