// fourbar_imperial: a planar crank-rocker in inches and pounds, written with
// six significant digits like SimMechanics Link 3.1 wrote the classic
// Pro/E four-bar. Grashof: ground 8, crank 2, coupler 7, rocker 5 in
// (2 + 8 <= 7 + 5), crank at 60 deg, coupler and rocker on the upper branch.
// All axes along world z, all joints at z = 0; links stacked in z.
#include <cmath>

#include "mechanism_builder.h"
#include "samples.h"
#include "simscape_document.h"
#include "whole_file.h"

namespace mbx_samples {

namespace {

// Intersection of circle (b, rb) and circle (d, rd) in the xy plane, upper one.
Eigen::Vector3d circle_meet(const Eigen::Vector3d& b, double rb, const Eigen::Vector3d& d, double rd) {
    const Eigen::Vector3d bd = d - b;
    const double dist = bd.norm();
    const double along = (rb * rb - rd * rd + dist * dist) / (2 * dist);
    const double across = std::sqrt(rb * rb - along * along);
    const Eigen::Vector3d u = bd / dist;
    const Eigen::Vector3d n(-u.y(), u.x(), 0);
    Eigen::Vector3d c = b + along * u + across * n;
    if (c.y() < b.y() + along * u.y()) c = b + along * u - across * n;
    return c;
}

// A link of the four-bar in its part frame: x from 0 to `length`, a
// counterweight on its +y side near the origin, `z` the layer's centre.
std::vector<VrmlShape> link_shapes(const std::string& name, double length, double z, const Eigen::Vector3d& color) {
    const double w = 0.5, t = 0.25;
    VrmlShape bar_shape{name + "_BAR", box(Eigen::Vector3d(length + w, w, t), make_pose(Eigen::Vector3d(length / 2, 0, z))),
                        color};
    VrmlShape weight{name + "_WEIGHT",
                     box(Eigen::Vector3d(1.0, 0.5, t), make_pose(Eigen::Vector3d(0.25, w / 2 + 0.25, z))), color};
    return {bar_shape, weight};
}

}  // namespace

void make_fourbar_imperial(const std::string& directory) {
    PmxmlUnits u;
    u.length = "in";
    u.mass = "lbm";
    u.inertia = "lbm*in^2";
    u.volume = "in^3";
    u.area = "in^2";
    u.inertia_factor = 1;
    const double steel = 0.2836;  // lbm/in^3
    MechanismBuilder m("FOURBAR_IMPERIAL", u, steel);

    const double pi = std::acos(-1.0);
    const Eigen::Vector3d A(0, 0, 0), D(8, 0, 0);
    const Eigen::Vector3d B = A + 2 * Eigen::Vector3d(std::cos(pi / 3), std::sin(pi / 3), 0);
    const Eigen::Vector3d C = circle_meet(B, 7, D, 5);
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    auto along = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
        return make_pose(from, frame_from_x(to - from, z.cross(to - from)));
    };

    // The ground link's part frame is the assembly origin, like the top
    // RootPart's: only the name tells them apart when matching shapes.
    const Eigen::Vector3d grey(0.6, 0.6, 0.65);
    std::vector<VrmlShape> ground = {
        {"GROUND_PLATE", box(Eigen::Vector3d(9, 1, 0.25), make_pose(Eigen::Vector3d(4, 0, -0.375))), grey},
        {"GROUND_FOOT", box(Eigen::Vector3d(3, 1, 0.5), make_pose(Eigen::Vector3d(4, 0, -0.75))), grey}};
    const int ground_link = m.add_part(0, "GROUND_LINK", make_pose(A), ground, "ground_link_p.wrl");
    // The crank's frame shares the origin too, turned by 60 deg: orientation decides.
    const int crank = m.add_part(0, "CRANK", along(A, B), link_shapes("CRANK", 2, -0.125, {0.8, 0.2, 0.2}),
                                 "crank_p.wrl");
    const int coupler = m.add_part(0, "COUPLER", along(B, C), link_shapes("COUPLER", 7, 0.125, {0.2, 0.6, 0.2}),
                                   "coupler_p.wrl");
    const int rocker = m.add_part(0, "ROCKER", along(D, C), link_shapes("ROCKER", 5, -0.125, {0.2, 0.3, 0.8}),
                                  "rocker_p.wrl");

    m.weld_to_root_part(0, ground_link);
    m.add_joint(ground_link, crank, A, {revolute(z)});
    m.add_joint(crank, coupler, B, {revolute(z)});
    m.add_joint(coupler, rocker, C, {revolute(z)});
    m.add_joint(ground_link, rocker, D, {revolute(z)});

    PmxmlDocument doc = m.finish();
    doc.digits = 6;
    doc.created_using = "SimMechanics Link Version 3.1";
    doc.created_from = "mbx_make_samples (Pro/E-style export, 6 significant digits)";
    write_pmxml(directory + "/fourbar.xml", doc);
    VrmlAssembly vrml = m.vrml("fourbar_a.wrl", 1.0, false);
    vrml.info = {"Four-bar crank-rocker, inches", "mbx sample fourbar_imperial"};
    write_vrml(directory, vrml);

    // The same four-bar as an Onshape-style export: typed joints, the loop
    // left to the translator, numbers and STEP parts in inches and pounds.
    const std::string twin = directory + "/simscape";
    make_directory(twin);
    SimscapeXmlDocument s = m.simscape(twin, step_inch());
    s.created_from = "mbx_make_samples (the fourbar_imperial assembly, typed joints)";
    s.length_unit = "inch";
    s.mass_unit = "lbm";
    s.per_metre = 1 / 0.0254;
    s.per_kilogram = 1 / 0.45359237;
    write_simscape_xml(twin + "/fourbar.xml", s);
}

}  // namespace mbx_samples
