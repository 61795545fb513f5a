// five_axis_arm: a five-axis arm like the Mitsubishi Movemaster of the thesis
// (section 2.7.1): waist, shoulder, elbow, wrist pitch, wrist roll. Its upper
// arm is a rigid CAD sub-assembly of three parts (shoulder housing, arm
// tube, elbow housing): the PMXML exporter writes it as ONE body, the VRML
// keeps three part Transforms under that body's Transform, at poses where no
// body frame is -- so shape matching must give that body all three shapes.
// Millimetres, kilograms (inertia kg*m^2), aluminium; VRML in millimetres.
#include <cmath>

#include "mechanism_builder.h"
#include "samples.h"
#include "simscape_document.h"
#include "whole_file.h"

namespace mbx_samples {

void make_five_axis_arm(const std::string& directory) {
    PmxmlUnits u;
    const double aluminium = 2.7e-6;  // kg/mm^3
    MechanismBuilder m("FIVE_AXIS_ARM", u, aluminium);

    const double deg = std::acos(-1.0) / 180;
    const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d waist(0, 0, 150), S(0, 0, 300);
    const Eigen::Vector3d d2(std::sin(30 * deg), 0, std::cos(30 * deg));
    const Eigen::Vector3d E = S + 250 * d2;
    const Eigen::Vector3d d3(std::cos(15 * deg), 0, -std::sin(15 * deg));
    const Eigen::Vector3d W = E + 220 * d3;
    const Eigen::Vector3d T = W + 50 * d3;
    // Cylinders are built along local z: these turn it onto x and onto y.
    const Eigen::Matrix3d z_to_x = Eigen::AngleAxisd(90 * deg, y).toRotationMatrix();
    const Eigen::Matrix3d z_to_y = Eigen::AngleAxisd(-90 * deg, x).toRotationMatrix();
    const Eigen::Vector3d dark(0.25, 0.25, 0.3), orange(0.95, 0.55, 0.1), light(0.8, 0.8, 0.82);

    const int base = m.add_part(0, "BASE", make_pose(Eigen::Vector3d::Zero()),
                                {{"PLATE", cylinder(90, 30, 32, make_pose(Eigen::Vector3d(0, 0, 15))), dark},
                                 {"COLUMN", cylinder(50, 120, 32, make_pose(Eigen::Vector3d(0, 0, 90))), dark}},
                                "base_p.wrl");
    const int waist_part =
        m.add_part(0, "WAIST", make_pose(waist, Eigen::AngleAxisd(10 * deg, z).toRotationMatrix()),
                   {{"TURNTABLE", cylinder(60, 40, 32, make_pose(Eigen::Vector3d(0, 0, 20))), orange},
                    {"BRACKET", box(Eigen::Vector3d(70, 120, 90), make_pose(Eigen::Vector3d(0, 0, 85))), orange}},
                   "waist_p.wrl");

    // The rigid sub-assembly: three parts, each in its own frame, placed in
    // the upper arm's body frame (x along the arm, y the shoulder axis).
    const Eigen::Isometry3d upper_cs1 = make_pose(S, frame_from_x(d2, y));
    std::vector<MechanismBuilder::SubPart> upper = {
        {"SHOULDER_HOUSING", make_pose(Eigen::Vector3d(-10, 0, 0), z_to_y),
         {{"SHOULDER_HOUSING", cylinder(45, 90, 32), orange}}, "shoulder_housing_p.wrl"},
        {"ARM_TUBE", make_pose(Eigen::Vector3d(125, 0, 0)),
         {{"ARM_TUBE", box(Eigen::Vector3d(160, 40, 50)), orange}}, "arm_tube_p.wrl"},
        {"ELBOW_HOUSING", make_pose(Eigen::Vector3d(240, 0, 0), z_to_y),
         {{"ELBOW_HOUSING", cylinder(35, 80, 32), orange}}, "elbow_housing_p.wrl"}};
    const int upper_arm = m.add_rigid_assembly(0, "UPPER_ARM", upper_cs1, upper);

    const Eigen::Matrix3d r_forearm = frame_from_x(d3, y);
    const int forearm = m.add_part(0, "FOREARM", make_pose(E, r_forearm),
                                   {{"BEAM", box(Eigen::Vector3d(160, 36, 40), make_pose(Eigen::Vector3d(115, 0, 0))), light}},
                                   "forearm_p.wrl");
    const int wrist_pitch = m.add_part(
        0, "WRIST_PITCH", make_pose(W, r_forearm),
        {{"PIVOT", cylinder(22, 50, 24, make_pose(Eigen::Vector3d::Zero(), z_to_y)), dark},
         {"NECK", box(Eigen::Vector3d(28, 30, 30), make_pose(Eigen::Vector3d(36, 0, 0))), dark}},
        "wrist_pitch_p.wrl");
    const Eigen::Vector3d turned_y(0, std::cos(30 * deg), std::sin(30 * deg));
    const int wrist_roll = m.add_part(
        0, "WRIST_ROLL", make_pose(T, frame_from_x(d3, r_forearm * turned_y)),
        {{"FLANGE", cylinder(30, 12, 32, make_pose(Eigen::Vector3d(6, 0, 0), z_to_x)), light},
         {"GRIPPER", box(Eigen::Vector3d(30, 50, 20), make_pose(Eigen::Vector3d(27, 0, 0))), light}},
        "wrist_roll_p.wrl");

    m.weld_to_root_part(0, base);
    m.add_joint(base, waist_part, waist, {revolute(z)});
    m.add_joint(waist_part, upper_arm, S, {revolute(y)});
    m.add_joint(upper_arm, forearm, E, {revolute(y)});
    m.add_joint(forearm, wrist_pitch, W, {revolute(y)});
    m.add_joint(wrist_pitch, wrist_roll, T, {revolute(d3)});

    write_pmxml(directory + "/five_axis_arm.xml", m.finish());
    VrmlAssembly vrml = m.vrml("five_axis_arm_a.wrl", 1.0, false);
    vrml.info = {"Five-axis arm, upper arm a rigid sub-assembly of three parts", "mbx sample five_axis_arm"};
    write_vrml(directory, vrml);

    // The same arm as a current export: the upper arm a rigid sub-assembly
    // instance of its three parts, each with its own mass properties and STEP
    // file (millimetres); numbers in metres and kilograms.
    const std::string twin = directory + "/simscape";
    make_directory(twin);
    SimscapeXmlDocument s = m.simscape(twin, step_millimetre());
    s.created_from = "mbx_make_samples (the five_axis_arm assembly, a rigid sub-assembly)";
    write_simscape_xml(twin + "/five_axis_arm.xml", s);
}

}  // namespace mbx_samples
