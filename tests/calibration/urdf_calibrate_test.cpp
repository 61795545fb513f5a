// The calibrated URDF: MuJoCo hides viscous friction and a lighter forearm
// in the DFKI double pendulum's own URDF, `mbx calibrate --write-urdf`
// names them and writes them into the user's file. The written file must
// parse in urdfdom, load in MuJoCo with the calibrated numbers, differ from
// the user's only in those numbers, and simulate as the user's URDF with
// the calibrated description.xml does.
#include <doctest/doctest.h>
#include <mujoco/mujoco.h>
#include <sys/wait.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/mechatronics/drive_file.h"
#include "hidden_effects.h"
#include "temp_dir.h"
#include "tests/common/file_text.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

struct Run {
    int code = -1;
    std::string out, err;
};

Run run_mbx(const mbx_test::TempDir& dir, const std::string& arguments) {
    const std::string command = std::string("'") + MBX_CLI_PATH + "' " + arguments + " >'" + dir.file("stdout") +
                                "' 2>'" + dir.file("stderr") + "'";
    const int status = std::system(command.c_str());
    Run r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = mbx_test::read_file(dir.file("stdout"));
    r.err = mbx_test::read_file(dir.file("stderr"));
    return r;
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// The line (0-based) of the first `what` after the first `after`.
size_t line_after(const std::vector<std::string>& lines, const std::string& after, const std::string& what) {
    size_t i = 0;
    while (i < lines.size() && lines[i].find(after) == std::string::npos) ++i;
    while (i < lines.size() && lines[i].find(what) == std::string::npos) ++i;
    REQUIRE_MESSAGE(i < lines.size(), "no " << what << " after " << after);
    return i;
}

// A line with its attribute values taken out: what must not change.
std::string without_values(const std::string& line) { return std::regex_replace(line, std::regex("\"[^\"]*\""), "\"\""); }

// Rows of numbers of a trajectory.csv (header skipped).
std::vector<std::vector<double>> csv_rows(const std::string& path) {
    std::vector<std::vector<double>> rows;
    const std::vector<std::string> lines = lines_of(mbx_test::read_file(path));
    for (size_t i = 1; i < lines.size(); ++i) {
        std::vector<double> row;
        std::istringstream cells(lines[i]);
        for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
        rows.push_back(row);
    }
    return rows;
}

struct MjFree {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
};

}  // namespace

