// Collision shapes and contact materials in MJCF, read back by MuJoCo: the
// exported geoms carry contype/conaffinity from the groups and masks, the
// friction, and a solref converted from mbx's spring-damper so that MuJoCo
// rests a ball at mbx's depth m g / k and rebounds it as mbx's damping ratio
// says. Also the converters of sim/contact/parameter_conversion.h against
// their closed forms, and the Modelica note that names the dropped shapes.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "apps/stub_host/assemblies/builder.h"
#include "core/mechatronics/contact_description.h"
#include "core/mechatronics/drive_file.h"
#include "export/mjcf/mjcf_contact.h"
#include "mujoco_helpers.h"
#include "../../sim/contact/parameter_conversion.h"
#include "tests/common/near.h"
#include "tests/common/skip.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

namespace {

using namespace mbx_stub::build;
namespace sc = mbx::sim::contact;

constexpr double kG = 9.81;

bool near(double value, double expected, double rel) { return std::abs(value / expected - 1) < rel; }

mbx_memory::Assembly ball_assembly(double mass, double z) {
    mbx_memory::Assembly a;
    a.name = "ball";
    const mbx_units si{1, 1, 1};
    Builder b(a, "ball", si, si);
    const Mat3 I = Mat3::Identity();
    b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, I, Vec3::Zero(), Vec3::Zero(), box_inertia(1.0, 0.1, 0.1, 0.1));
    b.body("part", "Part", 0, mass, I, Vec3(0, 0, z), Vec3(0, 0, z), box_inertia(mass, 0.1, 0.1, 0.1));
    return a;
}

mbx::ExportSettings with_contact(const xtest::Translated& t, const std::string& description) {
    mbx::MechatronicSpec spec;
    std::vector<mbx::LibraryError> errors;
    mbx::load_drive_text(description, "description.xml", "", spec, errors);
    REQUIRE(errors.empty());
    mbx::ExportSettings settings;
    settings.contact = mbx::resolve_contact(spec.contact, *t.mechanism, errors);
    REQUIRE(errors.empty());
    return settings;
}

}  // namespace

TEST_CASE("contact converters: MuJoCo solref and Drake parameters against their closed forms") {
    const double m = 2, k = 4e4, c = 80;
    const sc::LinearContact mbx_contact{k, c};
    const double zeta = sc::damping_ratio(mbx_contact, m);
    CHECK(near(zeta, c / (2 * std::sqrt(k * m)), 1e-12));
    for (double d : {0.5, 0.9, 0.99}) {
        const sc::MujocoSolref s = sc::mbx_to_mujoco(mbx_contact, m, d);
        CHECK(near(s.dampratio, zeta, 1e-12));
        // Same rest depth, m g / k.
        CHECK(near(sc::mujoco_rest_depth(s, d, kG), m * kG / k, 1e-12));
        const sc::LinearContact back = sc::mujoco_to_mbx(s, m, d);
        CHECK(near(back.stiffness, k, 1e-12));
        CHECK(near(back.damping, c, 1e-12));
    }
    // The published fit to the ContactNets tosses, solref (-3294, -45.1), in the standard form.
    const sc::MujocoSolref fitted = sc::mujoco_direct_to_standard(3294, 45.1);
    CHECK(near(1 / std::pow(fitted.timeconst * fitted.dampratio, 2), 3294, 1e-12));
    CHECK(near(2 / fitted.timeconst, 45.1, 1e-12));
    // Restitution and damping ratio are each other's inverse; the cut (the
    // contact lets go where its force, not its depth, reaches zero) raises
    // the restitution, most at high damping; zeta = 0.2 checked against the
    // root of x + 2 zeta x' found by hand (0.57174).
    for (double e : {0.1, 0.3, 0.5, 0.8, 0.95}) {
        CHECK(near(sc::restitution_of_damping_ratio(sc::damping_ratio_of_restitution(e)), e, 1e-12));
        CHECK(sc::restitution_with_cut(sc::damping_ratio_of_restitution(e)) > e);
    }
    for (double e : {0.2, 0.3, 0.5, 0.8, 0.95})
        CHECK(near(sc::restitution_with_cut(sc::damping_ratio_for_restitution_with_cut(e)), e, 1e-9));
    // Critically damped, a contact that cannot pull still rebounds at 13.5 %.
    CHECK(sc::restitution_with_cut(0.999) == mbx_test::relative(0.1355, 1e-3));
    CHECK(near(sc::restitution_with_cut(0.2), 0.5717400, 1e-6));
    CHECK(near(sc::restitution_with_cut(1e-6), 1, 1e-5));
    // Drake: two equal materials make half the stiffness and the same dissipation.
    const sc::DrakeContact pair = sc::drake_combine({1e6, 0.2}, {1e6, 0.2});
    CHECK(near(pair.stiffness, 5e5, 1e-12));
    CHECK(near(pair.dissipation, 0.2, 1e-12));
    // A rigid one leaves the other's.
    const sc::DrakeContact soft = sc::drake_combine({1e3, 0.5}, {1e15, 0.1});
    CHECK(near(soft.stiffness, 1e3, 1e-9));
    CHECK(near(soft.dissipation, 0.5, 1e-9));
}

