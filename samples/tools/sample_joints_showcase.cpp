// joints_showcase: every primitive the PMXML reader has to know besides
// revolute and weld. A carriage slides along a rail on the bed (prismatic),
// a pendulum hangs from it on a ball joint (spherical), a sleeve slides and
// turns on a post of the bed (cylindrical: ONE SimpleJoint of a prismatic
// and a revolute along the same axis), and a link with ball joints at both
// ends ties the carriage to the sleeve, closing a spatial loop.
// Millimetres, kilograms (inertia kg*m^2), steel; VRML in millimetres.
#include <cmath>

#include "mechanism_builder.h"
#include "samples.h"

namespace mbx_samples {

void make_joints_showcase(const std::string& directory) {
    PmxmlUnits u;
    const double steel = 7.85e-6;  // kg/mm^3
    MechanismBuilder m("JOINTS_SHOWCASE", u, steel);

    const double deg = std::acos(-1.0) / 180;
    const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), z = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d slide_at(100, 0, 15);    // carriage part frame, on the rail
    const Eigen::Vector3d ball_pendulum(100, -80, 35);
    const Eigen::Vector3d q1(130, 20, 70);         // link's ball on the carriage
    const Eigen::Vector3d q2(330, 60, 160);        // link's ball on the sleeve arm
    const Eigen::Vector3d post(400, 0, 160);       // cylindrical joint: axis z through here

    // Bed: plate, rail and post; part frame at (-100, 0, 0).
    const Eigen::Isometry3d bed_cs1 = make_pose(Eigen::Vector3d(-100, 0, 0));
    const Eigen::Isometry3d to_bed = bed_cs1.inverse();
    const Eigen::Vector3d grey(0.5, 0.5, 0.55);
    const int bed = m.add_part(
        0, "BED", bed_cs1,
        {{"PLATE", box(Eigen::Vector3d(600, 120, 40), to_bed * make_pose(Eigen::Vector3d(200, 0, -20))), grey},
         {"RAIL", box(Eigen::Vector3d(380, 30, 15), to_bed * make_pose(Eigen::Vector3d(110, 0, 7.5))), grey},
         {"POST", cylinder(15, 250, 24, to_bed * make_pose(Eigen::Vector3d(400, 0, 125))), grey}},
        "bed_p.wrl");

    // Carriage: block on the rail, an arm out to the pendulum's ball and a
    // stud up to the link's ball (world boxes, brought into the part frame).
    const Eigen::Isometry3d carriage_cs1 = make_pose(slide_at);
    const Eigen::Isometry3d to_carriage = carriage_cs1.inverse();
    const Eigen::Vector3d blue(0.2, 0.35, 0.75);
    const int carriage = m.add_part(
        0, "CARRIAGE", carriage_cs1,
        {{"BLOCK", box(Eigen::Vector3d(80, 80, 40), to_carriage * make_pose(Eigen::Vector3d(100, 0, 35))), blue},
         {"ARM", box(Eigen::Vector3d(20, 40, 20), to_carriage * make_pose(Eigen::Vector3d(100, -60, 35))), blue},
         {"STUD", box(Eigen::Vector3d(20, 20, 15), to_carriage * make_pose(Eigen::Vector3d(130, 20, 62.5))), blue}},
        "carriage_p.wrl");

    // Pendulum: rod and bob along its x, hanging tilted from the ball.
    const Eigen::Vector3d hang = Eigen::Vector3d(0.2, -0.3, -1).normalized();
    const Eigen::Vector3d red(0.8, 0.25, 0.2);
    const int pendulum = m.add_part(
        0, "PENDULUM", make_pose(ball_pendulum, frame_from_x(hang, x)),
        {{"ROD", box(Eigen::Vector3d(180, 14, 14), make_pose(Eigen::Vector3d(100, 0, 0))), red},
         {"BOB", box(Eigen::Vector3d(40, 40, 40), make_pose(Eigen::Vector3d(210, 0, 0))), red}},
        "pendulum_p.wrl");

    // Link between the two balls, along its x.
    const Eigen::Vector3d d = q2 - q1;
    const Eigen::Vector3d green(0.25, 0.65, 0.3);
    const int link = m.add_part(
        0, "LINK", make_pose(q1, frame_from_x(d, z)),
        {{"ROD", box(Eigen::Vector3d(d.norm() - 24, 12, 12), make_pose(Eigen::Vector3d(d.norm() / 2, 0, 0))), green}},
        "link_p.wrl");

    // Sleeve: a bored collar around the post (axis = its local y = world z)
    // and an arm out to the link's ball along its local x.
    const Eigen::Vector3d out = Eigen::Vector3d(q2.x() - post.x(), q2.y() - post.y(), 0);
    const Eigen::Matrix3d r_sleeve = frame_from_x(out, z);
    const Eigen::Matrix3d z_to_y = Eigen::AngleAxisd(-90 * deg, x).toRotationMatrix();
    const Eigen::Vector3d yellow(0.9, 0.75, 0.15);
    const int sleeve = m.add_part(
        0, "SLEEVE", make_pose(post, r_sleeve),
        {{"COLLAR", tube(16, 28, 60, 24, make_pose(Eigen::Vector3d::Zero(), z_to_y)), yellow},
         {"ARM", box(Eigen::Vector3d(out.norm() - 38, 16, 16), make_pose(Eigen::Vector3d((out.norm() + 28) / 2 - 5, 0, 0))),
          yellow}},
        "sleeve_p.wrl");

    m.weld_to_root_part(0, bed);
    m.add_joint(bed, carriage, slide_at, {prismatic(x)});
    m.add_joint(carriage, pendulum, ball_pendulum, {spherical()});
    m.add_joint(bed, sleeve, post, {prismatic(z), revolute(z)});
    m.add_joint(carriage, link, q1, {spherical()});
    m.add_joint(link, sleeve, q2, {spherical()});

    write_pmxml(directory + "/joints_showcase.xml", m.finish());
    VrmlAssembly vrml = m.vrml("joints_showcase_a.wrl", 1.0, false);
    vrml.info = {"Prismatic, spherical and cylindrical joints, one spatial loop", "mbx sample joints_showcase"};
    write_vrml(directory, vrml);
}

}  // namespace mbx_samples
