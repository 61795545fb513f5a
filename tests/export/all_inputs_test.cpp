// Every built-in, every sample and every real PMXML export in ../shared goes
// to every format: the MJCF loads in MuJoCo and steps without NaN, the URDF
// parses with urdfdom with one link per exported body, the Modelica package
// has its files, each body with geometry has its mesh, and exporting twice
// gives byte-identical files.
#include <mujoco/mujoco.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "export_fixture.h"
#include "tests/common/file_text.h"
#include "test_inputs.h"

namespace MBX_UNITY_ID {

namespace fs = std::filesystem;

namespace {

using simtest::Input;

// Every built-in, sample and real export (the MJCF tests' small assemblies
// have their own cases).
std::vector<Input> all_inputs() {
    std::vector<Input> in = simtest::builtin_inputs();
    for (auto* more : {&simtest::sample_inputs, &simtest::shared_pmxml_inputs})
        for (Input& i : more()) in.push_back(std::move(i));
    return in;
}

using mbx_test::read_file;

const mbx::OutputFile* with_suffix(const mbx::OutputFiles& files, const std::string& prefix, const std::string& suffix) {
    for (const auto& f : files)
        if (f.path.rfind(prefix, 0) == 0 && f.path.size() >= suffix.size() &&
            f.path.compare(f.path.size() - suffix.size(), suffix.size(), suffix) == 0)
            return &f;
    return nullptr;
}

void check_input(const Input& input) {
    CAPTURE(input.label);
    auto t = input.open();
    const mbx::Mechanism& m = *t->mechanism;
    mbx_test::TempDir dir("mbx_export_all"), again("mbx_export_all");
    mbx::ExportSettings settings;
    settings.model_name = "exported";
    const mbx::OutputFiles files = xtest::export_to(*t, dir, MBX_EXPORT_ALL, settings);
    xtest::export_to(*t, again, MBX_EXPORT_ALL, settings);

    // Byte-identical re-export.
    for (const auto& f : files) {
        CAPTURE(f.path);
        CHECK(read_file(dir.path / f.path) == f.contents);
        CHECK(read_file(again.path / f.path) == f.contents);
    }

    // MuJoCo loads and steps the MJCF.
    const mbx::OutputFile* mjcf = with_suffix(files, "mjcf/", ".xml");
    REQUIRE(mjcf);
    char error[1024] = "";
    mjModel* model = mj_loadXML((dir.path / mjcf->path).c_str(), nullptr, error, sizeof error);
    REQUIRE_MESSAGE(model, error);
    mjData* data = mj_makeData(model);
    for (int i = 0; i < 50; ++i) mj_step(model, data);
    bool finite = true;
    for (int i = 0; i < model->nq; ++i) finite = finite && std::isfinite(data->qpos[i]);
    CHECK(finite);
    int dynamic = 0;
    for (const mbx::RigidBody& b : m.bodies) dynamic += b.kind == MBX_RIGID_BODY_DYNAMIC;
    CHECK(model->nbody >= dynamic + 1);  // world + every dynamic body (+ light helper bodies)
    mj_deleteData(data);
    mj_deleteModel(model);

    // urdfdom parses the URDF; links cover every body but the world datum.
    const mbx::OutputFile* urdf = with_suffix(files, "urdf/", ".urdf");
    REQUIRE(urdf);
    const urdf::ModelInterfaceSharedPtr u = urdf::parseURDF(urdf->contents);
    REQUIRE(u);
    CHECK(int(u->links_.size()) >= dynamic);
    CHECK((with_suffix(files, "urdf/", ".cut_joints.json") != nullptr) == !m.loops.empty());

    // The Modelica package.
    CHECK(with_suffix(files, "modelica/", "/package.mo"));
    CHECK(with_suffix(files, "modelica/", "/package.order"));
    CHECK(with_suffix(files, "modelica/", "/UserModel.mo"));

    // One mesh per body with geometry, and the scene when there is any.
    mbx::ExportModel em = xtest::export_model(*t, settings);
    size_t with_geometry = 0;
    for (size_t b = 0; b < m.bodies.size(); ++b)
        if (em.has_mesh(int(b))) {
            ++with_geometry;
            CHECK(xtest::find_file(files, em.mesh_path(int(b), MBX_MESH_STL)));
        }
    CHECK((xtest::find_file(files, "scene.glb") != nullptr) == (with_geometry > 0));
}

}  // namespace

TEST_CASE("all inputs: built-ins, samples and real PMXML export to every format and load in MuJoCo and urdfdom") {
    for (const Input& input : all_inputs()) check_input(input);
}
}  // namespace MBX_UNITY_ID
