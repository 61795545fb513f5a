// The same drive gives the same effective joint inertia, effort limit and
// back-EMF damping in every format, each read back by its own consumer:
// MuJoCo for MJCF, urdfdom (limits, dynamics) and the transmission elements
// for URDF. The values are compared with each other and with the drive.
#include <urdf_parser/urdf_parser.h>

#include <pugixml.hpp>

#include <fstream>
#include <sstream>

#include "drives_support.h"
#include "export/mjcf/mjcf_export.h"
#include "mujoco_helpers.h"
#include "export/urdf/urdf_layout.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

struct Effective {
    double armature = 0, effort = 0, damping = 0, ratio = 0;
};

}  // namespace

TEST_CASE("drives: MJCF and URDF give every driven joint the same armature, effort limit and damping") {
    auto t = xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm.xml");
    const Mechanism& m = *t->mechanism;
    const std::vector<Drive> drives =
        xtest::resolve_drive_file(m, std::string(MBX_SAMPLES_DIR) + "/mechatronics/five_axis_arm_drives.xml");
    REQUIRE(drives.size() == 5);
    mbx_test::TempDir dir("drives_formats");
    ExportSettings settings;
    settings.model_name = "arm";
    settings.drives = drives;
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, settings);
    const OutputFiles files = xtest::export_to(*t, dir, MBX_EXPORT_URDF, settings);
    const OutputFile* urdf_out = xtest::find_file(files, "urdf/arm.urdf");
    REQUIRE(urdf_out);
    const urdf::ModelInterfaceSharedPtr urdf_model = urdf::parseURDF(urdf_out->contents);
    REQUIRE(urdf_model);
    pugi::xml_document urdf_xml;
    REQUIRE(urdf_xml.load_string(urdf_out->contents.c_str()));
    ExportModel em = xtest::export_model(*t, settings);
    const UrdfLayout layout = plan_urdf(em);

    size_t transmissions = 0;
    for (pugi::xml_node tr : urdf_xml.child("robot").children("transmission")) {
        (void)tr;
        ++transmissions;
    }
    CHECK(transmissions == drives.size());

    const mjModel* model = run.model.get();
    for (const Drive& d : drives) {
        INFO("drive " << d.name);
        // MJCF as MuJoCo compiled it.
        const std::string mj_joint = xtest::mjcf_joint_name(run.layout, d.joint);
        const int jid = mj_name2id(model, mjOBJ_JOINT, mj_joint.c_str());
        const int aid = mj_name2id(model, mjOBJ_ACTUATOR, mjcf_actuator_name(mj_joint).c_str());
        REQUIRE(jid >= 0);
        REQUIRE(aid >= 0);
        Effective mj;
        mj.armature = model->dof_armature[model->jnt_dofadr[jid]];
        mj.damping = model->dof_damping[model->jnt_dofadr[jid]];
        mj.ratio = model->actuator_gear[6 * aid];
        mj.effort = model->actuator_forcerange[2 * aid + 1] * mj.ratio;

        // URDF: limits and dynamics through urdfdom, the transmission as XML
        // (urdfdom does not read transmissions); Drake's convention puts
        // rotor_inertia * gear_ratio^2 on the joint.
        const std::string& u_joint = layout.joint_name[size_t(d.joint)];
        const urdf::JointConstSharedPtr joint = urdf_model->getJoint(u_joint);
        REQUIRE(joint);
        REQUIRE(joint->limits);
        REQUIRE(joint->dynamics);
        Effective ur;
        ur.effort = joint->limits->effort;
        ur.damping = joint->dynamics->damping;
        const pugi::xml_node tr = urdf_xml.child("robot").find_child([&](pugi::xml_node n) {
            return std::string(n.name()) == "transmission" &&
                   n.child("joint").attribute("name").as_string() == u_joint;
        });
        REQUIRE(tr);
        CHECK(std::string(tr.child_value("type")) == "transmission_interface/SimpleTransmission");
        const pugi::xml_node actuator = tr.child("actuator");
        ur.ratio = actuator.child("mechanicalReduction").text().as_double();
        CHECK(actuator.child("drake:gear_ratio").attribute("value").as_double() == mbx_test::relative(ur.ratio, 1e-12));
        const double rotor = actuator.child("drake:rotor_inertia").attribute("value").as_double();
        ur.armature = rotor * ur.ratio * ur.ratio;
        CHECK(joint->limits->velocity == mbx_test::relative(d.velocity_limit, 1e-12));

        for (const Effective* e : {&mj, &ur}) {
            CHECK(e->armature == mbx_test::relative(d.armature, 1e-12));
            CHECK(e->effort == mbx_test::relative(d.effort_limit, 1e-12));
            CHECK(e->damping == mbx_test::relative(d.servo.emf_damping, 1e-12));
            CHECK(e->ratio == mbx_test::relative(d.ratio, 1e-12));
        }
    }
}

