// The mechanisms the exporter and simulator tests run on: mbx's built-ins,
// the bundled samples (PMXML + VRML shapes, and the Simscape export on its
// STEP levers), the real PMXML exports in
// ../shared and the small assemblies of the MJCF tests, each translated by
// mbx's own pipeline.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "export_fixture.h"
#include "host_adapters/simscape/simscape_adapter.h"
#include "mujoco_assemblies.h"
#include "tests/common/shared_data.h"

namespace simtest {

struct Input {
    std::string label;
    std::function<std::unique_ptr<xtest::Translated>()> open;
};

inline std::unique_ptr<xtest::Translated> open_sample(const std::string& folder, const std::string& stem) {
    const std::string dir = std::string(MBX_SAMPLES_DIR) + "/" + folder;
    mbx_files::FileAdapterOptions o;
    o.shapes_path = dir + "/" + stem + "_a.wrl";
    return xtest::translate_file(dir + "/" + stem + ".xml", o);
}

inline std::vector<Input> builtin_inputs() {
    std::vector<Input> in;
    for (const std::string& name : mbx_stub::builtin_names())
        in.push_back({"builtin " + name, [name] { return xtest::translate_builtin(name); }});
    return in;
}

// A Simscape sample: `file` under samples/, its STEP parts beside it or in `mesh_dir`.
inline std::unique_ptr<xtest::Translated> open_simscape_sample(const std::string& file, const std::string& mesh_dir = "") {
    mbx_files::FileInputOptions o;
    if (!mesh_dir.empty()) o.mesh_dirs.push_back(mesh_dir);
    std::shared_ptr<mbx_files::SimscapeAdapter> adapter =
        mbx_files::SimscapeAdapter::open(std::string(MBX_SAMPLES_DIR) + "/" + file, o);
    return xtest::translate_table(adapter->table(), adapter);
}

// Every folder of samples/ that holds an assembly.
inline std::vector<Input> sample_inputs() {
    std::vector<Input> in;
    for (const auto& [folder, stem] : std::vector<std::pair<std::string, std::string>>{
             {"double_cardan", "double_cardan"},
             {"emps_axis", "emps_axis"},
             {"five_axis_arm", "five_axis_arm"},
             {"fourbar_imperial", "fourbar"},
             {"joints_showcase", "joints_showcase"}})
        in.push_back({"sample " + folder, [folder = folder, stem = stem] { return open_sample(folder, stem); }});
    // The DFKI pendulum in both dialects, its levers' STEP files from ../shared.
    for (const char* file : {"double_pendulum_simscape/double_pendulum.xml", "double_pendulum_simscape/double_pendulum_mates.xml"})
        in.push_back({std::string("sample ") + file,
                      [file] { return open_simscape_sample(file, mbx_test::shared_data("step/dfki_double_pendulum")); }});
    // The PMXML samples' Simscape twins: a loop, a nested and a rigid sub-assembly.
    for (const char* file : {"fourbar_imperial/simscape/fourbar.xml", "double_cardan/simscape/double_cardan.xml",
                             "five_axis_arm/simscape/five_axis_arm.xml"})
        in.push_back({std::string("sample ") + file, [file] { return open_simscape_sample(file); }});
    return in;
}

inline std::vector<Input> shared_pmxml_inputs() {
    std::vector<Input> in;
    const std::string data = mbx_test::shared_data("pmxml");
    in.push_back({"ergoCub", [data] {
                      mbx_files::FileAdapterOptions o;
                      o.mesh_dirs.push_back(data + "/ergocub/meshes/simmechanics");
                      return xtest::translate_file(data + "/ergocub/SIM_ERGOCUB_1-0.xml", o);
                  }});
    for (const char* f : {"/ironcub/IRONCUB-MK1_SIM_MODEL.xml", "/ironcub/IRONCUB-MK1_1_SIM_MODEL.xml",
                          "/legs_mechanism_2014/LEGS_MECHANISM.xml", "/legs_mechanism_2015/LEGS_MECHANISM.xml"}) {
        const std::string path = data + f;
        in.push_back({path.substr(data.size() + 1), [path] { return xtest::translate_file(path); }});
    }
    return in;
}

inline std::vector<Input> small_inputs() {
    namespace a = xtest::mjcf_assemblies;
    return {
        {"pendulum", [] { return xtest::translate(a::Pendulum().assembly()); }},
        {"tumbler (free body)", [] { return xtest::translate(a::Tumbler().assembly()); }},
        {"double pendulum", [] { return xtest::translate(a::double_pendulum()); }},
        {"spatial (universal, spherical, cylindrical, floating)", [] { return xtest::translate(a::spatial()); }},
        {"slider_crank (prismatic cut)", [] { return xtest::translate(a::slider_crank()); }},
    };
}

}  // namespace simtest