TEST_CASE("MJCF contact: MuJoCo rests a ball at mbx's m g / k and rebounds it as the damping ratio says") {
    const double mass = 1, radius = 0.05, k = 1e5, h0 = 0.3;
    const double zeta = 0.2, c = 2 * zeta * std::sqrt(k * mass);
    auto t = xtest::translate(ball_assembly(mass, radius + h0));
    mbx_test::TempDir dir("mjcf_contact");
    const mbx::ExportSettings settings = with_contact(*t,
        "<mechatronics version=\"1\">\n"
        "  <collision body=\"world\" shape=\"plane\" group=\"1\"/>\n"
        "  <collision body=\"ball/part\" shape=\"sphere\" radius=\"0.05\" group=\"2\" mask=\"1\"/>\n"
        "  <contact normal=\"spring_damper\" stiffness=\"1e5\" damping=\"" + std::to_string(c) + "\" mu=\"0.4\"/>\n"
        "</mechatronics>\n");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    const mjModel* mm = run.model.get();
    mjData* md = run.data.get();
    const int ball = mj_name2id(mm, mjOBJ_GEOM, "collision_Part_sphere");
    const int plane = mj_name2id(mm, mjOBJ_GEOM, "collision_world_plane");
    REQUIRE(ball >= 0);
    REQUIRE(plane >= 0);
    CHECK(mm->geom_contype[ball] == 2);
    CHECK(mm->geom_conaffinity[ball] == 1);
    CHECK(mm->geom_friction[3 * ball] == mbx_test::relative(0.4, 1e-6));
    CHECK(mm->geom_type[plane] == mjGEOM_PLANE);

    // Dropped from h0: the restitution of the first bounce (the speed the
    // ball leaves with over the speed it hits with; the contact cannot pull,
    // so it lets go where the spring-damper force reaches zero), then the
    // rest depth.
    mj_forward(mm, md);
    double impact = 0, rebound = 0;
    const int steps = int(std::lround(3.0 / mm->opt.timestep));
    for (int i = 0; i < steps; ++i) {
        mj_step(mm, md);
        const double vz = md->qvel[2];
        if (rebound == 0 || vz > rebound) {
            if (vz < 0 && rebound == 0) impact = std::max(impact, -vz);
            else if (vz > 0 && i * mm->opt.timestep < 0.4) rebound = std::max(rebound, vz);
        }
    }
    const double e_cut = sc::restitution_with_cut(zeta);
    MESSAGE("MuJoCo restitution " << rebound / impact << " at " << impact << " m/s; the damping ratio's, with the cut, "
                                  << e_cut << " (first order " << sc::restitution_of_damping_ratio(zeta) << ")");
    CHECK(near(rebound / impact, e_cut, 0.02));
    const double depth = radius - md->qpos[2];
    MESSAGE("MuJoCo rest depth " << depth << " m, mbx's m g / k " << mass * kG / k);
    CHECK(near(depth, mass * kG / k, 0.02));
    CHECK(std::abs(md->qvel[2]) < 1e-6);
}

