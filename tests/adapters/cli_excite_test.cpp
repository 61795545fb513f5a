// `mbx excite` from the command line on real inputs: the DFKI double
// pendulum's URDF (its limits read back by urdfdom, the independent reader)
// and the four-bar. The written CSV keeps every limit at every sample and
// starts and ends at rest; experiment.xml names the CSV's joints and columns;
// a calibration.json's named causes and ambiguous groups are what the design
// is for; and bad options, joints, causes and files exit non-zero, naming
// what is wrong, with nothing written.
#include <urdf_parser/urdf_parser.h>

#include <pugixml.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "core/report/json_value.h"
#include "cli_support.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"
#include "tests/common/skip.h"

namespace MBX_UNITY_ID {

namespace {

using Run = atest::CliRun;
using atest::run_cli;
namespace fs = std::filesystem;

struct Csv {
    std::vector<std::string> header;
    std::vector<std::vector<double>> rows;
    int column(const std::string& name) const {
        for (size_t k = 0; k < header.size(); ++k)
            if (header[k] == name) return int(k);
        return -1;
    }
};

Csv read_csv(const std::string& path) {
    Csv csv;
    std::ifstream in(path);
    std::string line;
    REQUIRE(std::getline(in, line));
    std::stringstream h(line);
    for (std::string cell; std::getline(h, cell, ',');) csv.header.push_back(cell);
    while (std::getline(in, line)) {
        std::vector<double> row;
        std::stringstream r(line);
        for (std::string cell; std::getline(r, cell, ',');) row.push_back(std::strtod(cell.c_str(), nullptr));
        REQUIRE(row.size() == csv.header.size());
        csv.rows.push_back(row);
    }
    return csv;
}

}  // namespace

TEST_CASE("cli excite: the DFKI pendulum's references keep the URDF's limits at every sample and rest at both ends") {
    const std::string urdf_path = mbx_test::shared_data("measured/dfki_double_pendulum_c0/identified_model_3.1_acrobot.urdf");
    atest::TempDir dir("mbx_cli_excite");
    const std::string out = dir.file("out");
    const double margin = 0.2, acceleration = 30;
    const Run r = run_cli(dir, "excite '" + urdf_path + "' -o '" + out +
                                   "' --acceleration-limit 30 --margin 0.2 --period 5 --harmonics 8 --periods 2 "
                                   "--evaluations 120 --sample-rate 500 --progress");
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("mbx: excite 100.0%") != std::string::npos);
    for (const char* f : {"excitation.csv", "experiment.xml", "excitation.json", "excitation.html"})
        CHECK(fs::exists(fs::path(out) / f));

    // The limits as urdfdom reads them: Joint1 has a speed and a range,
    // Joint2 also an effort.
    std::ifstream in(urdf_path);
    std::stringstream text;
    text << in.rdbuf();
    // (its base_weld hangs from a "world" link the file leaves out, as ROS
    // tools allow and urdfdom does not)
    std::string xml = text.str();
    const size_t robot = xml.find('>', xml.find("<robot"));
    REQUIRE(robot != std::string::npos);
    xml.insert(robot + 1, "<link name=\"world\"/>");
    const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(xml);
    REQUIRE(model);
    const Csv csv = read_csv(out + "/excitation.csv");
    REQUIRE(csv.rows.size() == 5001);  // 10 s at 500 Hz, both ends
    for (const char* name : {"Joint1", "Joint2"}) {
        const urdf::JointConstSharedPtr j = model->getJoint(name);
        REQUIRE(j);
        REQUIRE(j->limits);
        const int q = csv.column(std::string(name) + "_ref"), qd = csv.column(std::string(name) + "_ref_velocity"),
                  qdd = csv.column(std::string(name) + "_ref_acceleration");
        REQUIRE(q > 0);
        REQUIRE(qd > 0);
        REQUIRE(qdd > 0);
        const double room = margin * (j->limits->upper - j->limits->lower);
        double reach = 0;
        for (const std::vector<double>& row : csv.rows) {
            CHECK(row[size_t(q)] <= j->limits->upper - room + 1e-9);
            CHECK(row[size_t(q)] >= j->limits->lower + room - 1e-9);
            CHECK(std::abs(row[size_t(qd)]) <= (1 - margin) * j->limits->velocity * (1 + 1e-9));
            CHECK(std::abs(row[size_t(qdd)]) <= (1 - margin) * acceleration * (1 + 1e-9));
            reach = std::max(reach, std::abs(row[size_t(qd)]) / ((1 - margin) * j->limits->velocity));
        }
        for (const std::vector<double>* row : {&csv.rows.front(), &csv.rows.back()}) {
            CHECK((*row)[size_t(qd)] == mbx_test::within(0.0, 1e-9, "at rest"));
            CHECK((*row)[size_t(qdd)] == mbx_test::within(0.0, 1e-9, "at rest"));
        }
        MESSAGE(name << ": the design uses " << reach << " of the speed limit");
    }
    // Joint2's rated effort, on the design's own inverse dynamics.
    CHECK(r.out.find("effort: rated") != std::string::npos);

