// URDF read back by urdfdom: link poses composed from the parsed joints match
// mbx's forward kinematics at random joint values, inertials and visuals sit
// where the mechanism has them, joint types and limits follow the CAD data.
#include <cmath>

#include "urdf_consumer.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace urdf_test;

namespace {

std::string data_dir() { return mbx_test::shared_data("pmxml"); }

}  // namespace

TEST_CASE("urdf: every builtin parses and matches forward kinematics") {
    unsigned seed = 1;
    for (const std::string& name : mbx_stub::builtin_names()) {
        CAPTURE(name);
        auto t = xtest::translate_builtin(name);
        ExportSettings s;
        s.model_name = name;
        const Result r = check_urdf(*t, seed++, 4, s);
        CHECK(r.layout.robot == name);
    }
}

TEST_CASE("urdf: obj meshes are referenced when obj is chosen, stl otherwise") {
    auto t = xtest::translate_builtin("six_axis_arm");
    ExportSettings s;
    s.mesh_format = MBX_MESH_OBJ;
    check_urdf(*t, 11, 1, s);
    s.mesh_format = MBX_MESH_GLTF;  // URDF consumers read STL
    const Result r = check_urdf(*t, 12, 1, s);
    CHECK(r.files[0].contents.find(".stl\"") != std::string::npos);
    CHECK(r.files[0].contents.find(".gltf") == std::string::npos);
}

TEST_CASE("urdf: committed samples (spherical and prismatic joints, loops)") {
    const std::string dir = MBX_SAMPLES_DIR;
    const std::pair<const char*, const char*> samples[] = {{"fourbar_imperial/fourbar.xml", "fourbar_imperial/fourbar_a.wrl"},
                                                           {"double_cardan/double_cardan.xml", "double_cardan/double_cardan_a.wrl"},
                                                           {"five_axis_arm/five_axis_arm.xml", "five_axis_arm/five_axis_arm_a.wrl"},
                                                           {"joints_showcase/joints_showcase.xml", "joints_showcase/joints_showcase_a.wrl"}};
    unsigned seed = 100;
    for (const auto& [xml_, wrl] : samples) {
        const auto& xml = xml_;  // (CAPTURE cannot capture a structured binding)
        CAPTURE(xml);
        mbx_files::FileAdapterOptions options;
        options.shapes_path = dir + "/" + wrl;
        auto t = xtest::translate_file(dir + "/" + xml, options);
        const Result r = check_urdf(*t, seed++);
        if (std::string(xml).find("showcase") != std::string::npos) {
            CHECK(count_notes(r.notes, MBX_FINDING_EXPORT_APPROXIMATION) >= 1);  // its spherical joint
        }
    }
}

TEST_CASE("urdf: ergoCub with its STL meshes") {
    mbx_files::FileAdapterOptions options;
    options.mesh_dirs.push_back(data_dir() + "/ergocub/meshes/simmechanics");
    auto t = xtest::translate_file(data_dir() + "/ergocub/SIM_ERGOCUB_1-0.xml", options);
    ExportModel model = xtest::export_model(*t);
    int with_mesh = 0;
    for (size_t b = 0; b < t->mechanism->bodies.size(); ++b) with_mesh += model.has_mesh(int(b));
    CHECK(with_mesh > 10);
    check_urdf(*t, 7, 3);
}

TEST_CASE("urdf: ironCub models") {
    for (const char* file : {"IRONCUB-MK1_SIM_MODEL.xml", "IRONCUB-MK1_1_SIM_MODEL.xml"}) {
        CAPTURE(file);
        auto t = xtest::translate_file(data_dir() + "/ironcub/" + file);
        check_urdf(*t, 21, 3);
    }
}

TEST_CASE("urdf: both legs mechanisms") {
    for (const char* dir : {"legs_mechanism_2014", "legs_mechanism_2015"}) {
        CAPTURE(dir);
        auto t = xtest::translate_file(data_dir() + "/" + dir + "/LEGS_MECHANISM.xml");
        check_urdf(*t, 31, 3);
    }
}
}  // namespace MBX_UNITY_ID
