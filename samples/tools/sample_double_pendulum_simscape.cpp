// double_pendulum_simscape: the DFKI double pendulum (design C.0, whose
// measured runs are in ../shared/data/measured/dfki_double_pendulum_c0) as a
// Simscape Multibody second-generation export with typed joints, built on
// its real STEP levers in ../shared/data/step/dfki_double_pendulum: a motor
// mount on the ground, the 200 mm lever on the shoulder, the 300 mm lever on
// the elbow at the first lever's far bore. Each lever's mass properties come
// from its solid (mbx's STEP reader, aluminium), rounded as exporters print
// them. The levers' own frames have the hub bore's axis as z; the pendulum
// hangs in the world's x-z plane, both hinges along the world's y axis.
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/geometry/mesh_properties.h"
#include "host_adapters/step/assembly.h"
#include "host_adapters/step/tessellate.h"
#include "samples.h"
#include "simscape_document.h"

namespace mbx_samples {
namespace {

constexpr double kAluminium = 2700;  // kg/m^3

// Six significant digits, as exporters print mass properties: the sample
// stays the same when the mesher's last digits move; what is below `zero`
// is the mesh's rounding on a symmetric part.
double rounded(double x, double zero) {
    if (std::abs(x) < zero || !std::isfinite(x)) return 0;
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.6g", x);
    return std::strtod(buffer, nullptr);
}

SimscapeXmlPart lever(const std::string& step_dir, const std::string& file, const std::string& uid,
                      const std::string& name) {
    const std::string path = step_dir + "/" + file;
    const mbx_step::File f = mbx_step::read_part21_file(path);
    const mbx_step::Brep b = mbx_step::read_breps(f);
    const std::vector<mbx_step::SolidMesh> meshes = mbx_step::tessellate(b, mbx_step::Tolerance{});
    if (meshes.size() != 1 || !meshes[0].problems.empty()) throw std::runtime_error(path + ": not one clean solid");
    std::vector<uint32_t> flat;
    for (const auto& t : meshes[0].mesh.triangles) flat.insert(flat.end(), t.begin(), t.end());
    mbx::SolidAccumulator acc;
    acc.add(meshes[0].mesh.points, flat);
    const mbx::SolidProperties p = acc.result();
    SimscapeXmlPart part;
    part.uid = uid;
    part.name = name;
    part.mass = rounded(p.volume * kAluminium, 0);
    for (int k = 0; k < 3; ++k) part.com[k] = rounded(p.centroid[k], 1e-9);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) part.inertia(r, c) = rounded(p.inertia_per_density(r, c) * kAluminium, 1e-12);
    part.inertia = (0.5 * (part.inertia + part.inertia.transpose())).eval();
    part.geometry_file = file;
    part.colour = Eigen::Vector4d(0.753, 0.753, 0.753, 1);
    return part;
}

Eigen::Isometry3d frame(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& at) {
    Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
    x.linear() = rotation;
    x.translation() = at;
    return x;
}

}  // namespace

SimscapeXmlDocument double_pendulum_simscape(const std::string& step_dir) {
    SimscapeXmlDocument d;
    d.created_from = "mbx_make_samples (DFKI double pendulum C.0 levers)";
    d.root_name = "double_pendulum";
    d.root_uid = "dp0root";
    d.digits = 10;
    SimscapeXmlPart mount;
    mount.uid = "dp-mount";
    mount.name = "motor_mount";
    mount.mass = 1.0806;  // the authors' base link
    mount.com = Eigen::Vector3d(-0.025147, 0, -0.021712);
    mount.inertia << 0.0052004, 0, -0.00037275, 0, 0.001836, 0, -0.00037275, 0, 0.0051241;
    mount.colour = Eigen::Vector4d(0.898, 0.918, 0.929, 1);
    d.parts = {mount, lever(step_dir, "lever_200.STEP", "dp-lever200", "lever_200"),
               lever(step_dir, "lever_300.STEP", "dp-lever300", "lever_300")};
    // Lever frames: x along the lever (hanging down, world -z), z the hinge
    // (world y); the second lever sits 30 mm further along the hinge axis.
    Eigen::Matrix3d hanging;
    hanging.col(0) = -Eigen::Vector3d::UnitZ();
    hanging.col(2) = Eigen::Vector3d::UnitY();
    hanging.col(1) = hanging.col(2).cross(hanging.col(0));
    const Eigen::Isometry3d shoulder_world = frame(hanging, Eigen::Vector3d(0, 0.0342, 0));
    const Eigen::Isometry3d lever1 = shoulder_world;
    const Eigen::Isometry3d lever2 = lever1 * frame(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.2, 0, 0.03));
    d.instances = {{"Mmount1", "motor_mount <1>", "dp-mount", Eigen::Isometry3d::Identity(), true, false, "", {}},
                   {"Mlever1", "lever_200 <1>", "dp-lever200", lever1, false, false, "", {}},
                   {"Mlever2", "lever_300 <1>", "dp-lever300", lever2, false, false, "", {}}};
    // The shoulder on the hub bore (the lever's origin), the elbow on the
    // 200 mm lever's far bore and the 300 mm lever's hub.
    const Eigen::Isometry3d elbow_in_lever1 = frame(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.2, 0, 0.03));
    d.joints = {{"Revolute", "shoulder", {{"Mmount1"}, shoulder_world}, {{"Mlever1"}, Eigen::Isometry3d::Identity()}},
                {"Revolute", "elbow", {{"Mlever1"}, elbow_in_lever1}, {{"Mlever2"}, Eigen::Isometry3d::Identity()}}};
    return d;
}

// The same export as SolidWorks, Creo and Inventor write it: no joints, a
// concentric and a coincident mate at each hinge (the hub bore's axis and the
// lever's face), each geometry in its instance's frame.
SimscapeXmlDocument double_pendulum_mates(const SimscapeXmlDocument& typed) {
    SimscapeXmlDocument d = typed;
    d.joints.clear();
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ(), y = Eigen::Vector3d::UnitY();
    const Eigen::Vector3d shoulder(0, 0.0342, 0), elbow(0.2, 0, 0.03);
    d.mates = {{"Concentric", "Concentric1", {"cylinder", {"Mmount1"}, shoulder, y}, {"cylinder", {"Mlever1"}, {0, 0, 0}, z}},
               {"Coincident", "Coincident1", {"plane", {"Mmount1"}, shoulder, y}, {"plane", {"Mlever1"}, {0, 0, 0}, -z}},
               {"Concentric", "Concentric2", {"cylinder", {"Mlever1"}, elbow, z}, {"cylinder", {"Mlever2"}, {0, 0, 0}, z}},
               {"Coincident", "Coincident2", {"plane", {"Mlever1"}, elbow, z}, {"plane", {"Mlever2"}, {0, 0, 0}, -z}}};
    return d;
}

void make_double_pendulum_simscape(const std::string& directory) {
    const SimscapeXmlDocument typed = double_pendulum_simscape(MBX_SHARED_STEP_DIR);
    write_simscape_xml(directory + "/double_pendulum.xml", typed);
    write_simscape_xml(directory + "/double_pendulum_mates.xml", double_pendulum_mates(typed));
}

}  // namespace mbx_samples