    // experiment.xml: a column per joint and quantity, named as the CSV's stems.
    pugi::xml_document x;
    REQUIRE(x.load_file((out + "/experiment.xml").c_str()));
    int references = 0;
    for (pugi::xml_node c : x.child("experiment").children("column")) {
        const std::string quantity = c.attribute("quantity").value(), name = c.attribute("name").value();
        if (quantity == "reference") {
            ++references;
            CHECK(csv.column(name) > 0);
            CHECK(model->getJoint(c.attribute("joint").value()));
        }
    }
    CHECK(references == 2);
    CHECK(x.child("experiment").child("drive").attribute("mode").value() == std::string("closed_loop"));
}

TEST_CASE("cli excite: a calibration.json's named cause and ambiguous group are what the four-bar's design is for") {
    atest::TempDir dir("mbx_cli_excite_fourbar");
    // As mbx calibrate writes it (calibration/outputs/calibration_json.cpp).
    {
        std::ofstream json(dir.file("calibration.json"));
        json << "{\n  \"causes\": [\n    {\"step\": 1, \"cause\": \"viscous_friction\", \"subject\": {\"kind\": \"joint\", "
                "\"id\": \"x\", \"name\": \"rev_A\"}, \"parameters\": [{\"name\": \"damping\", \"value\": 0.1, \"std_error\": "
                "0.02}]}\n  ],\n  \"ambiguous\": [[\"mass_error on body 'Coupler'\", \"armature on joint 'rev_A'\"]]\n}\n";
    }
    const std::string out = dir.file("out");
    const Run r = run_cli(dir, "excite fourbar -o '" + out + "' --joint rev_A --limit rev_A=-1:1:3:30: --calibration '" +
                                   dir.file("calibration.json") + "' --period 4 --harmonics 6 --evaluations 80");
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    // Exactly the three parameters asked for, with the records' own standard error beside the design's.
    CHECK(r.out.find("viscous_friction.damping on joint 'rev_A'") != std::string::npos);
    CHECK(r.out.find("mass_error.mass_change on body 'Coupler'") != std::string::npos);
    CHECK(r.out.find("armature.armature on joint 'rev_A'") != std::string::npos);
    CHECK(r.out.find("coulomb_friction") == std::string::npos);
    CHECK(r.out.find(" / 0.02\n") != std::string::npos);
    CHECK(r.out.find("limits from option") != std::string::npos);
}