TEST_CASE("MJCF contact: materials that differ by pair become <pair> elements, Modelica names the dropped shapes") {
    auto t = xtest::translate(ball_assembly(1, 0.5));
    mbx_test::TempDir dir("mjcf_contact");
    mbx::ExportSettings settings = with_contact(*t,
        "<mechatronics version=\"1\">\n"
        "  <collision body=\"world\" shape=\"plane\" material=\"floor\"/>\n"
        "  <collision body=\"world\" shape=\"box\" size=\"1 1 0.2\" xyz=\"2 0 0\" material=\"wall\"/>\n"
        "  <collision body=\"ball/part\" shape=\"capsule\" radius=\"0.05\" length=\"0.1\" material=\"rubber\"/>\n"
        "  <contact a=\"rubber\" b=\"floor\" normal=\"spring_damper\" stiffness=\"1e5\" restitution=\"0.5\" mu=\"0.8\"/>\n"
        "  <contact a=\"rubber\" b=\"wall\" normal=\"spring_damper\" stiffness=\"1e4\" restitution=\"0.5\" mu=\"0.2\"/>\n"
        "</mechatronics>\n");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    const mjModel* mm = run.model.get();
    // Two pairs (ball-floor, ball-wall); the two world shapes never meet.
    REQUIRE(mm->npair == 2);
    const int capsule = mj_name2id(mm, mjOBJ_GEOM, "collision_Part_capsule");
    REQUIRE(capsule >= 0);
    CHECK(mm->geom_contype[capsule] == 0);
    CHECK(mm->geom_size[3 * capsule + 1] == mbx_test::relative(0.05, 1e-6));
    for (int p = 0; p < mm->npair; ++p) {
        const bool floor = mm->pair_geom1[p] == mj_name2id(mm, mjOBJ_GEOM, "collision_world_plane") ||
                           mm->pair_geom2[p] == mj_name2id(mm, mjOBJ_GEOM, "collision_world_plane");
        CHECK(mm->pair_friction[5 * p] == mbx_test::relative(floor ? 0.8 : 0.2, 1e-6));
        // Ten times softer: sqrt(10) times the time constant.
        const double tc = mm->pair_solref[mjNREF * p];
        CHECK(near(tc, (floor ? 1.0 : std::sqrt(10.0)) * sc::mbx_to_mujoco({1e5, 2 * sc::damping_ratio_for_restitution_with_cut(0.5) * std::sqrt(1e5)}, 1, mbx::kMjcfContactImpedance).timeconst, 1e-6));
    }

    // Modelica: no contact in the MSL; a note names what is left out.
    mbx::ExportModel model = xtest::export_model(*t, settings);
    mbx::export_files(model, MBX_EXPORT_MODELICA);
    bool named = false;
    for (const mbx::Finding& f : model.notes())
        named = named || (f.message.find("Modelica Standard Library has no contact") != std::string::npos &&
                          f.message.find("Part_capsule") != std::string::npos &&
                          f.message.find("world_plane") != std::string::npos);
    CHECK(named);
}

TEST_CASE("MJCF contact: a box rests in MuJoCo at mbx's m g / (4 k), a hull, on MuJoCo's three mesh-plane points, deeper") {
    // mbx's box and hull on a plane touch at every corner below it, each with
    // the material's k; MuJoCo's four box-plane contacts, with the solref
    // sized for the body's mass, come to the same depth. Its mesh-plane
    // collision gives at most three points, so the hull (a mesh geom) rests
    // deeper there: the export says so in a note.
    const double mass = 2, side = 0.1, k = 1e5;
    for (const char* shape : {"box", "hull"}) {
        CAPTURE(shape);
        mbx_memory::Assembly a;
        a.name = "box";
        const mbx_units si{1, 1, 1};
        Builder b(a, "box", si, si);
        const Mat3 I = Mat3::Identity();
        b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, I, Vec3::Zero(), Vec3::Zero(), box_inertia(1.0, 0.1, 0.1, 0.1));
        b.body("part", "Part", 0, mass, I, Vec3(0, 0, side / 2 + 0.002), Vec3(0, 0, side / 2 + 0.002),
               box_inertia(mass, side, side, side));
        b.mesh("part", box_mesh("part_mesh", Vec3(side, side, side), I, Vec3::Zero()));
        auto t = xtest::translate(std::move(a));
        mbx_test::TempDir dir("mjcf_contact");
        const std::string geometry = std::string(shape) == "box" ? "shape=\"box\" size=\"0.1 0.1 0.1\"" : "shape=\"hull\"";
        const mbx::ExportSettings settings = with_contact(*t,
            "<mechatronics version=\"1\">\n"
            "  <collision body=\"world\" shape=\"plane\"/>\n"
            "  <collision body=\"box/part\" " + geometry + "/>\n"
            "  <contact normal=\"spring_damper\" stiffness=\"1e5\" restitution=\"0.3\" mu=\"0.5\"/>\n"
            "</mechatronics>\n");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
        const mjModel* mm = run.model.get();
        mjData* md = run.data.get();
        const int steps = int(std::lround(2.0 / mm->opt.timestep));
        for (int i = 0; i < steps; ++i) mj_step(mm, md);
        const double depth = side / 2 - md->qpos[2];
        MESSAGE(std::string(shape) << ": MuJoCo rest depth " << depth << " m on " << md->ncon
                                   << " contacts, mbx's m g / (4k) " << mass * kG / (4 * k));
        if (std::string(shape) == "box") {
            CHECK(md->ncon == 4);
            CHECK(near(depth, mass * kG / (4 * k), 0.02));
            CHECK(std::abs(md->qpos[4]) + std::abs(md->qpos[5]) < 1e-6);  // level
        } else {
            CHECK(mm->geom_type[mj_name2id(mm, mjOBJ_GEOM, "collision_Part_hull")] == mjGEOM_MESH);
            CHECK(md->ncon == 3);
            CHECK(depth > mass * kG / (4 * k));
            CHECK(depth < 2 * mass * kG / (4 * k));
            mbx::ExportModel model = xtest::export_model(*t, settings);
            mbx::export_files(model, MBX_EXPORT_MJCF);
            bool noted = false;
            for (const mbx::Finding& f : model.notes()) noted = noted || f.message.find("at most three points") != std::string::npos;
            CHECK(noted);
        }
    }
}

