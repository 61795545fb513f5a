// The URDF adapter on files written here: each joint type's primitives along
// its axis in the world, the inertial turned into the link's axes (checked
// against a pendulum's closed form), the tree's errors naming joint and line,
// package:// paths, mesh files scaled and placed, the file's own description
// (joint dynamics, collision shapes) and the findings it leaves.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "host_adapters/common/file_error.h"
#include "core/report/json_value.h"
#include "host_adapters/inputs/input_formats.h"
#include "host_adapters/urdf/urdf_adapter.h"
#include "host_adapters/urdf/urdf_assembly.h"
#include "host_adapters/urdf/urdf_reader.h"
#include "mechanism_dynamics.h"
#include "stl_text.h"
#include "tests/common/near.h"
#include "cli_support.h"
#include "translation_support.h"

namespace MBX_UNITY_ID {
namespace {

std::string robot(const std::string& body) { return "<?xml version=\"1.0\"?>\n<robot name=\"r\">\n" + body + "</robot>\n"; }

const char* kBase =
    "  <link name=\"base\"><inertial><mass value=\"2\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" "
    "izz=\"1\"/></inertial></link>\n";

std::string link(const std::string& name, double mass = 1) {
    return "  <link name=\"" + name + "\"><inertial><origin xyz=\"0.1 0 0\"/><mass value=\"" + std::to_string(mass) +
           "\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.02\" iyz=\"0\" izz=\"0.03\"/></inertial></link>\n";
}

std::string joint(const std::string& name, const std::string& type, const std::string& parent, const std::string& child,
                  const std::string& extra = "") {
    return "  <joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" + child +
           "\"/>" + extra + "</joint>\n";
}

std::string error_of(const std::string& text) {
    try {
        mbx_files::parse_urdf(text, "r.urdf");
        const mbx_files::UrdfModel m = mbx_files::parse_urdf(text, "r.urdf");
        mbx_files::to_assembly(m);
    } catch (const mbx_files::FileError& e) {
        return std::to_string(e.line()) + ": " + e.message();
    }
    return "";
}

}  // namespace

TEST_CASE("urdf: each joint type is its primitives along its axis in the world, with the file's limits") {
    // The joint frame turned 90 degrees about z: a joint axis x in it is the world's y.
    const std::string turned = "<origin xyz=\"0 0 1\" rpy=\"0 0 1.5707963267948966\"/><axis xyz=\"1 0 0\"/>";
    const std::string text = robot(std::string(kBase) + link("a") + link("b") + link("c") + link("d") + link("e") +
                                   link("f") + joint("rev", "revolute", "base", "a", turned + "<limit lower=\"-1\" upper=\"2\" effort=\"5\" velocity=\"3\"/>") +
                                   joint("cont", "continuous", "a", "b", turned) +
                                   joint("pri", "prismatic", "b", "c", turned + "<limit lower=\"0\" upper=\"0.5\" effort=\"1\" velocity=\"1\"/>") +
                                   joint("fix", "fixed", "c", "d", turned) + joint("flo", "floating", "d", "e", turned) +
                                   joint("pla", "planar", "e", "f", turned));
    const mbx_files::UrdfAssembly built = mbx_files::to_assembly(mbx_files::parse_urdf(text, "r.urdf"));
    const mbx_memory::Assembly& a = built.assembly;
    REQUIRE(a.bodies.size() == 7);
    CHECK(a.bodies[0].id == "base");
    CHECK((a.bodies[0].flags & MBX_BODY_GROUND) != 0);
    REQUIRE(a.constraints.size() == 6);
    auto axis_of = [](const mbx_memory::Primitive& p) { return Eigen::Vector3d(p.axis[0], p.axis[1], p.axis[2]); };
    const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
    // Each link sits 1 m above its parent, turned by another 90 degrees: the
    // k-th joint's x axis is the world's turned k times.
    auto world_x = [](int k) { return Eigen::Vector3d(std::cos(k * M_PI / 2), std::sin(k * M_PI / 2), 0); };
    const mbx_memory::Constraint& rev = a.constraints[0];
    CHECK(rev.id == "rev");
    REQUIRE(rev.chain.size() == 1);
    CHECK(rev.chain[0].type == MBX_PRIMITIVE_REVOLUTE);
    CHECK((axis_of(rev.chain[0]) - y).norm() < 1e-15);
    CHECK(rev.chain[0].has_limits);
    CHECK(rev.chain[0].lower == -1);
    CHECK(rev.chain[0].upper == 2);
    const mbx_memory::Constraint& cont = a.constraints[1];
    CHECK(cont.chain[0].type == MBX_PRIMITIVE_REVOLUTE);
    CHECK_FALSE(cont.chain[0].has_limits);
    CHECK((axis_of(cont.chain[0]) - world_x(2)).norm() < 1e-15);
    const mbx_memory::Constraint& pri = a.constraints[2];
    CHECK(pri.chain[0].type == MBX_PRIMITIVE_PRISMATIC);
    CHECK(pri.chain[0].upper == 0.5);
    CHECK((axis_of(pri.chain[0]) - world_x(3)).norm() < 1e-15);
    CHECK(a.constraints[3].chain[0].type == MBX_PRIMITIVE_WELD);
    const mbx_memory::Constraint& flo = a.constraints[4];
    REQUIRE(flo.chain.size() == 4);
    for (int k = 0; k < 3; ++k) CHECK(flo.chain[size_t(k)].type == MBX_PRIMITIVE_PRISMATIC);
    CHECK(flo.chain[3].type == MBX_PRIMITIVE_SPHERICAL);
    const mbx_memory::Constraint& pla = a.constraints[5];
    REQUIRE(pla.chain.size() == 3);
    CHECK(pla.chain[2].type == MBX_PRIMITIVE_REVOLUTE);
    const Eigen::Vector3d n = axis_of(pla.chain[2]), u = axis_of(pla.chain[0]), v = axis_of(pla.chain[1]);
    CHECK((n - world_x(6)).norm() < 1e-14);  // the plane's normal: the joint's axis
    CHECK(std::abs(u.dot(n)) < 1e-15);
    CHECK(std::abs(v.dot(n)) < 1e-15);
    CHECK(std::abs(u.dot(v)) < 1e-15);
    // Both frames of a joint at the child link's pose: 1 m per joint up.
    CHECK(a.frames[1].body_id == "a");
    CHECK(a.frames[1].pose.position[2] == 1);
    CHECK(a.bodies[6].pose.position[2] == 6);
}

TEST_CASE("urdf: a pendulum's inertial, turned in its origin, gives the closed-form mass matrix and gravity torque") {
    // A rod along the link's x (inertia given in axes turned 90 degrees about
    // z, so its long axis reads as y there), hinged about the world's y.
    const double m = 2, L = 0.6, r = L / 2, I_rod = m * L * L / 12;
    const std::string text = robot(
        std::string(kBase) + "  <link name=\"rod\"><inertial><origin xyz=\"" + std::to_string(r) +
        " 0 0\" rpy=\"0 0 1.5707963267948966\"/><mass value=\"2\"/><inertia ixx=\"" + std::to_string(I_rod) +
        "\" ixy=\"0\" ixz=\"0\" iyy=\"1e-6\" iyz=\"0\" izz=\"" + std::to_string(I_rod) + "\"/></inertial></link>\n" +
        joint("hinge", "continuous", "base", "rod", "<axis xyz=\"0 1 0\"/>"));
    atest::TempDir dir("mbx_urdf_pendulum");
    atest::write_file(dir.file("p.urdf"), text);
    const auto adapter = mbx_files::UrdfAdapter::open(dir.file("p.urdf"));
    const mbx_memory::Body& rod = adapter->assembly().bodies[1];
    // In the link's axes: small about x (the rod's axis), I_rod about y and z.
    CHECK(rod.inertia[0] == mbx_test::within(1e-6, 1e-15, "rounding"));
    CHECK(rod.inertia[4] == mbx_test::relative(I_rod, 1e-5));
    CHECK(rod.com[0] == mbx_test::relative(r, 1e-5));

    atest::Translation t(adapter->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    mbx_sim_model* model = nullptr;
    mbx_sim_data* data = nullptr;
    REQUIRE(mbx_sim_model_create(t.context(), t.mechanism(), nullptr, &model) == MBX_OK);
    REQUIRE(mbx_sim_data_create(t.context(), model, &data) == MBX_OK);
    for (double q : {0.0, 0.7, -2.0}) {
        double v = 0, M = 0, tau = 0, acc = 0;
        REQUIRE(mbx_sim_set_state(t.context(), data, 0, &q, &v) == MBX_OK);
        REQUIRE(mbx_sim_mass_matrix(t.context(), data, &M) == MBX_OK);
        REQUIRE(mbx_sim_inverse_dynamics(t.context(), data, &acc, &tau) == MBX_OK);
        CHECK(M == mbx_test::relative(I_rod + m * r * r, 1e-5));
        // Turned about +y by q the rod points along (cos q, 0, -sin q): gravity turns it on about +y with
        // m g r cos q, so the effort that holds it is the opposite.
        CHECK(tau == mbx_test::within(-m * 9.81 * r * std::cos(q), 1e-5, "rounding of the written numbers"));
    }
    mbx_sim_data_destroy(data);
    mbx_sim_model_destroy(model);
}

TEST_CASE("urdf: a file that cannot describe a robot is an error naming its line") {
    const std::string two = std::string(kBase) + link("a");
    struct Case {
        std::string text, expected;
    };
    const std::vector<Case> cases = {
        {"<robot name=\"r\"><link name=\"a\">", "1: not well-formed XML"},
        {"<?xml version=\"1.0\"?>\n<model/>\n", "2: not a URDF file: the root element is 'model'"},
        {robot(two + link("a")), "5: a second link named 'a'"},
        {robot(two + "  <joint name=\"j\" type=\"revolute\"><child link=\"a\"/></joint>\n"), "5: joint 'j' has no <parent"},
        {robot(two + joint("j", "hinge", "base", "a")), "5: joint 'j': type 'hinge' is not one of"},
        {robot(two + joint("j", "revolute", "base", "b")), "5: joint 'j': its child link 'b' is not in the file"},
        {robot(two + joint("j", "revolute", "base", "a", "<axis xyz=\"0 0 0\"/>")), "5: joint 'j': a zero axis"},
        {robot(two + joint("j", "revolute", "base", "a", "<origin xyz=\"0 nan 0\"/>")), "5: <origin> xyz='nan' is not a finite number"},
        {robot("  <link name=\"a\"><inertial><mass value=\"-1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>\n"),
         "3: link 'a': a negative mass"},
        {robot(two + link("b") + joint("j", "fixed", "base", "b") + joint("k", "fixed", "a", "b")),
         "7: link 'b' is the child of joint 'j' (line 6) and of joint 'k'"},
        {robot(two + link("b")), "4: 3 links have no parent joint ('base', 'a', 'b')"},
        {robot(link("a") + link("b") + joint("j", "fixed", "a", "b") + joint("k", "fixed", "b", "a")),
         "2: every link has a parent joint"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.text);
        const std::string e = error_of(c.text);
        CHECK_MESSAGE(e.rfind(c.expected, 0) == 0, e);
    }
}

TEST_CASE("urdf: package:// paths through the given packages, the longest name first, then ROS_PACKAGE_PATH") {
    atest::TempDir dir("mbx_urdf_packages");
    namespace fs = std::filesystem;
    fs::create_directories(dir.file("ws/robots/arm/meshes"));
    fs::create_directories(dir.file("other/arm_description/meshes"));
    fs::create_directories(dir.file("ros/arm_description/meshes"));
    atest::write_file(dir.file("ws/robots/arm/meshes/a.stl"), "x");
    atest::write_file(dir.file("other/arm_description/meshes/a.stl"), "x");
    atest::write_file(dir.file("ros/arm_description/meshes/b.stl"), "x");
    using mbx_files::resolve_urdf_path;
    const std::vector<std::pair<std::string, std::string>> packages = {{"data", dir.file("nowhere")},
                                                                        {"data/robots", dir.file("ws/robots")}};
    CHECK(resolve_urdf_path("package://data/robots/arm/meshes/a.stl", "/u", packages, "") ==
          dir.file("ws/robots/arm/meshes/a.stl"));
    // ROS_PACKAGE_PATH: a folder named like the package, or one that holds it.
    CHECK(resolve_urdf_path("package://arm_description/meshes/a.stl", "/u", {}, dir.file("x") + ":" + dir.file("other")) ==
          dir.file("other/arm_description/meshes/a.stl"));
    CHECK(resolve_urdf_path("package://arm_description/meshes/b.stl", "/u", {}, dir.file("ros/arm_description")) ==
          dir.file("ros/arm_description/meshes/b.stl"));
    std::string tried;
    CHECK(resolve_urdf_path("package://nothing/m.stl", "/u", {}, "", &tried).empty());
    CHECK(tried.find("no --package-path names package 'nothing'") != std::string::npos);
    CHECK(resolve_urdf_path("file:///abs/m.stl", "/u", {}, "") == "/abs/m.stl");
    CHECK(resolve_urdf_path("/abs/m.stl", "/u", {}, "") == "/abs/m.stl");
    CHECK(resolve_urdf_path("meshes/m.stl", "/u", {}, "") == "/u/meshes/m.stl");
}

TEST_CASE("urdf: mesh files are scaled and placed by their element, primitives meshed, a missing file is a finding") {
    atest::TempDir dir("mbx_urdf_meshes");
    // A unit cube from 0 to 1 (ASCII STL).
    atest::write_file(dir.file("cube.stl"), atest::stl_ascii(atest::box_triangles(Eigen::Vector3d::Constant(0.5), Eigen::Vector3d::Ones())));
    const std::string text = robot(
        "  <link name=\"base\"><visual><origin xyz=\"0 0 0.5\"/><geometry><box size=\"0.2 0.4 0.6\"/></geometry></visual>"
        "<visual><geometry><cylinder radius=\"0.1\" length=\"2\"/></geometry></visual></link>\n"
        "  <link name=\"arm\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>"
        "<visual><origin xyz=\"1 0 0\"/><geometry><mesh filename=\"cube.stl\" scale=\"2 3 4\"/></geometry></visual>\n"
        "    <visual><geometry><mesh filename=\"package://none/gone.stl\"/></geometry></visual></link>\n" +
        joint("j", "revolute", "base", "arm", "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>"));
    atest::write_file(dir.file("r.urdf"), text);
    const auto adapter = mbx_files::UrdfAdapter::open(dir.file("r.urdf"));
    const mbx_memory::Assembly& a = adapter->assembly();
    // The base's box and cylinder (URDF's along z).
    REQUIRE(a.shapes.count("base"));
    const std::vector<mbx_memory::Mesh>& base = a.shapes.at("base");
    REQUIRE(base.size() == 2);
    auto extent = [](const mbx_memory::Mesh& m, int axis) {
        double lo = 1e9, hi = -1e9;
        for (size_t v = 0; v < m.vertices.size() / 3; ++v) {
            // In the link frame: pose applied.
            double x = m.pose.position[axis];
            for (int k = 0; k < 3; ++k) x += m.pose.rotation[3 * axis + k] * m.vertices[3 * v + size_t(k)];
            lo = std::min(lo, x), hi = std::max(hi, x);
        }
        return std::make_pair(lo, hi);
    };
    CHECK(extent(base[0], 2).first == mbx_test::within(0.2, 1e-12, "rounding"));
    CHECK(extent(base[0], 1).second == mbx_test::within(0.2, 1e-12, "rounding"));
    CHECK(extent(base[1], 2).second == mbx_test::within(1.0, 1e-12, "rounding"));
    CHECK(extent(base[1], 0).second == mbx_test::within(0.1, 1e-12, "rounding"));
    // The missing package's mesh: a finding naming the file and line.
    const atest::Translation t(adapter->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    const std::vector<atest::FindingCopy> findings = t.findings();
    bool missing = false;
    for (const atest::FindingCopy& f : findings)
        if (f.code_name == "mesh_file_missing") {
            missing = true;
            CHECK(f.line == 5);
            CHECK(f.message.find("package://none/gone.stl") != std::string::npos);
            CHECK(f.message.find("no --package-path names package 'none'") != std::string::npos);
        }
    CHECK(missing);
    // The cube, scaled 2 x 3 x 4 and moved 1 m along x: from (1, 0, 0) to (3, 3, 4) in the link's frame.
    mbx_shape_stats stats{};
    stats.struct_size = sizeof stats;
    uint32_t arm = 0;
    REQUIRE(mbx_mechanism_find_part(t.mechanism(), "arm", &arm) == MBX_OK);
    REQUIRE(mbx_mechanism_get_shape_stats(t.context(), t.mechanism(), arm, &stats) == MBX_OK);
    CHECK(stats.mesh_count == 1);
    const double lo[3] = {1, 0, 0}, hi[3] = {3, 3, 4};
    for (int k = 0; k < 3; ++k) {
        CHECK(stats.bounds_min[k] == mbx_test::within(lo[k], 1e-6, "STL's floats"));
        CHECK(stats.bounds_max[k] == mbx_test::within(hi[k], 1e-6, "STL's floats"));
    }
}

TEST_CASE("urdf: joint dynamics and collision elements are the file's own description, mimic and missing limits are findings") {
    const std::string text = robot(
        "  <link name=\"base\"><collision><origin xyz=\"0 0 0.1\" rpy=\"0 0 0.5\"/><geometry><box size=\"1 2 0.2\"/></geometry></collision></link>\n" +
        link("a") + link("b") +
        "  <link name=\"c\"><collision><geometry><mesh filename=\"x.stl\"/></geometry></collision>"
        "<collision><geometry><mesh filename=\"y.stl\"/></geometry></collision>"
        "<collision name=\"tip\"><geometry><sphere radius=\"0.05\"/></geometry></collision></link>\n" +
        joint("j1", "revolute", "base", "a", "<dynamics damping=\"0.5\" friction=\"2\"/>") +
        joint("j2", "prismatic", "a", "b", "<limit lower=\"0\" upper=\"1\" effort=\"1\" velocity=\"1\"/><dynamics damping=\"3\"/>") +
        joint("j3", "continuous", "b", "c", "<mimic joint=\"j1\" multiplier=\"2\" offset=\"0.1\"/>"));
    atest::TempDir dir("mbx_urdf_description");
    atest::write_file(dir.file("r.urdf"), text);
    const auto adapter = mbx_files::UrdfAdapter::open(dir.file("r.urdf"));
    const std::string d = adapter->description();
    CHECK(d.find("<joint constraint=\"j1\" damping=\"0.5\" coulomb=\"2\"/>") != std::string::npos);
    CHECK(d.find("<joint constraint=\"j2\" damping=\"3\" coulomb=\"0\"/>") != std::string::npos);
    CHECK(d.find("constraint=\"j3\"") == std::string::npos);
    CHECK(d.find("<collision body=\"base\" shape=\"box\" size=\"1 2 0.20000000000000001\" xyz=\"0 0 0.10000000000000001\" rpy=\"0 0 0.5\"/>") !=
          std::string::npos);
    // Two collision meshes of a link: one hull of the link.
    CHECK(d.find("<collision body=\"c\" shape=\"hull\"/>") != std::string::npos);
    CHECK(d.find("shape=\"hull\"", d.find("shape=\"hull\"") + 1) == std::string::npos);
    CHECK(d.find("<collision body=\"c\" name=\"tip\" shape=\"sphere\" radius=\"0.050000000000000003\"") != std::string::npos);

    // It loads as a description file and attaches to the mechanism.
    atest::Translation t(adapter->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    mbx_mechatronics* mt = nullptr;
    REQUIRE(mbx_mechatronics_create(t.context(), &mt) == MBX_OK);
    REQUIRE_MESSAGE(mbx_mechatronics_load_drives_text(t.context(), mt, d.c_str(), "r.urdf") == MBX_OK,
                    mbx_context_last_error(t.context()));
    REQUIRE_MESSAGE(mbx_mechanism_set_mechatronics(t.context(), t.mechanism(), mt) == MBX_OK,
                    mbx_context_last_error(t.context()));
    CHECK(mbx_mechanism_collision_shape_count(t.mechanism()) == 3);  // the box, the hull, the sphere
    mbx_mechatronics_destroy(mt);

    const std::vector<atest::FindingCopy> findings = t.findings();
    bool mimic = false, no_limit = false;
    for (const atest::FindingCopy& f : findings) {
        if (f.code_name == "urdf_mimic_not_simulated") {
            mimic = true;
            CHECK(f.subject_id == "j3");
            CHECK(f.line == 9);
            CHECK(f.message.find("mimics 'j1'") != std::string::npos);
        }
        if (f.code_name == "urdf_no_limit") {
            no_limit = true;
            CHECK(f.line == 7);
        }
    }
    CHECK(mimic);
    CHECK(no_limit);

    // An inertia no rigid body has: a finding naming the <inertia> line.
    const mbx_files::UrdfModel bad = mbx_files::parse_urdf(
        robot("  <link name=\"a\"><inertial><mass value=\"1\"/>\n<inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"3\"/>"
              "</inertial></link>\n"),
        "bad.urdf");
    REQUIRE(bad.diagnostics.size() == 1);
    CHECK(bad.diagnostics[0].code == "urdf_inertia_not_physical");
    CHECK(bad.diagnostics[0].line == 4);
    CHECK(bad.diagnostics[0].message.find("break the triangle inequality") != std::string::npos);
}

TEST_CASE("urdf: a floating base is six freedoms from the world, and the input table picks URDF by its root element") {
    atest::TempDir dir("mbx_urdf_floating");
    const std::string text = robot(std::string(kBase) + link("a") + joint("j", "continuous", "base", "a"));
    atest::write_file(dir.file("robot.xml"), text);  // another extension: the root element tells
    const mbx_files::InputFormat* f = mbx_files::input_format_of(dir.file("robot.xml"));
    REQUIRE(f != nullptr);
    CHECK(std::string(f->name) == "urdf");
    mbx_files::FileInputOptions o;
    o.floating_base = true;
    const auto floating = mbx_files::open_input(dir.file("robot.xml"), o);
    const auto fixed = mbx_files::open_input(dir.file("robot.xml"));
    CHECK(atest::dynamics(floating->table(), 7).size() > atest::dynamics(fixed->table(), 1).size());
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("urdf cut-joint file: JSON read with its lines, a broken file an error naming its line") {
    using mbx::JsonValue;
    const JsonValue v = mbx::parse_json("{\n  \"a\": [1, -2.5e3, true, null],\n  \"b\": {\"c\": \"x\\n\\u00e9\"}\n}\n");
    REQUIRE(v.kind == JsonValue::Kind::object);
    const JsonValue* a = v.find("a");
    REQUIRE(a != nullptr);
    CHECK(a->line == 2);
    REQUIRE(a->array.size() == 4);
    CHECK(a->array[1].number == -2500);
    CHECK(a->array[2].boolean);
    CHECK(a->array[3].is_null());
    CHECK(v.find("b")->find("c")->string == "x\n\xC3\xA9");
    CHECK(v.find("b")->line == 3);
    struct Bad {
        std::string text;
        int line;
        std::string message;
    };
    for (const Bad& bad : std::vector<Bad>{{"{\"a\": [1, 2}", 1, "expected ']'"},
                                           {"{\n\"a\": nan}", 2, "'nan' is not a JSON value"},
                                           {"{\"a\": 1} x", 1, "text after"},
                                           {"\"open", 1, "never ends"},
                                           {std::string(100, '['), 1, "nested deeper than 64"}}) {
        CAPTURE(bad.text);
        try {
            mbx::parse_json(bad.text);
            FAIL("accepted");
        } catch (const mbx::JsonError& e) {
            CHECK(e.line() == bad.line);
            CHECK(std::string(e.what()).find(bad.message) != std::string::npos);
        }
    }

    // A cut-joint file naming a link the URDF lacks: an error naming the file and the joint's line.
    atest::TempDir dir("mbx_urdf_cut_file");
    atest::write_file(dir.file("r.urdf"), robot(std::string(kBase) + link("a") + joint("j", "continuous", "base", "a")));
    const std::string side = "\"xyz\": [0, 0, 0], \"rpy\": [0, 0, 0], \"axis\": [0, 0, 1]";
    atest::write_file(dir.file("r.cut_joints.json"),
                      "{\"format\": \"mbx-urdf-cut-joints\", \"version\": 1, \"cut_joints\": [\n"
                      "  {\"name\": \"k\", \"type\": \"revolute\", \"parent\": {\"link\": \"base\", " + side +
                          "}, \"child\": {\"link\": \"nowhere\", " + side + "}, \"limits\": null}]}\n");
    try {
        mbx_files::UrdfAdapter::open(dir.file("r.urdf"));
        FAIL("opened");
    } catch (const mbx_files::FileError& e) {
        CHECK(e.file() == dir.file("r.cut_joints.json"));
        CHECK(e.line() == 2);
        CHECK(e.message().find("link 'nowhere' is not in the URDF") != std::string::npos);
    }
    atest::write_file(dir.file("r.cut_joints.json"), "{\"format\": \"something else\"}");
    CHECK_THROWS_WITH_AS(mbx_files::UrdfAdapter::open(dir.file("r.urdf")),
                         doctest::Contains("not a cut-joint file"), mbx_files::FileError);
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("urdf round trip: joint dynamics written by mbx's URDF export come back as the file's own description, and a user's file refines them") {
    atest::TempDir dir("mbx_urdf_dynamics_trip");
    atest::write_file(dir.file("d.xml"), "<mechatronics version=\"1\">\n"
                                         "  <joint constraint=\"fourbar/rev_A\" damping=\"0.5\" coulomb=\"2\"/>\n"
                                         "  <joint constraint=\"fourbar/rev_B\" damping=\"0.25\"/>\n"
                                         "</mechatronics>\n");
    const atest::CliRun out = atest::run_cli(dir, "translate fourbar --drives '" + dir.file("d.xml") + "' --format urdf -o '" +
                                                      dir.file("out") + "'");
    INFO(out.err);
    REQUIRE(out.code == 0);
    // The URDF names the joints by the report's names (the built-in's ids are 'fourbar/rev_A').
    const auto adapter = mbx_files::UrdfAdapter::open(dir.file("out/urdf/fourbar.urdf"));
    const std::string d = adapter->description();
    CHECK(d.find("<joint constraint=\"rev_A\" damping=\"0.5\" coulomb=\"2\"/>") != std::string::npos);
    CHECK(d.find("<joint constraint=\"rev_B\" damping=\"0.25\" coulomb=\"0\"/>") != std::string::npos);
    // Read through the CLI, the URDF's dynamics reach the report; a user's file replaces rev_A's only.
    atest::write_file(dir.file("mine.xml"), "<mechatronics version=\"1\"><joint constraint=\"rev_A\" damping=\"7\"/></mechatronics>\n");
    const atest::CliRun back = atest::run_cli(dir, "translate '" + dir.file("out/urdf/fourbar.urdf") + "' --drives '" +
                                                       dir.file("mine.xml") + "' --format none -o '" + dir.file("back") + "'");
    INFO(back.err);
    REQUIRE(back.code == 0);
    const std::string report = atest::read_file(dir.file("back/report.txt"));
    CHECK(report.find("'rev_A': damping 7 N m s/rad, Coulomb 0 N m") != std::string::npos);
    CHECK(report.find("'rev_B': damping 0.25 N m s/rad") != std::string::npos);
}

TEST_CASE("urdf round trip: a joint's rated velocity and effort reach the host table and mbx's URDF export writes them back") {
    atest::TempDir dir("mbx_urdf_rated");
    const std::string text = robot(std::string(kBase) + link("a") + link("b") + link("c") +
                                   joint("rev", "revolute", "base", "a", "<axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"2\" effort=\"12.5\" velocity=\"3.25\"/>") +
                                   joint("cont", "continuous", "a", "b", "<axis xyz=\"0 1 0\"/><limit effort=\"4\" velocity=\"9\"/>") +
                                   joint("free", "continuous", "b", "c", "<axis xyz=\"0 1 0\"/>"));
    atest::write_file(dir.file("r.urdf"), text);
    const mbx_files::UrdfAssembly built = mbx_files::to_assembly(mbx_files::parse_urdf(text, "r.urdf"));
    REQUIRE(built.assembly.constraints.size() == 3);
    CHECK(built.assembly.constraints[0].chain[0].effort_limit == 12.5);
    CHECK(built.assembly.constraints[0].chain[0].velocity_limit == 3.25);
    CHECK(built.assembly.constraints[1].chain[0].effort_limit == 4);
    CHECK_FALSE(built.assembly.constraints[1].chain[0].has_limits);
    CHECK(built.assembly.constraints[2].chain[0].effort_limit == 0);

    const atest::CliRun out = atest::run_cli(dir, "translate '" + dir.file("r.urdf") + "' --format urdf -o '" + dir.file("out") + "'");
    INFO(out.err);
    REQUIRE(out.code == 0);
    const mbx_files::UrdfModel back = mbx_files::parse_urdf(atest::read_file(dir.file("out/urdf/r.urdf")), "back.urdf");
    std::map<std::string, const mbx_files::UrdfJoint*> by_name;
    for (const mbx_files::UrdfJoint& j : back.joints) by_name[j.name] = &j;
    REQUIRE(by_name.count("rev"));
    REQUIRE(by_name.count("cont"));
    REQUIRE(by_name.count("free"));
    CHECK(by_name["rev"]->effort == 12.5);
    CHECK(by_name["rev"]->velocity == 3.25);
    CHECK(by_name["rev"]->upper == 2);
    CHECK(by_name["cont"]->type == "continuous");
    CHECK(by_name["cont"]->effort == 4);
    CHECK(by_name["cont"]->velocity == 9);
    // A joint without rated values has none to write: a continuous joint no <limit>.
    CHECK_FALSE(by_name["free"]->has_limit);
}

}  // namespace MBX_UNITY_ID
