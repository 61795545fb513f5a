// double_cardan: the thesis's double cardan shaft. An input shaft and an
// output shaft turn in bearings on a frame, parallel to world x and offset;
// a centre yoke joins them through two cardan joints and turns in a third
// bearing. Cardan 1's cross is a part (in the CARDAN_SHAFT sub-assembly with
// the centre yoke); cardan 2 is ONE SimpleJoint of two revolutes, its cross a
// massless joint node. Millimetres and kilograms (inertia kg*m^2), VRML in
// metres as stl2vrml writes it.
//
// Geometry (mm): P1 = (200, 0, 0) on the input axis, c = (cos 20, sin 20, 0)
// the centre yoke axis, P2 = P1 + 300 c on the output axis (parallel to x);
// input fork a1 = (0, -sin 30, cos 30), centre forks b1 = b2 = unit(c x a1),
// output fork a2 = unit(x x b2).
#include <cmath>

#include "mechanism_builder.h"
#include "samples.h"
#include "simscape_document.h"
#include "whole_file.h"

namespace mbx_samples {

void make_double_cardan(const std::string& directory) {
    PmxmlUnits u;  // mm, kg, kg*m^2
    const double steel = 7.85e-6;  // kg/mm^3
    MechanismBuilder m("DOUBLE_CARDAN", u, steel);

    const double deg = std::acos(-1.0) / 180;
    const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY();
    const Eigen::Vector3d P1(200, 0, 0);
    const Eigen::Vector3d c(std::cos(20 * deg), std::sin(20 * deg), 0);
    const Eigen::Vector3d P2 = P1 + 300 * c;
    const Eigen::Vector3d a1(0, -std::sin(30 * deg), std::cos(30 * deg));
    const Eigen::Vector3d b1 = c.cross(a1).normalized();
    const Eigen::Vector3d b2 = b1;
    const Eigen::Vector3d a2 = x.cross(b2).normalized();
    const Eigen::Vector3d bearing_in(50, 0, 0), bearing_centre = P1 + 150 * c, bearing_out = P2 + 150 * x;
    // Cylinders are built along their local z; this turns local z onto world x.
    const Eigen::Matrix3d z_to_x = Eigen::AngleAxisd(90 * deg, y).toRotationMatrix();

    // Frame: a bed under everything and a pedestal under each bearing.
    const Eigen::Isometry3d frame_cs1 = make_pose(Eigen::Vector3d(250, 0, -120));
    const Eigen::Isometry3d to_frame = frame_cs1.inverse();
    const Eigen::Vector3d grey(0.55, 0.55, 0.6);
    std::vector<VrmlShape> frame = {
        {"BED", box(Eigen::Vector3d(720, 220, 30), to_frame * make_pose(Eigen::Vector3d(340, 50, -120))), grey}};
    int k = 0;
    for (const Eigen::Vector3d& at : {bearing_in, bearing_centre, bearing_out}) {
        const Eigen::Vector3d foot(at.x(), at.y(), -67.5);  // from the bed's top (z -105) up to z -30
        frame.push_back({"PEDESTAL_" + std::to_string(++k), box(Eigen::Vector3d(40, 40, 75), to_frame * make_pose(foot)),
                         grey});
    }
    const int frame_part = m.add_part(0, "FRAME", frame_cs1, frame, "frame_p.wrl");

    // Input shaft from x = 0 to 175, part frame at x = 90 (not its middle).
    const Eigen::Vector3d steel_blue(0.35, 0.45, 0.6);
    const int input_shaft =
        m.add_part(0, "INPUT_SHAFT", make_pose(Eigen::Vector3d(90, 0, 0)),
                   {{"SHAFT", cylinder(12, 175, 24, make_pose(Eigen::Vector3d(-2.5, 0, 0), z_to_x)), steel_blue}},
                   "input_shaft_p.wrl");

    // Input yoke: a hub and two prongs along its local z (= a1).
    const Eigen::Matrix3d r_yoke = Eigen::AngleAxisd(30 * deg, x).toRotationMatrix();
    const Eigen::Vector3d orange(0.85, 0.5, 0.15);
    const int input_yoke = m.add_part(
        0, "INPUT_YOKE", make_pose(P1 - 20 * x, r_yoke),
        {{"HUB", box(Eigen::Vector3d(15, 40, 40), make_pose(Eigen::Vector3d(-7.5, 0, 0))), orange},
         {"PRONG_A", box(Eigen::Vector3d(30, 16, 8), make_pose(Eigen::Vector3d(15, 0, 26))), orange},
         {"PRONG_B", box(Eigen::Vector3d(30, 16, 8), make_pose(Eigen::Vector3d(15, 0, -26))), orange}},
        "input_yoke_p.wrl");

    // The cardan shaft sub-assembly, placed at P1: its RootPart sits where
    // the cross's part frame does, but world-aligned.
    const int shaft = m.add_subsystem(0, "CARDAN_SHAFT", make_pose(P1));
    const Eigen::Vector3d red(0.75, 0.2, 0.2);
    std::vector<VrmlShape> cross = {{"HUB", box(Eigen::Vector3d(16, 16, 16)), red}};
    const Eigen::Matrix3d z_to_y = Eigen::AngleAxisd(-90 * deg, x).toRotationMatrix();
    for (int s : {1, -1}) {
        cross.push_back({s > 0 ? "ARM_XP" : "ARM_XN", cylinder(5, 14, 16, make_pose(Eigen::Vector3d(s * 15, 0, 0), z_to_x)), red});
        cross.push_back({s > 0 ? "ARM_YP" : "ARM_YN", cylinder(5, 14, 16, make_pose(Eigen::Vector3d(0, s * 15, 0), z_to_y)), red});
    }
    const int cross1 = m.add_part(shaft, "CROSS1", make_pose(P1, frame_from_x(a1, b1)), cross, "cross1_p.wrl");

    // Centre yoke: a tube along its local x (= c) with forks at both ends
    // along its local y (= b1 = b2).
    const Eigen::Vector3d green(0.3, 0.6, 0.35);
    std::vector<VrmlShape> centre = {{"TUBE", cylinder(15, 240, 24, make_pose(Eigen::Vector3d::Zero(), z_to_x)), green}};
    for (int end : {-1, 1})
        for (int side : {-1, 1})
            centre.push_back({std::string(end < 0 ? "FORK_IN_" : "FORK_OUT_") + (side < 0 ? "N" : "P"),
                              box(Eigen::Vector3d(40, 8, 16), make_pose(Eigen::Vector3d(end * 140, side * 26, 0))), green});
    const int centre_yoke = m.add_part(shaft, "CENTRE_YOKE", make_pose(P1 + 150 * c, frame_from_x(c, b1)), centre,
                                       "centre_yoke_p.wrl");

    // Output shaft: prongs along a2 at P2, then a hub and the shaft along x.
    const Eigen::Matrix3d r_prongs = frame_from_x(x, a2);
    const int output_shaft = m.add_part(
        0, "OUTPUT_SHAFT", make_pose(P2),
        {{"PRONG_A", box(Eigen::Vector3d(30, 8, 16), make_pose(r_prongs * Eigen::Vector3d(5, 26, 0), r_prongs)), steel_blue},
         {"PRONG_B", box(Eigen::Vector3d(30, 8, 16), make_pose(r_prongs * Eigen::Vector3d(5, -26, 0), r_prongs)), steel_blue},
         {"HUB", box(Eigen::Vector3d(15, 40, 40), make_pose(Eigen::Vector3d(27.5, 0, 0))), steel_blue},
         {"SHAFT", cylinder(12, 165, 24, make_pose(Eigen::Vector3d(117.5, 0, 0), z_to_x)), steel_blue}},
        "output_shaft_p.wrl");

    // Host order decides the cut joints (README): bearing_centre makes the
    // centre yoke a tree body before cross1_out (stored in the subsystem,
    // so read last) closes loop 1.
    m.weld_to_root_part(0, frame_part);
    m.add_joint(frame_part, input_shaft, bearing_in, {revolute(x)});
    m.add_joint(input_shaft, input_yoke, P1 - 40 * x, {weld()});
    m.add_joint(input_yoke, cross1, P1, {revolute(a1)});
    m.add_joint(frame_part, centre_yoke, bearing_centre, {revolute(c)});
    m.add_joint(frame_part, output_shaft, bearing_out, {revolute(x)});
    m.add_joint(centre_yoke, output_shaft, P2, {revolute(b2), revolute(a2)});
    m.weld_to_root_part(shaft, cross1);
    m.add_joint(cross1, centre_yoke, P1, {revolute(b1)});

    write_pmxml(directory + "/double_cardan.xml", m.finish());
    VrmlAssembly vrml = m.vrml("double_cardan_a.wrl", 1000.0, false);
    vrml.info = {"Double cardan shaft, VRML in metres (model in millimetres)", "mbx sample double_cardan"};
    write_vrml(directory, vrml);

    // The same shaft as a current export: the CARDAN_SHAFT subsystem a
    // nested sub-assembly instance whose Assembly holds its joint, STEP parts
    // in millimetres, numbers in metres and kilograms.
    const std::string twin = directory + "/simscape";
    make_directory(twin);
    SimscapeXmlDocument s = m.simscape(twin, step_millimetre());
    s.created_from = "mbx_make_samples (the double_cardan assembly, a nested sub-assembly)";
    write_simscape_xml(twin + "/double_cardan.xml", s);
}

}  // namespace mbx_samples
