// mbx_mechanism_update_urdf: a description's joint dynamics and body
// corrections written into the user's own URDF. The file read back must be
// the described model (a welded body's links sharing its correction in
// their own turned inertial frames), the text must differ only where a
// value changed, and a file the mechanism was not read from must be refused
// with its line.
#include <cmath>
#include <filesystem>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <urdf_parser/urdf_parser.h>

#include "adapter_test_support.h"
#include "host_adapters/urdf/urdf_adapter.h"
#include "tests/common/near.h"
#include "translation_support.h"

namespace MBX_UNITY_ID {
namespace {

// A URDF opened and translated through the C API with its own description
// and `extra` (a description file's text) attached.
struct Opened {
    std::unique_ptr<mbx_files::UrdfAdapter> adapter;
    std::unique_ptr<atest::Translation> t;
    mbx_mechatronics* mechatronics = nullptr;

    Opened(const std::string& path, const std::string& extra) {
        adapter = mbx_files::UrdfAdapter::open(path);
        t = std::make_unique<atest::Translation>(adapter->table(), 0);
        REQUIRE(t->status() == MBX_OK);
        REQUIRE(mbx_mechatronics_create(ctx(), &mechatronics) == MBX_OK);
        if (!adapter->description().empty())
            REQUIRE(mbx_mechatronics_load_drives_text(ctx(), mechatronics, adapter->description().c_str(), path.c_str()) == MBX_OK);
        if (!extra.empty())
            REQUIRE_MESSAGE(mbx_mechatronics_load_drives_text(ctx(), mechatronics, extra.c_str(), "d.xml") == MBX_OK,
                            std::string(mbx_context_last_error(ctx())));
        REQUIRE_MESSAGE(mbx_mechanism_set_mechatronics(ctx(), mech(), mechatronics) == MBX_OK, std::string(mbx_context_last_error(ctx())));
    }
    ~Opened() {
        t.reset();
        mbx_mechatronics_destroy(mechatronics);
    }
    mbx_context* ctx() const { return t->context(); }
    mbx_mechanism* mech() const { return t->mechanism(); }

    mbx_rigid_body_info body_of(const std::string& part) const {
        uint32_t index = 0;
        REQUIRE(mbx_mechanism_find_part(mech(), part.c_str(), &index) == MBX_OK);
        mbx_rigid_body_info b{};
        b.struct_size = sizeof b;
        REQUIRE(mbx_mechanism_get_rigid_body(mech(), index, &b) == MBX_OK);
        return b;
    }
};

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::string without_values(const std::string& line) { return std::regex_replace(line, std::regex("\"[^\"]*\""), "\"\""); }

// Two bodies with the same mass, centre of mass and inertia.
void check_same_body(const mbx_rigid_body_info& got, const mbx_rigid_body_info& want) {
    CHECK(got.mass == mbx_test::relative(want.mass, 1e-12));
    double com = 0, inertia = 0, scale = 0;
    for (int k = 0; k < 3; ++k) com = std::max(com, std::fabs(got.com[k] - want.com[k]));
    for (int k = 0; k < 9; ++k) {
        inertia = std::max(inertia, std::fabs(got.inertia[k] - want.inertia[k]));
        scale = std::max(scale, std::fabs(want.inertia[k]));
    }
    CHECK(com < 1e-12);
    CHECK(inertia < 1e-12 * scale);
}

// An arm on a hinge with a tool bolted to it: one rigid body of two massive
// links, every inertial frame and the bolt turned, no <dynamics> on the hinge,
// a comment and a tag mbx does not know.
const char* kWelded = R"(<?xml version="1.0"?>
<!-- the user's comment, kept -->
<robot name="welded">
  <link name="base"/>
  <joint name="hinge" type="revolute">
    <origin xyz="0 0 1" rpy="0 0 0"/>
    <parent link="base"/>
    <child link="arm"/>
    <axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="5"/>
  </joint>
  <link name="arm">
    <inertial>
      <origin xyz="0.1 0.02 -0.2" rpy="0.3 -0.2 0.5"/>
      <mass value="2.0"/>
      <inertia ixx="0.03" ixy="0.001" ixz="-0.002" iyy="0.04" iyz="0.0015" izz="0.02"/>
    </inertial>
    <gazebo_extension reference='arm' colour = "red" />
  </link>
  <joint name="bolt" type="fixed">
    <origin xyz="0.05 0 -0.4" rpy="0.7 0.1 -0.4"/>
    <parent link="arm"/>
    <child link="tool"/>
  </joint>
  <link name="tool">
    <inertial>
      <origin xyz="0 0.01 -0.05" rpy="-0.4 0.2 0.9"/>
      <mass value="0.5"/>
      <inertia ixx="0.004" ixy="0.0002" ixz="0" iyy="0.003" iyz="-0.0001" izz="0.002"/>
    </inertial>
  </link>
</robot>
)";

std::string welded() { return kWelded; }

const char* kWeldedDescription = R"(<mechatronics version="1">
  <joint constraint="hinge" damping="0.3" coulomb="0.1"/>
  <body id="tool" mass_scale="1.25" com_shift="0.01 -0.02 0.03" inertia_change="0.002 -0.001 0.003 0.0004 -0.0002 0.0001"/>
</mechatronics>
)";