TEST_CASE("drives: a model without drives exports no actuators or transmissions") {
    auto t = xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm.xml");
    mbx_test::TempDir dir("drives_none");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
    CHECK(run.model->nu == 0);
    for (int d = 0; d < run.model->nv; ++d) {
        CHECK(run.model->dof_armature[d] == 0);
        CHECK(run.model->dof_damping[d] == 0);
    }
    const OutputFiles files = xtest::export_to(*t, dir, MBX_EXPORT_URDF);
    for (const OutputFile& f : files) CHECK(f.contents.find("<transmission") == std::string::npos);
}

TEST_CASE("drives: a changed and re-exported CAD model keeps its drives on the same joints") {
    // The CAD model changes: the joints are written in reverse order and a
    // part gets heavier. The drive description, keyed by constraint ids,
    // applies unchanged.
    const std::string xml_path = std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm.xml";
    const std::string drives_path = std::string(MBX_SAMPLES_DIR) + "/mechatronics/five_axis_arm_drives.xml";
    auto before = xtest::translate_file(xml_path);
    const std::vector<Drive> original = xtest::resolve_drive_file(*before->mechanism, drives_path);

    std::string xml;
    {
        std::ifstream in(xml_path);
        std::stringstream s;
        s << in.rdbuf();
        xml = s.str();
    }
    const size_t open = xml.find("<joints>") + std::string("<joints>").size();
    const size_t close = xml.find("</joints>");
    REQUIRE(open < close);
    std::vector<std::string> joints;
    for (size_t at = xml.find("<SimpleJoint>", open); at < close; at = xml.find("<SimpleJoint>", at + 1)) {
        const size_t end = xml.find("</SimpleJoint>", at) + std::string("</SimpleJoint>").size();
        joints.push_back(xml.substr(at, end - at));
    }
    REQUIRE(joints.size() >= 5);
    std::string reversed = "\n";
    for (auto it = joints.rbegin(); it != joints.rend(); ++it) reversed += *it + "\n";
    xml = xml.substr(0, open) + reversed + xml.substr(close);
    const size_t mass = xml.find("<mass>");
    REQUIRE(mass != std::string::npos);
    xml.insert(mass + std::string("<mass>").size(), "1");  // "3.2" -> "13.2": a heavier part

    mbx_test::TempDir dir("drives_cad_change");
    // The sample's VRML and mesh files are not needed: the XML names none.
    { std::ofstream(dir.file("five_axis_arm.xml")) << xml; }
    auto after = xtest::translate_file(dir.file("five_axis_arm.xml"));
    const Mechanism& m2 = *after->mechanism;
    const std::vector<Drive> again = xtest::resolve_drive_file(m2, drives_path);
    REQUIRE(again.size() == original.size());
    const Mechanism& m1 = *before->mechanism;
    bool some_joint_moved = false;
    for (size_t i = 0; i < again.size(); ++i) {
        const Joint& j1 = m1.joints[size_t(original[i].joint)];
        const Joint& j2 = m2.joints[size_t(again[i].joint)];
        CHECK(m2.assembly.constraints[size_t(j2.constraint)].id == m1.assembly.constraints[size_t(j1.constraint)].id);
        CHECK(j2.name == j1.name);
        some_joint_moved = some_joint_moved || original[i].joint != again[i].joint;
        CHECK(again[i].armature == original[i].armature);
        CHECK(again[i].effort_limit == original[i].effort_limit);
    }
    // Reversing the file really did reorder the joints the drives land on.
    CHECK(some_joint_moved);
}
}  // namespace MBX_UNITY_ID