// The EMPS rig's drive (samples/mechatronics/emps_axis_drives.xml): a P
// position loop (kp 160.18 1/s) inside a P velocity loop (kv 243.45 V/(m/s))
// into a current amplifier, 35.15 N/V at the carriage, the rig's published
// figures. At the joint that is a servo of stiffness kp kv 35.15 N/m and
// damping kv 35.15 N s/m on the measured speed; the design follows it, says
// so, and keeps the limits on the motion it predicts as on the reference.
TEST_CASE("cli excite: a drive's controller is the servo the EMPS design follows, its motion within the limits") {
    atest::TempDir dir("mbx_cli_excite_emps");
    const std::string samples = MBX_SAMPLES_DIR, out = dir.file("out");
    const double acceleration = 5, margin = 0.1;
    const Run r = run_cli(dir, "excite '" + samples + "/emps_axis/emps_axis.xml' --drives '" + samples +
                                   "/mechatronics/emps_axis_drives.xml' -o '" + out +
                                   "' --acceleration-limit 5 --limit BED--CARRIAGE=0:0.2::: --margin 0.1 --period 4 "
                                   "--harmonics 6 --periods 2 --evaluations 120");
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("servo: drive") != std::string::npos);
    std::ifstream in(out + "/excitation.json");
    std::stringstream text;
    text << in.rdbuf();
    const mbx::JsonValue json = mbx::parse_json(text.str());
    const mbx::JsonValue* joints = json.find("joints");
    REQUIRE(joints);
    REQUIRE(joints->array.size() == 1);
    const mbx::JsonValue& joint = joints->array[0];
    const mbx::JsonValue* servo = joint.find("servo");
    REQUIRE(servo);
    const double gtau = 35.15;
    CHECK(servo->find("stiffness")->number == mbx_test::relative(160.18 * 243.45 * gtau, 1e-3));
    CHECK(servo->find("damping")->number == mbx_test::relative(243.45 * gtau, 1e-3));
    CHECK(servo->find("damping_on")->string == "speed");
    CHECK(servo->find("inertia")->number > 0);
    // The predicted motion and the written reference both within the limits less the margin.
    const mbx::JsonValue* limits = joint.find("limits");
    const mbx::JsonValue* reached = joint.find("reached");
    REQUIRE(limits);
    REQUIRE(reached);
    const double speed = limits->find("velocity")->number, room = margin * 0.2;
    CHECK(reached->find("highest")->number <= 0.2 - room + 1e-9);
    CHECK(reached->find("lowest")->number >= room - 1e-9);
    CHECK(reached->find("velocity")->number <= (1 - margin) * speed * (1 + 1e-9));
    CHECK(reached->find("acceleration")->number <= (1 - margin) * acceleration * (1 + 1e-9));
    const Csv csv = read_csv(out + "/excitation.csv");
    const int q = csv.column("BED__CARRIAGE_ref"), qd = csv.column("BED__CARRIAGE_ref_velocity");
    REQUIRE(q > 0);
    REQUIRE(qd > 0);
    for (const std::vector<double>& row : csv.rows) {
        CHECK(row[size_t(q)] <= 0.2 - room + 1e-9);
        CHECK(row[size_t(q)] >= room - 1e-9);
        CHECK(std::abs(row[size_t(qd)]) <= (1 - margin) * speed * (1 + 1e-9));
    }
}

TEST_CASE("cli excite: bad options, joints, causes and files exit non-zero with the fault named and nothing written") {
    atest::TempDir dir("mbx_cli_excite_bad");
    struct Bad {
        std::string arguments, words;
        int code;
    };
    {
        std::ofstream(dir.file("not.json")) << "{\n  \"causes\": [\n    {\"cause\": 3,\n";
        std::ofstream(dir.file("empty.json")) << "{\"causes\": [], \"ambiguous\": []}\n";
    }
    const std::vector<Bad> bad = {
        {"excite fourbar -o '" + dir.file("o1") + "' --joint wrist", "no joint 'wrist'", 1},
        {"excite fourbar -o '" + dir.file("o2") + "' --joint rev_A --limit rev_A=-1:1:3:30: --cause 'armature on joint "
         "'\\''ghost'\\'''", "armature on joint 'ghost'", 1},
        {"excite fourbar -o '" + dir.file("o3") + "' --joint rev_A --limit rev_A=-1:1:3:30: --cause stiction", "stiction", 1},
        {"excite fourbar -o '" + dir.file("o4") + "' --joint rev_A --limit rev_A=1:2", "--limit", 2},
        {"excite fourbar -o '" + dir.file("o5") + "' --joint rev_A --limit rev_A=-1:1:3:30: --calibration '" +
             dir.file("not.json") + "'", "not.json: line", 1},
        {"excite fourbar -o '" + dir.file("o6") + "' --joint rev_A --limit rev_A=-1:1:3:30: --calibration '" +
             dir.file("empty.json") + "'", "nothing for a design to settle", 1},
        {"excite fourbar -o '" + dir.file("o7") + "' --joint rev_A --limit rev_A=-1:1:3:30: --calibration /dev/zero",
         "not a regular file", 1},
        {"excite fourbar -o '" + dir.file("o8") + "' --joint rev_A --limit rev_A=-1:1:3:30: --harmonics 1",
         "harmonics must be 2 to 50", 1},
        {"excite fourbar -o '" + dir.file("o9") + "' --joint rev_A --limit rev_A=::::", "has no position range, speed or acceleration limit", 1},
        {"excite fourbar -o '" + dir.file("o10") + "' --periods 0", "whole number", 2},
    };
    for (const Bad& b : bad) {
        const Run r = run_cli(dir, b.arguments);
        INFO(b.arguments << "\n" << r.out << r.err);
        CHECK(r.code == b.code);
        CHECK(r.err.find(b.words) != std::string::npos);
    }
    for (int k = 1; k <= 10; ++k) CHECK_FALSE(fs::exists(dir.file("o" + std::to_string(k)) + "/excitation.csv"));
}

}  // namespace MBX_UNITY_ID
