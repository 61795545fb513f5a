// MJCF of the real PMXML exports: ergoCub loads with its meshes, each mesh on
// its own body and every body where CAD put it at qpos0; ironCub and the two
// legs mechanisms (the 2015 one with a loop) load and step; the file's header says what
// MuJoCo needs; exporting twice gives the same bytes.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "export/mjcf/mjcf_export.h"
#include "mujoco_assemblies.h"
#include "mujoco_helpers.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// (a function: a missing folder skips the test that asks, not the executable)
std::string data_dir() { return mbx_test::shared_data("pmxml"); }

std::unique_ptr<xtest::Translated> open_ergocub() {
    mbx_files::FileAdapterOptions o;
    o.mesh_dirs.push_back(data_dir() + "/ergocub/meshes/simmechanics");
    return xtest::translate_file(data_dir() + "/ergocub/SIM_ERGOCUB_1-0.xml", o);
}

// Every body MuJoCo has is where mbx puts it at qpos0 (= the CAD pose).
void check_assembly_pose(const xtest::MuJoCoRun& run, const Mechanism& m) {
    mj_kinematics(run.model.get(), run.data.get());
    for (size_t b = 1; b < m.bodies.size(); ++b) {
        const int id = run.body_id(int(b));
        if (m.bodies[b].kind == MBX_RIGID_BODY_DYNAMIC) REQUIRE(id > 0);
        if (id <= 0) continue;
        CAPTURE(m.bodies[b].name);
        const Pose got = run.pose(id);
        CHECK((got.position - m.bodies[b].pose.position).norm() < 1e-9);
        CHECK(xtest::rotation_error(got.rotation, m.bodies[b].pose.rotation) < 1e-9);
    }
}

bool steps_finite(const xtest::MuJoCoRun& run, int steps) {
    for (int i = 0; i < steps; ++i) mj_step(run.model.get(), run.data.get());
    for (int i = 0; i < run.model->nq; ++i)
        if (!std::isfinite(run.data->qpos[i])) return false;
    for (int i = 0; i < run.model->nv; ++i)
        if (!std::isfinite(run.data->qvel[i])) return false;
    return true;
}

}  // namespace

TEST_CASE("MJCF: ergoCub loads with one mesh geom per meshed body, each body at its CAD pose") {
    auto t = open_ergocub();
    const Mechanism& m = *t->mechanism;
    mbx_test::TempDir dir("mbx_mjcf_ergocub");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
    const mjModel* model = run.model.get();

    ExportModel em = xtest::export_model(*t);
    int meshed = 0;
    std::set<std::string> parts;  // CAD parts whose STL reached a mesh file
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        if (!em.has_mesh(int(b))) continue;
        ++meshed;
        for (const Mesh& mesh : em.shapes(int(b))) parts.insert(mesh.part_id);
        CAPTURE(m.bodies[b].name);
        const int mesh = mj_name2id(model, mjOBJ_MESH, em.mesh_stem(int(b)).c_str());
        REQUIRE(mesh >= 0);
        CHECK(model->mesh_vertnum[mesh] > 0);
        const int geom = mj_name2id(model, mjOBJ_GEOM, em.mesh_stem(int(b)).c_str());
        REQUIRE(geom >= 0);
        CHECK(model->geom_dataid[geom] == mesh);
        CHECK(model->geom_bodyid[geom] == run.body_id(int(b)));
    }
    // One mesh and one geom per rigid body with geometry; welded parts share
    // their body's file, so the 66 STL parts arrive in fewer meshes.
    CHECK(model->nmesh == meshed);
    CHECK(model->ngeom == meshed);
    CHECK(parts.size() == 66);
    check_assembly_pose(run, m);
    CHECK(steps_finite(run, 100));
}

TEST_CASE("MJCF: ironCub and the legs mechanisms load, sit at their CAD pose and step without NaN") {
    for (const char* f : {"/ironcub/IRONCUB-MK1_SIM_MODEL.xml", "/ironcub/IRONCUB-MK1_1_SIM_MODEL.xml",
                          "/legs_mechanism_2014/LEGS_MECHANISM.xml", "/legs_mechanism_2015/LEGS_MECHANISM.xml"}) {
        CAPTURE(f);
        auto t = xtest::translate_file(data_dir() + f);
        const Mechanism& m = *t->mechanism;
        mbx_test::TempDir dir("mbx_mjcf_real");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        CHECK(run.load_message.empty());
        if (std::string(f).find("legs_mechanism_2015") != std::string::npos) CHECK(!m.loops.empty());
        CHECK(run.model->neq >= int(m.loops.size()));
        check_assembly_pose(run, m);
        CHECK(steps_finite(run, 100));
        CHECK(xtest::warning_count(run.data.get()) == 0);
    }
}