std::string dfki() { return mbx_test::shared_data("measured/dfki_double_pendulum_c0/identified_model_3.1_acrobot.urdf"); }

}  // namespace

TEST_CASE("urdf update: a welded body's correction shared by its links in their turned frames reads back as that body") {
    atest::TempDir dir("mbx_urdf_update");
    const std::string input = dir.file("welded.urdf"), output = dir.file("out.urdf");
    atest::write_file(input, welded());
    mbx_rigid_body_info described{};
    {
        Opened o(input, kWeldedDescription);
        described = o.body_of("tool");
        CHECK(described.part_count == 2);
        REQUIRE_MESSAGE(mbx_mechanism_update_urdf(o.ctx(), o.mech(), input.c_str(), output.c_str()) == MBX_OK,
                        std::string(mbx_context_last_error(o.ctx())));
    }
    const std::string before = atest::read_file(input), after = atest::read_file(output);

    // The body read back is the described one, the hinge has its dynamics.
    Opened back(output, "");
    check_same_body(back.body_of("arm"), described);
    const std::string own = back.adapter->description();
    std::smatch hinge_dynamics;
    REQUIRE(std::regex_search(own, hinge_dynamics, std::regex("constraint=\"hinge\" damping=\"([^\"]*)\" coulomb=\"([^\"]*)\"")));
    CHECK(std::stod(hinge_dynamics[1]) == 0.3);
    CHECK(std::stod(hinge_dynamics[2]) == 0.1);
    // Without the description the input's body is another.
    Opened plain(input, "");
    CHECK(std::fabs(plain.body_of("arm").mass - described.mass) > 0.1);

    // The text: one line inserted after the hinge's start tag, indented like
    // its children; only the two links' inertial lines differ otherwise, and
    // only inside attribute values.
    const std::vector<std::string> a = lines_of(before), b = lines_of(after);
    REQUIRE(b.size() == a.size() + 1);
    size_t hinge = 0;
    while (hinge < a.size() && a[hinge].find("<joint name=\"hinge\"") == std::string::npos) ++hinge;
    REQUIRE(hinge + 1 < b.size());
    CHECK(b[hinge + 1] == "    <dynamics damping=\"0.3\" friction=\"0.1\"/>");
    std::vector<std::string> b_without = b;
    b_without.erase(b_without.begin() + std::ptrdiff_t(hinge + 1));
    int changed = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (a[i] == b_without[i]) continue;
        ++changed;
        CHECK_MESSAGE(std::regex_search(a[i], std::regex("<origin xyz|<mass|<inertia ")), "line " << i + 1 << ": " << b_without[i]);
        CHECK(without_values(a[i]) == without_values(b_without[i]));
    }
    CHECK(changed == 6);  // origin, mass, inertia of both links
    CHECK(after.find("<!-- the user's comment, kept -->") != std::string::npos);
    CHECK(after.find("<gazebo_extension reference='arm' colour = \"red\" />") != std::string::npos);

    // urdfdom reads the new numbers: every mass scaled alike.
    const urdf::ModelInterfaceSharedPtr u = urdf::parseURDF(after);
    REQUIRE(u);
    CHECK(u->getLink("tool")->inertial->mass == mbx_test::relative(0.5 * 1.25, 1e-15));
    CHECK(u->getLink("arm")->inertial->mass == mbx_test::relative(2.0 * 1.25, 1e-15));
    REQUIRE(u->getJoint("hinge")->dynamics);
    CHECK(u->getJoint("hinge")->dynamics->damping == 0.3);
    CHECK(u->getJoint("hinge")->dynamics->friction == 0.1);
}

