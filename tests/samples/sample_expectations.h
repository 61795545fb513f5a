// The samples' expected mechanisms, transcribed from their READMEs (derived
// by hand there, not taken from a run of the SDK).
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace samples_test {

struct SampleExpectation {
    std::string folder, xml, wrl;
    double vrml_scale;
    std::map<std::string, size_t> meshes;  // body name -> matched VRML meshes
    uint32_t parts, rigid_bodies, joint_nodes, joints, revolute, prismatic, spherical, welds, cut_joints, loops,
        planar_loops;
    int dof, gruebler_dof;
    uint32_t redundant;
    std::map<std::string, int> findings;  // code name -> count: all the findings there are
    double density_kg_m3;                 // every checked part's mass / mesh volume
};

inline std::vector<SampleExpectation> sample_expectations() {
    return {
        {"fourbar_imperial", "fourbar.xml", "fourbar_a.wrl", 1.0,
         {{"GROUND_LINK", 2}, {"CRANK", 2}, {"COUPLER", 2}, {"ROCKER", 2}},
         6, 3, 0, 4, 4, 0, 0, 2, 1, 1, 1, 1, -2, 3,
         {{"planar_loop", 1}},
         0.2836 * 0.45359237 / (0.0254 * 0.0254 * 0.0254)},
        {"double_cardan", "double_cardan.xml", "double_cardan_a.wrl", 1000.0,
         {{"FRAME", 4}, {"INPUT_SHAFT", 1}, {"INPUT_YOKE", 3}, {"CROSS1", 5}, {"CENTRE_YOKE", 5}, {"OUTPUT_SHAFT", 4}},
         9, 4, 1, 7, 7, 0, 0, 4, 2, 2, 0, 1, -5, 6,
         {{"redundant_constraints", 2}, {"mobility_mismatch", 2}},
         7850},
        {"five_axis_arm", "five_axis_arm.xml", "five_axis_arm_a.wrl", 1.0,
         {{"BASE", 2}, {"WAIST", 2}, {"UPPER_ARM", 3}, {"FOREARM", 1}, {"WRIST_PITCH", 2}, {"WRIST_ROLL", 2}},
         8, 5, 0, 5, 5, 0, 0, 2, 0, 0, 0, 5, 5, 0,
         {},
         2700},
        {"joints_showcase", "joints_showcase.xml", "joints_showcase_a.wrl", 1.0,
         {{"BED", 3}, {"CARRIAGE", 3}, {"PENDULUM", 2}, {"LINK", 1}, {"SLEEVE", 2}},
         7, 4, 1, 6, 1, 2, 3, 2, 1, 1, 0, 6, 6, 0,
         {},
         7850},
    };
}

}  // namespace samples_test
