// emps_axis: a ball-screw positioning axis shaped after the EMPS rig whose
// measurements are in ../shared/data/measured/emps: a steel carriage slides
// on a bed (one prismatic joint along x, stroke 0 to 0.25 m from the CAD
// pose). Its CAD mass is the carriage alone (about 9.4 kg); the drive
// description samples/mechatronics/emps_axis_drives.xml adds the motor and
// the 5 mm screw, whose reflected inertia (about 86 kg) brings the axis to
// the ~95 kg the rig's identification found. Millimetres, kilograms
// (inertia kg*m^2), steel; VRML in millimetres.
#include "mechanism_builder.h"
#include "samples.h"

namespace mbx_samples {

void make_emps_axis(const std::string& directory) {
    PmxmlUnits u;
    const double steel = 7.85e-6;  // kg/mm^3
    MechanismBuilder m("EMPS_AXIS", u, steel);

    const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
    const Eigen::Vector3d slide_at(0, 0, 50);  // carriage frame at the stroke's zero
    const Eigen::Vector3d grey(0.5, 0.5, 0.55), blue(0.2, 0.35, 0.75);

    // Bed: plate from -150 to 450 mm along x with two screw bearing blocks.
    const int bed = m.add_part(
        0, "BED", make_pose(Eigen::Vector3d::Zero()),
        {{"PLATE", box(Eigen::Vector3d(600, 200, 20), make_pose(Eigen::Vector3d(150, 0, 10))), grey},
         {"BEARING_A", box(Eigen::Vector3d(30, 60, 60), make_pose(Eigen::Vector3d(-135, 0, 50))), grey},
         {"BEARING_B", box(Eigen::Vector3d(30, 60, 60), make_pose(Eigen::Vector3d(435, 0, 50))), grey}},
        "bed_p.wrl");
    const int carriage = m.add_part(
        0, "CARRIAGE", make_pose(slide_at),
        {{"BLOCK", box(Eigen::Vector3d(200, 150, 40), make_pose(Eigen::Vector3d(0, 0, 20))), blue}}, "carriage_p.wrl");

    m.weld_to_root_part(0, bed);
    m.add_joint(bed, carriage, slide_at, {prismatic(x)});

    write_pmxml(directory + "/emps_axis.xml", m.finish());
    VrmlAssembly vrml = m.vrml("emps_axis_a.wrl", 1.0, false);
    vrml.info = {"Ball-screw positioning axis shaped after the EMPS rig", "mbx sample emps_axis"};
    write_vrml(directory, vrml);
}

}  // namespace mbx_samples