TEST_CASE("urdf update: the DFKI pendulum's file with a moved centre of mass and friction, an armature left as a note") {
    atest::TempDir dir("mbx_urdf_update_dfki");
    const std::string output = dir.file("out.urdf");
    const std::string description = R"(<mechatronics version="1">
  <joint constraint="Joint1" damping="0.0123" coulomb="0.0456"/>
  <joint constraint="Joint2" damping="0.002" coulomb="0.03" armature="1e-4"/>
  <body id="Link2" mass_scale="0.9" com_shift="0.001 0.002 -0.01" inertia_change="-0.001 0 0 0 0 0"/>
</mechatronics>
)";
    mbx_rigid_body_info described{};
    {
        Opened o(dfki(), description);
        described = o.body_of("Link2");
        REQUIRE(mbx_mechanism_update_urdf(o.ctx(), o.mech(), dfki().c_str(), output.c_str()) == MBX_OK);
        bool noted = false;
        for (const atest::FindingCopy& f : o.t->findings())
            noted = noted || (f.subject_id == "Joint2" && f.message.find("armature 1e-04") != std::string::npos);
        CHECK(noted);
    }
    Opened back(output, "");
    check_same_body(back.body_of("Link2"), described);
    const std::vector<std::string> a = lines_of(atest::read_file(dfki())), b = lines_of(atest::read_file(output));
    REQUIRE(a.size() == b.size());
    std::vector<std::string> changed;
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i] != b[i]) {
            changed.push_back(b[i]);
            CHECK(without_values(a[i]) == without_values(b[i]));
        }
    REQUIRE(changed.size() == 5);  // Joint1's dynamics; Link2's origin, mass, inertia; Joint2's dynamics
    CHECK(changed[0] == "    <dynamics damping=\"0.0123\" friction=\"0.0456\" />");
    CHECK(changed[4] == "    <dynamics damping=\"0.002\" friction=\"0.03\" />");
    // urdfdom (with the world link it wants declared) reads the corrected link.
    const std::string declared =
        std::regex_replace(atest::read_file(output), std::regex("(<robot[^>]*>)"), "$1<link name=\"world\"/>");
    const urdf::ModelInterfaceSharedPtr u = urdf::parseURDF(declared);
    REQUIRE(u);
    const urdf::InertialSharedPtr in = u->getLink("Link2")->inertial;
    CHECK(in->mass == mbx_test::relative(0.563935954099688 * 0.9, 1e-15));
    CHECK(std::fabs(in->origin.position.x - 0.001) < 1e-15);
    CHECK(std::fabs(in->origin.position.y - 0.002) < 1e-15);
    CHECK(std::fabs(in->origin.position.z - (0.3212669909674605 - 0.01)) < 1e-15);
    CHECK(in->ixx == mbx_test::relative(0.9 * 0.053878129629650884 - 0.001, 1e-14));
    CHECK(in->iyy == mbx_test::relative(0.9 * 0.053878129629650884, 1e-14));
    CHECK(in->ixy == 0);
}