TEST_CASE("calibrate --write-urdf: the DFKI pendulum's own URDF gets the named friction and mass, all else kept") {
    mbx_test::TempDir dir("mbx_urdf_calibrate");
    mbx_test::CaseSpec spec;
    spec.name = "acrobot", spec.mechanism = "dfki_acrobot", spec.seed = 5;
    spec.effects = {{"viscous_friction", "Joint1", 0.03, 0.03}, {"mass_error", "Link2", -0.2, -0.2}};
    const mbx_test::GeneratedCase c = mbx_test::generate_case(spec, dir.file("case"));
    const std::string urdf = c.input;
    const std::string out = dir.file("out"), written = dir.file("calibrated.urdf");

    const Run r = run_mbx(dir, "calibrate '" + urdf + "' --experiment '" + c.experiment_path + "' -o '" + out +
                                   "' --write-urdf '" + written + "'");
    MESSAGE(r.out << r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("urdf: " + written) != std::string::npos);

    // What description.xml holds is what the URDF must hold.
    MechatronicSpec calibrated;
    std::vector<DriveError> errors;
    load_drive_file(out + "/description.xml", calibrated, errors);
    REQUIRE(errors.empty());
    double damping1 = -1, mass_scale = -1;
    for (const JointDynamicsSpec& j : calibrated.joint_dynamics)
        if (j.joint.constraint_id == "Joint1") damping1 = j.damping;
    for (const BodyMassSpec& b : calibrated.body_masses)
        if (b.body == "Link2") mass_scale = b.mass_scale;
    CHECK(damping1 == mbx_test::relative(0.03, 0.1));
    CHECK(mass_scale == mbx_test::relative(0.8, 0.03));

    // Only the calibrated values changed: the same lines, each with the same
    // text around its attribute values, and only the lines of a calibrated
    // joint's <dynamics> or a calibrated link's <inertial> differ.
    const std::string before = mbx_test::read_file(urdf), after = mbx_test::read_file(written);
    const std::vector<std::string> a = lines_of(before), b = lines_of(after);
    REQUIRE(a.size() == b.size());
    std::set<size_t> allowed;
    for (const JointDynamicsSpec& j : calibrated.joint_dynamics)
        allowed.insert(line_after(a, "<joint name=\"" + j.joint.constraint_id + "\"", "<dynamics"));
    for (const BodyMassSpec& m : calibrated.body_masses)
        for (const char* element : {"<origin", "<mass", "<inertia "})
            allowed.insert(line_after(a, "<link name=\"" + m.body + "\"", element));
    std::set<size_t> changed;
    for (size_t i = 0; i < a.size(); ++i) {
        if (a[i] == b[i]) continue;
        changed.insert(i);
        CHECK_MESSAGE(allowed.count(i) == 1, "line " << i + 1 << " changed: " << b[i]);
        CHECK(without_values(a[i]) == without_values(b[i]));
    }
    CHECK(changed.count(line_after(a, "<joint name=\"Joint1\"", "<dynamics")) == 1);
    CHECK(changed.count(line_after(a, "<link name=\"Link2\"", "<mass")) == 1);

    // urdfdom reads the calibrated numbers. It refuses Gazebo's implied world
    // link (the user's file as much as the calibrated one), so it reads both
    // with that link declared.
    CHECK_FALSE(urdf::parseURDF(after));
    CHECK_FALSE(urdf::parseURDF(before));
    const auto with_world = [](const std::string& text) {
        return std::regex_replace(text, std::regex("(<robot[^>]*>)"), "$1<link name=\"world\"/>");
    };
    REQUIRE(urdf::parseURDF(with_world(before)));
    const urdf::ModelInterfaceSharedPtr u = urdf::parseURDF(with_world(after));
    REQUIRE(u);
    const double link2_mass = 0.563935954099688;
    REQUIRE(u->getLink("Link2")->inertial);
    CHECK(u->getLink("Link2")->inertial->mass == mbx_test::relative(link2_mass * mass_scale, 1e-15));
    CHECK(u->getLink("Link1")->inertial->mass == 0.6416937799349799);
    REQUIRE(u->getJoint("Joint1")->dynamics);
    CHECK(u->getJoint("Joint1")->dynamics->damping == damping1);

    // MuJoCo loads it (its copy without the visuals, whose meshes are not in
    // ../shared, and with the world link declared) with the same numbers.
    const std::string for_mujoco = with_world(std::regex_replace(after, std::regex("<visual[\\s\\S]*?</visual>"), ""));
    std::ofstream(dir.file("mujoco.urdf"), std::ios::binary) << for_mujoco;
    char error[1000] = "";
    std::unique_ptr<mjModel, MjFree> mj(mj_loadXML(dir.file("mujoco.urdf").c_str(), nullptr, error, sizeof error));
    REQUIRE_MESSAGE(mj, error);
    const int joint1 = mj_name2id(mj.get(), mjOBJ_JOINT, "Joint1");
    const int link2 = mj_name2id(mj.get(), mjOBJ_BODY, "Link2");
    REQUIRE(joint1 >= 0);
    REQUIRE(link2 >= 0);
    CHECK(mj->dof_damping[mj->jnt_dofadr[joint1]] == mbx_test::relative(damping1, 1e-12));
    CHECK(mj->body_mass[link2] == mbx_test::relative(link2_mass * mass_scale, 1e-12));

    // The calibrated URDF alone moves as the user's URDF with description.xml.
    const std::string set = " --set Joint1.q=1.2 --set Joint2.q=-0.6 --set Joint1.qd=2 --stop-time 1.5";
    const Run with_description = run_mbx(dir, "simulate '" + urdf + "' --drives '" + out + "/description.xml'" + set +
                                                  " -o '" + dir.file("sim_description") + "'");
    REQUIRE_MESSAGE(with_description.code == 0, with_description.err);
    const Run alone = run_mbx(dir, "simulate '" + written + "'" + set + " -o '" + dir.file("sim_urdf") + "'");
    REQUIRE_MESSAGE(alone.code == 0, alone.err);
    const Run uncalibrated = run_mbx(dir, "simulate '" + urdf + "'" + set + " -o '" + dir.file("sim_input") + "'");
    REQUIRE_MESSAGE(uncalibrated.code == 0, uncalibrated.err);
    const auto expected = csv_rows(dir.file("sim_description/trajectory.csv"));
    const auto got = csv_rows(dir.file("sim_urdf/trajectory.csv"));
    const auto input = csv_rows(dir.file("sim_input/trajectory.csv"));
    REQUIRE(input.size() == got.size());
    // The calibration matters to the motion: the user's URDF alone goes elsewhere.
    CHECK(std::fabs(input.back()[1] - got.back()[1]) > 1e-3);
    REQUIRE(expected.size() == got.size());
    REQUIRE(expected.size() > 100);
    double largest = 0, moved = 0;
    for (size_t i = 0; i < got.size(); ++i) {
        REQUIRE(got[i].size() == expected[i].size());
        for (size_t k = 0; k < got[i].size(); ++k) largest = std::max(largest, std::fabs(got[i][k] - expected[i][k]));
        moved = std::max(moved, std::fabs(got[i][1] - got[0][1]));
    }
    MESSAGE("largest difference of the two runs " << largest << " (Joint1 moved " << moved << " rad)");
    CHECK(moved > 0.5);
    CHECK(largest < 1e-9);
}

TEST_CASE("calibrate --write-urdf: an input that is no URDF is refused before any work") {
    mbx_test::TempDir dir("mbx_urdf_calibrate_refused");
    const std::string pmxml = std::string(MBX_SAMPLES_DIR) + "/emps_axis/emps_axis.xml";
    const Run r = run_mbx(dir, "calibrate '" + pmxml + "' --experiment '" + dir.file("none.xml") + "' -o '" +
                                   dir.file("out") + "' --write-urdf '" + dir.file("x.urdf") + "'");
    CHECK(r.code == 2);
    CHECK(r.err.find("--write-urdf needs a URDF input") != std::string::npos);
    CHECK(r.err.find("pmxml") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("out")));
}

}  // namespace MBX_UNITY_ID