TEST_CASE("MJCF: the header sets radians, the mesh folder, explicit inertials and the simulation defaults") {
    auto t = xtest::translate_builtin("fourbar");
    mbx_test::TempDir dir("mbx_mjcf_header");
    ExportSettings settings;
    settings.model_name = "four bar";
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    CHECK(xtest::find_file(run.files, "mjcf/four_bar.xml"));
    CHECK(run.xml.find("<mujoco model=\"four_bar\">") != std::string::npos);
    CHECK(run.xml.find("angle=\"radian\"") != std::string::npos);
    CHECK(run.xml.find("meshdir=\"../meshes\"") != std::string::npos);
    CHECK(run.xml.find("inertiafromgeom=\"false\"") != std::string::npos);
    CHECK(run.model->opt.integrator == mjINT_RK4);
    // Ground's geometry is a world geom at ground's pose; meshes come from
    // ../meshes as the mesh exporter writes them.
    ExportModel em = xtest::export_model(*t);
    const int g = mj_name2id(run.model.get(), mjOBJ_GEOM, em.mesh_stem(0).c_str());
    REQUIRE(g >= 0);
    CHECK(run.model->geom_bodyid[g] == 0);
    CHECK(xtest::find_file(run.files, em.mesh_path(0, MBX_MESH_STL)));

    // OBJ when asked for; glTF falls back to STL (MuJoCo 2.2 reads neither glTF nor glb).
    for (mbx_mesh_format format : {MBX_MESH_OBJ, MBX_MESH_GLTF}) {
        settings.mesh_format = format;
        mbx_test::TempDir d2("mbx_mjcf_header");
        xtest::MuJoCoRun r2 = xtest::load_mjcf(*t, d2, settings);
        const char* ext = format == MBX_MESH_OBJ ? ".obj\"" : ".stl\"";
        CHECK(r2.xml.find(em.mesh_stem(1) + ext) != std::string::npos);
        CHECK(r2.model->nmesh == run.model->nmesh);
    }
}

TEST_CASE("MJCF: exporting twice gives byte-identical files") {
    std::vector<std::function<std::unique_ptr<xtest::Translated>()>> inputs;
    for (const std::string& name : mbx_stub::builtin_names())
        inputs.push_back([name] { return xtest::translate_builtin(name); });
    inputs.push_back([] { return xtest::translate(xtest::mjcf_assemblies::spatial()); });
    inputs.push_back([] { return xtest::translate(xtest::mjcf_assemblies::slider_crank()); });
    inputs.push_back(open_ergocub);
    for (const auto& open : inputs) {
        std::string first, second;
        for (std::string* out : {&first, &second}) {
            auto t = open();  // a fresh translation each time
            ExportModel em = xtest::export_model(*t);
            OutputFiles files;
            export_mjcf(em, files);
            REQUIRE(files.size() == 1);
            *out = files[0].contents;
        }
        CHECK(!first.empty());
        CHECK(first == second);
    }
}

TEST_CASE("MJCF: a model with more loop rows than MuJoCo's default reserves enough constraint rows") {
    mbx_stub::GeneratedCounts counts;
    auto t = xtest::translate(mbx_stub::generate_assembly(700, 7, &counts));
    mbx_test::TempDir dir("mbx_mjcf_big");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
    INFO("loops " << counts.loops << ", rows " << run.layout.constraint_rows);
    REQUIRE(run.layout.constraint_rows > 500);  // MuJoCo 2.2's default njmax
    CHECK(run.model->njmax == run.layout.constraint_rows);
    CHECK(run.model->neq >= int(counts.loops));
    CHECK(steps_finite(run, 20));
    CHECK(run.data->warning[mjWARN_CNSTRFULL].number == 0);
    CHECK(run.data->nefc <= run.model->njmax);
    CHECK(run.data->nefc > 500);
}
}  // namespace MBX_UNITY_ID