TEST_CASE("urdf update: another file, a link whose mass differs, a share that is no inertia or no file are refused") {
    atest::TempDir dir("mbx_urdf_update_errors");
    const std::string output = dir.file("out.urdf");
    Opened o(dfki(), "<mechatronics version=\"1\"><joint constraint=\"Joint1\" damping=\"0.01\"/></mechatronics>");
    const auto refused = [&](const std::string& source) {
        const mbx_status s = mbx_mechanism_update_urdf(o.ctx(), o.mech(), source.c_str(), output.c_str());
        CHECK(s == MBX_ERROR_INVALID_INPUT);
        CHECK_FALSE(std::filesystem::exists(output));
        return std::string(std::string(mbx_context_last_error(o.ctx())));
    };
    // Another robot's file: the pendulum's joint is not in it.
    CHECK(refused(mbx_test::shared_data("urdf/panda_description/urdf/panda.urdf")).find("not the URDF it was read from") !=
          std::string::npos);
    // The same file with Link1 heavier: named with its line.
    std::string text = atest::read_file(dfki());
    text = std::regex_replace(text, std::regex("0\\.6416937799349799"), "0.7");
    atest::write_file(dir.file("edited.urdf"), text);
    const std::string edited = refused(dir.file("edited.urdf"));
    CHECK(edited.find("link 'Link1' has mass 0.7 kg here") != std::string::npos);
    mbx_error_info info{};
    info.struct_size = sizeof info;
    REQUIRE(mbx_context_last_error_info(o.ctx(), &info) == MBX_OK);
    CHECK(info.line == atest::line_of(text, "<link name=\"Link1\">"));
    CHECK(std::string(info.subject_id) == "Link1");
    CHECK(refused(dir.path.string()).find("not a regular file") != std::string::npos);
    CHECK(refused(dir.file("missing.urdf")).find("not a regular file") != std::string::npos);

    // A welded body whose inertia change is the body's to take but not its
    // heaviest link's: two small links half a metre apart, a rod whose
    // inertia is nearly all spread; taking 0.005 kg m^2 off the rod's two
    // large moments leaves the rod a rigid body but not the arm link.
    const std::string input = dir.file("thin.urdf");
    const std::string small = "<inertia ixx=\"1e-4\" ixy=\"0\" ixz=\"0\" iyy=\"1e-4\" iyz=\"0\" izz=\"1e-4\"/>";
    atest::write_file(input, "<robot name=\"thin\">\n  <link name=\"base\"/>\n"
                             "  <joint name=\"hinge\" type=\"continuous\"><parent link=\"base\"/><child link=\"arm\"/></joint>\n"
                             "  <link name=\"arm\"><inertial><mass value=\"2\"/>" + small + "</inertial></link>\n"
                             "  <joint name=\"bolt\" type=\"fixed\"><origin xyz=\"0 0 -0.5\"/><parent link=\"arm\"/><child link=\"tool\"/></joint>\n"
                             "  <link name=\"tool\"><inertial><mass value=\"0.5\"/>" + small + "</inertial></link>\n</robot>\n");
    Opened thin(input, "<mechatronics version=\"1\"><body id=\"arm\" inertia_change=\"-0.005 -0.005 0 0 0 0\"/></mechatronics>");
    CHECK(mbx_mechanism_update_urdf(thin.ctx(), thin.mech(), input.c_str(), output.c_str()) == MBX_ERROR_INVALID_INPUT);
    CHECK(std::string(mbx_context_last_error(thin.ctx())).find("link 'arm' would take the inertia change") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(output));
}

}  // namespace MBX_UNITY_ID