TEST_CASE("MJCF contact: ergoCub's default hulls collide in MuJoCo, except the pairs overlapping at the CAD pose, as in mbx") {
    const std::string root = mbx_test::shared_data("pmxml/ergocub");
    mbx_files::FileAdapterOptions o;
    o.mesh_dirs.push_back(root + "/meshes/simmechanics");
    auto t = xtest::translate_file(root + "/SIM_ERGOCUB_1-0.xml", o);
    mbx_test::TempDir dir("mjcf_ergocub_hulls");
    const mbx::ExportSettings settings = with_contact(*t, "<mechatronics version=\"1\"><collision body=\"*\" shape=\"hull\"/></mechatronics>");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    const mjModel* mm = run.model.get();
    mjData* md = run.data.get();
    // Every hull geom has a bounding sphere (a mesh geom at density 0 has
    // none, and MuJoCo's broadphase then never pairs it).
    int hulls = 0;
    for (int g = 0; g < mm->ngeom; ++g)
        if (mm->geom_group[g] == 3 && mm->geom_type[g] == mjGEOM_MESH) {
            ++hulls;
            CHECK(mm->geom_rbound[g] > 0);
        }
    CHECK(hulls >= 50);
    // At qpos0 (the CAD pose) no hull touches another: the overlapping
    // pairs are excluded. Removing the excludes brings them back.
    mj_forward(mm, md);
    CHECK(md->ncon == 0);
    MESSAGE("ergoCub in MuJoCo: " << hulls << " hull geoms, " << mm->nexclude << " excluded body pairs, " << md->ncon
                                  << " contacts at qpos0");
    CHECK(mm->nexclude >= 10);
    std::string xml = run.xml;
    REQUIRE(xml.find("<exclude ") != std::string::npos);
    for (size_t at = 0; (at = xml.find("<exclude ")) != std::string::npos;) xml.erase(at, xml.find("/>", at) + 2 - at);
    const std::string path = dir.file("mjcf/without_excludes.xml");  // beside the original: same mesh paths
    std::ofstream(path) << xml;
    char error[1000] = "";
    mjModel* bare = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    REQUIRE_MESSAGE(bare, error);
    mjData* bd = mj_makeData(bare);
    mj_forward(bare, bd);
    double deepest = 0;
    for (int i = 0; i < bd->ncon; ++i) deepest = std::max(deepest, -bd->contact[i].dist);
    MESSAGE("without the excludes: " << bd->ncon << " contacts at qpos0, deepest " << deepest * 1e3 << " mm");
    CHECK(bd->ncon > 0);
    mj_deleteData(bd);
    mj_deleteModel(bare);
}
}  // namespace MBX_UNITY_ID
