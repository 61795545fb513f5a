// Drive descriptions (docs/mechatronics.md): every kind of bad entry is an
// error naming file, line and drive; resolution against a mechanism refuses
// joints that cannot be driven and library objects of the wrong kind, and
// gives the drive quantities worked out by hand from the library's numbers.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "assembly_builder.h"
#include "core/progress.h"
#include "core/mechatronics/drive_file.h"
#include "core/report/report.h"

#include <nlohmann/json.hpp>
#include "core/translator/translate.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

const std::string kLibrary = std::string(MBX_SOURCE_DIR) + "/samples/library/mbx_object_library.xml";
const std::string kKrs = "628F99AAAA7444D5A2A36A6FA1175594";
const std::string kRe40 = "5B0E3C1F7A2D4E8C9F61A4B2C3D5E7F9";
const std::string kStrainWave = "A7C3E5F1092B4D6E8F0A1B2C3D4E5F60";
const std::string kScrew = "3E8F2A1B6C4D4E9F8A7B0C1D2E3F4A5B";
constexpr double kPi = 3.14159265358979323846;

// Ground -- R1 (revolute z) -- arm -- P1 (prismatic x) -- slider -- S1 (spherical) -- ball,
// plus W1 welding a bracket to the arm and a chain C1 = revolute z + revolute x.
std::unique_ptr<Mechanism> test_mechanism() {
    test::AssemblyBuilder b;
    const int ground = b.part("ground", 1, {0, 0, 0}, MBX_BODY_GROUND);
    const int arm = b.part("arm", 2, {0.5, 0, 0});
    const int slider = b.part("slider", 1, {1, 0, 0});
    const int ball = b.part("ball", 0.5, {1.5, 0, 0});
    const int bracket = b.part("bracket", 0.2, {0.5, 0.2, 0});
    const int tip = b.part("tip", 0.3, {1.5, 0.5, 0});
    b.revolute("R1", ground, arm, {0, 0, 0});
    b.joint("P1", arm, slider, {1, 0, 0}, {MBX_PRIMITIVE_PRISMATIC}, Vec3::UnitX());
    b.joint("S1", slider, ball, {1.5, 0, 0}, {MBX_PRIMITIVE_SPHERICAL});
    b.weld("W1", arm, bracket);
    b.joint("C1", ball, tip, {1.5, 0.5, 0}, {MBX_PRIMITIVE_REVOLUTE, MBX_PRIMITIVE_REVOLUTE});
    Progress progress;
    return translate_assembly(b.a, {}, TranslateOptions{}, progress);
}

// A drive description around `drives`, with the bundled library.
std::string drive_file(const std::string& drives) {
    return "<mechatronics version=\"1\">\n"                                  // line 1
           "<library file=\"" + kLibrary + "\"/>\n" +                        // 2
           drives + "</mechatronics>\n";
}

struct Loaded {
    MechatronicSpec spec;
    std::vector<DriveError> errors;
};

Loaded load(const std::string& text) {
    Loaded l;
    load_drive_text(text, "drives.xml", "", l.spec, l.errors);
    for (const LibraryError& e : l.spec.library.errors()) FAIL_CHECK(e.text());
    return l;
}

// The single error of `text`, which must contain `words`, at `line`.
void expect_file_error(const std::string& text, int line, const std::string& words) {
    const Loaded l = load(text);
    INFO(text);
    REQUIRE(l.errors.size() == 1);
    CHECK(l.errors[0].file == "drives.xml");
    CHECK(l.errors[0].line == line);
    INFO(l.errors[0].text());
    CHECK(l.errors[0].text().find(words) != std::string::npos);
    CHECK(l.spec.drives.empty());
}

const std::string kController = "<controller kp=\"50\"/>\n";

std::vector<Drive> resolve(const std::string& drives, std::vector<DriveError>& errors) {
    static const std::unique_ptr<Mechanism> m = test_mechanism();
    Loaded l = load(drive_file(drives));
    for (const DriveError& e : l.errors) FAIL_CHECK(e.text());
    return resolve_drives(l.spec, *m, errors);
}

void expect_resolve_error(const std::string& drives, const std::string& words) {
    std::vector<DriveError> errors;
    const std::vector<Drive> out = resolve(drives, errors);
    INFO(drives);
    REQUIRE(errors.size() == 1);
    INFO(errors[0].text());
    CHECK(errors[0].text().find(words) != std::string::npos);
    CHECK(errors[0].line == 3);  // the <drive> element
    CHECK(out.empty());
}

}  // namespace

TEST_CASE("drive file: a clean file gives its drives with controller, amplifier, overrides and motion in SI") {
    const Loaded l = load(drive_file(
        "<drive name=\"d\" constraint=\"R1\" primitive=\"0\" motor=\"" + kKrs + "\">\n"
        "<override name=\"Ratio\" value=\"100\"/>\n"
        "<amplifier mode=\"current\" gain=\"0.5\"/>\n"
        "<controller kp=\"160\" ki=\"1\" kd=\"2\" kv=\"243\" kvi=\"3\" sample_period=\"0.001\" delay=\"0.002\" "
        "output_limit=\"10\" velocity_estimate=\"filtered_difference\"/>\n"
        "<motion interpolation=\"smooth\" unit=\"deg\"><point t=\"0\" q=\"0\"/><point t=\"1\" q=\"90\"/></motion>\n"
        "</drive>\n"));
    REQUIRE(l.errors.empty());
    REQUIRE(l.spec.drives.size() == 1);
    const DriveSpec& d = l.spec.drives[0];
    CHECK(d.name == "d");
    CHECK(d.joint.constraint_id == "R1");
    CHECK(d.joint.primitive == 0);
    CHECK(d.motor_id == kKrs);
    CHECK(d.overrides.at("Ratio") == 100);
    CHECK(d.amplifier.mode == AmplifierMode::Current);
    CHECK(d.amplifier.gain == 0.5);
    const ControllerSpec& c = d.controller;
    CHECK(c.kp == 160);
    CHECK(c.ki == 1);
    CHECK(c.kd == 2);
    CHECK(c.kv == 243);
    CHECK(c.kvi == 3);
    CHECK(c.sample_period == 0.001);
    CHECK(c.delay == 0.002);
    CHECK(c.output_limit == 10);
    CHECK(c.velocity_estimate == VelocityEstimate::FilteredDifference);
    CHECK(d.motion.interpolation() == Interpolation::Smooth);
    CHECK(d.motion.at(1).position == mbx_test::relative(kPi / 2, 1e-6));
    CHECK(d.motion_unit == "deg");
}

TEST_CASE("drive file: every problem is an error naming file, line and drive") {
    const std::string head = "<drive name=\"d\" constraint=\"R1\" motor=\"" + kKrs + "\">\n";  // line 3
    // Line 4 holds the element at fault.
    expect_file_error(drive_file(head + "<controller kp=\"50\" kdd=\"1\"/>\n</drive>\n"), 4, "unknown attribute 'kdd'");
    expect_file_error(drive_file(head + "<controller kp=\"fifty\"/>\n</drive>\n"), 4, "kp = 'fifty' is not a number");
    expect_file_error(drive_file(head + "<controller kd=\"1\"/>\n</drive>\n"), 4, "controller needs kp");
    expect_file_error(drive_file(head + "<controller kp=\"50\" delay=\"-1\"/>\n</drive>\n"), 4, "delay must not be negative");
    expect_file_error(drive_file(head + "<controller kp=\"50\" sample_period=\"0.001\" delay=\"0.0015\"/>\n</drive>\n"), 4,
                      "whole number of sample periods");
    expect_file_error(drive_file(head + "<controller kp=\"50\" velocity_estimate=\"difference\"/>\n</drive>\n"), 4,
                      "needs a sample_period");
    expect_file_error(drive_file(head + "<controller kp=\"50\" velocity_estimate=\"guess\"/>\n</drive>\n"), 4,
                      "velocity_estimate 'guess'");
    expect_file_error(drive_file(head + "<amplifier mode=\"pwm\"/>\n" + kController + "</drive>\n"), 4,
                      "amplifier mode 'pwm'");
    expect_file_error(drive_file(head + "<amplifier mode=\"voltage\" gain=\"2\"/>\n" + kController + "</drive>\n"), 4,
                      "a voltage amplifier has no gain");
    expect_file_error(drive_file(head + "<override name=\"Ratio\"/>\n" + kController + "</drive>\n"), 4,
                      "override of 'Ratio' has no value");
    expect_file_error(drive_file(head + "<motion interpolation=\"cubic\"><point t=\"0\" q=\"0\"/></motion>\n" +
                                 kController + "</drive>\n"),
                      4, "interpolation 'cubic'");
    expect_file_error(drive_file(head + "<motion unit=\"furlong\"><point t=\"0\" q=\"0\"/></motion>\n" + kController +
                                 "</drive>\n"),
                      4, "motion unit 'furlong'");
    expect_file_error(drive_file(head + "<motion></motion>\n" + kController + "</drive>\n"), 4, "has no points");
    expect_file_error(drive_file(head + "<motion>\n<point t=\"1\" q=\"0\"/>\n<point t=\"1\" q=\"1\"/>\n</motion>\n" +
                                 kController + "</drive>\n"),
                      6, "times must increase strictly");
    expect_file_error(drive_file(head + "<motion>\n<point t=\"1\"/>\n</motion>\n" + kController + "</drive>\n"), 5,
                      "needs t and q");
    expect_file_error(drive_file(head + "<gearbox/>\n" + kController + "</drive>\n"), 4, "unknown element <gearbox>");
    expect_file_error(drive_file(head + "</drive>\n"), 3, "drive has no <controller>");
    expect_file_error(drive_file("<drive name=\"d\" motor=\"" + kKrs + "\">\n" + kController + "</drive>\n"), 3,
                      "drive has no constraint");
    expect_file_error(drive_file("<drive name=\"d\" constraint=\"R1\">\n" + kController + "</drive>\n"), 3,
                      "drive has no motor");
    expect_file_error(drive_file("<drive name=\"d\" constraint=\"R1\" primitive=\"-2\" motor=\"" + kKrs + "\">\n" +
                                 kController + "</drive>\n"),
                      3, "primitive must be a whole number");
    expect_file_error("<mechatronics>\n<drive>\n</mechatronics>\n", 3, "not well-formed XML");
    expect_file_error("<drives/>\n", 1, "root element must be <mechatronics>");
    expect_file_error("<mechatronics version=\"2\">\n</mechatronics>\n", 1, "unsupported version '2'");
    expect_file_error("<mechatronics>\n<library/>\n</mechatronics>\n", 2, "needs a file attribute");
    expect_file_error("<mechatronics>\n<library file=\"/no/such/lib.xml\"/>\n</mechatronics>\n", 2,
                      "cannot read the object library '/no/such/lib.xml': cannot open it: no such file");

    // A second drive for the same joint names the first one's line.
    const std::string drive = "<drive constraint=\"R1\" motor=\"" + kKrs + "\">" + kController + "</drive>\n";
    const Loaded twice = load(drive_file(drive + drive));
    REQUIRE(twice.errors.size() == 1);
    CHECK(twice.errors[0].line == 5);  // each drive takes two lines
    CHECK(twice.errors[0].text().find("first is at line 3") != std::string::npos);
    CHECK(twice.spec.drives.size() == 1);

    // Good drives of a file with a bad one are kept; the bad one is not.
    const Loaded mixed = load(drive_file(drive + "<drive constraint=\"P1\" motor=\"x\"><controller/></drive>\n"));
    CHECK(mixed.errors.size() == 1);
    CHECK(mixed.spec.drives.size() == 1);
}

TEST_CASE("drives: resolution gives the drive quantities worked out from the library's numbers") {
    std::vector<DriveError> errors;
    const std::vector<Drive> drives = resolve(
        "<drive name=\"servo\" constraint=\"R1\" motor=\"" + kKrs + "\">\n"
        "<controller kp=\"50\" kd=\"0.1\"/>\n"
        "</drive>\n"
        "<drive name=\"axis\" constraint=\"P1\" motor=\"" + kRe40 + "\" transmission=\"" + kScrew + "\">\n"
        "<amplifier mode=\"current\" gain=\"0.5\"/>\n"
        "<controller kp=\"160\" kv=\"240\" output_limit=\"10\"/>\n"
        "</drive>\n"
        "<drive name=\"wrist\" constraint=\"C1\" primitive=\"1\" motor=\"" + kRe40 + "\" transmission=\"" +
        kStrainWave + "\">\n"
        "<override name=\"efficiency\" value=\"0.8\"/>\n"
        "<controller kp=\"20\" output_limit=\"24\"/>\n"
        "</drive>\n",
        errors);
    for (const DriveError& e : errors) FAIL_CHECK(e.text());
    REQUIRE(drives.size() == 3);

    // Kondo KRS-784ICS in voltage mode, no transmission, output limit VaNominal.
    const Drive& s = drives[0];
    const double k_krs = (8 - 0.78 * 1.2) / (8200 * 2 * kPi / 60);
    CHECK(s.name == "servo");
    CHECK_FALSE(s.linear);
    CHECK(s.motor.torque_constant == mbx_test::relative(k_krs, 1e-12));
    CHECK(s.ratio == 251);
    CHECK(s.armature == mbx_test::relative(1.2e-7 * 251 * 251, 1e-12));
    CHECK(s.output_limit == 8);
    CHECK(s.effort_limit == mbx_test::relative(251 * k_krs * 8 / 0.78, 1e-12));
    CHECK(s.velocity_limit == mbx_test::relative(8 / k_krs / 251, 1e-12));
    // Servo: stiffness and damping through G = N k / Ra; back-EMF N^2 k^2 / Ra.
    const double g = 251 * k_krs / 0.78;
    CHECK(s.servo.stiffness == mbx_test::relative(50 * g, 1e-12));
    CHECK(s.servo.damping == mbx_test::relative(0.1 * g, 1e-12));
    CHECK(s.servo.emf_damping == mbx_test::relative(251.0 * 251 * k_krs * k_krs / 0.78, 1e-12));
    CHECK(s.servo.approximation.empty());

    // RE40-class motor on a 5 mm ball screw behind a current amplifier.
    const Drive& a = drives[1];
    const double k_re = (48 - 1.16 * 3.17) / (6940 * 2 * kPi / 60);
    const double screw = 2 * kPi / 0.005;
    CHECK(a.linear);
    CHECK(a.transmission_kind == "ball_screw");
    CHECK(a.ratio == mbx_test::relative(screw, 1e-12));
    CHECK(a.armature == mbx_test::relative((1.42e-5 + 4e-5) * screw * screw, 1e-12));
    CHECK(a.effort_limit == mbx_test::relative(0.9 * screw * k_re * 0.5 * 10, 1e-12));
    const double g_a = 0.9 * screw * k_re * 0.5;  // N per unit of output
    CHECK(a.servo.stiffness == mbx_test::relative(g_a * 240 * 160, 1e-12));
    CHECK(a.servo.damping == mbx_test::relative(g_a * 240, 1e-12));
    CHECK(a.servo.emf_damping == 0);  // a current amplifier cancels the back-EMF

    // Second revolute of the two-primitive chain, strain-wave gear with an
    // overridden (editable) efficiency.
    const Drive& w = drives[2];
    CHECK(w.efficiency == 0.8);
    CHECK(w.ratio == 100);
    CHECK(w.armature == mbx_test::relative((1.42e-5 + 3.3e-6) * 1e4, 1e-12));
    CHECK(w.effort_limit == mbx_test::relative(0.8 * 100 * k_re * 24 / 1.16, 1e-12));
}

TEST_CASE("drives: resolution refuses what cannot be driven, each with the drive's line") {
    const std::string c = kController;
    expect_resolve_error("<drive constraint=\"NOPE\" motor=\"" + kKrs + "\">" + c + "</drive>\n",
                         "no constraint with id 'NOPE'");
    expect_resolve_error("<drive constraint=\"S1\" motor=\"" + kKrs + "\">" + c + "</drive>\n",
                         "no prismatic or revolute primitive");
    expect_resolve_error("<drive constraint=\"W1\" motor=\"" + kKrs + "\">" + c + "</drive>\n",
                         "no prismatic or revolute primitive");
    expect_resolve_error("<drive constraint=\"C1\" motor=\"" + kKrs + "\">" + c + "</drive>\n",
                         "say which with a primitive index");
    expect_resolve_error("<drive constraint=\"C1\" primitive=\"5\" motor=\"" + kKrs + "\">" + c + "</drive>\n",
                         "no such primitive joint");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"00000000000000000000000000000000\">" + c + "</drive>\n",
                         "is not in the object library");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kStrainWave + "\">" + c + "</drive>\n",
                         "not a dc_motor");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kKrs + "\" transmission=\"" + kRe40 + "\">" + c +
                             "</drive>\n",
                         "not a gearbox or ball_screw");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kKrs + "\" transmission=\"" + kScrew + "\">" + c +
                             "</drive>\n",
                         "a ball screw cannot drive the revolute joint");
    expect_resolve_error("<drive constraint=\"P1\" motor=\"" + kKrs + "\">" + c + "</drive>\n",
                         "needs a ball_screw transmission");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kKrs + "\"><override name=\"J_Rotor\" value=\"1\"/>" + c +
                             "</drive>\n",
                         "'J_Rotor' of 'KRS-784ICS' is not editable");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kKrs + "\"><override name=\"Ratio\" value=\"0.5\"/>" + c +
                             "</drive>\n",
                         "outside the bounds");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kKrs + "\"><override name=\"Torque\" value=\"1\"/>" + c +
                             "</drive>\n",
                         "unknown parameter 'Torque'");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kKrs + "\"><controller kp=\"0\"/></drive>\n",
                         "kp must be positive");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kKrs + "\"><controller kp=\"1\" kvi=\"1\"/></drive>\n",
                         "kvi needs a velocity loop");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kKrs + "\"><amplifier mode=\"current\" gain=\"1\"/>" + c +
                             "</drive>\n",
                         "needs an output limit");
    expect_resolve_error("<drive constraint=\"R1\" motor=\"" + kKrs +
                             "\"><motion unit=\"mm\"><point t=\"0\" q=\"1\"/></motion>" + c + "</drive>\n",
                         "motion in 'mm' for the revolute joint");
    // The same joint named twice (by chain index and by default).
    std::vector<DriveError> errors;
    resolve("<drive constraint=\"R1\" motor=\"" + kKrs + "\">" + c + "</drive>\n<drive constraint=\"R1\" primitive=\"0\" motor=\"" +
                kKrs + "\">" + c + "</drive>\n",
            errors);
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].text().find("driven twice") != std::string::npos);
}

TEST_CASE("drives: integral action, sampling and delay are named where a servo equivalent leaves them out") {
    std::vector<DriveError> errors;
    const std::vector<Drive> d = resolve("<drive constraint=\"R1\" motor=\"" + kKrs + "\">"
                                         "<controller kp=\"5\" ki=\"1\" sample_period=\"0.001\" delay=\"0.002\"/></drive>\n",
                                         errors);
    REQUIRE(d.size() == 1);
    CHECK(d[0].servo.approximation.find("integral action") != std::string::npos);
    CHECK(d[0].servo.approximation.find("sampling at 0.001 s") != std::string::npos);
    CHECK(d[0].servo.approximation.find("delay of 0.002 s") != std::string::npos);
}

TEST_CASE("drives: the report lists each drive with its joint quantities, and only when there are drives") {
    std::vector<DriveError> errors;
    const std::vector<Drive> drives = resolve("<drive name=\"servo\" constraint=\"R1\" motor=\"" + kKrs + "\">\n"
                                              "<controller kp=\"50\" kd=\"0.1\"/>\n"
                                              "<motion><point t=\"0\" q=\"0\"/><point t=\"2\" q=\"1\"/></motion>\n"
                                              "</drive>\n",
                                              errors);
    REQUIRE(drives.size() == 1);
    const std::unique_ptr<Mechanism> m = test_mechanism();
    const nlohmann::json with = nlohmann::json::parse(report_json(*m, &drives));
    REQUIRE(with.contains("drives"));
    REQUIRE(with["drives"].size() == 1);
    const nlohmann::json& d = with["drives"][0];
    CHECK(d["name"] == "servo");
    CHECK(d["constraint_id"] == "R1");
    CHECK(d["motor"] == "KRS-784ICS");
    CHECK(d["armature"].get<double>() == drives[0].armature);
    CHECK(d["effort_limit"].get<double>() == drives[0].effort_limit);
    CHECK(d["servo"]["emf_damping"].get<double>() == drives[0].servo.emf_damping);
    CHECK(d["motion"]["points"].size() == 2);
    CHECK(d["motion"]["points"][1][1].get<double>() == 1);
    CHECK(report_text(*m, &drives).find("'servo': KRS-784ICS, ratio 251") != std::string::npos);

    const nlohmann::json without = nlohmann::json::parse(report_json(*m));
    CHECK_FALSE(without.contains("drives"));
    CHECK(report_text(*m).find("Drives (") == std::string::npos);
}

TEST_CASE("drive file: a library already loaded (by any path to the same file) is not loaded twice") {
    MechatronicSpec spec;
    std::vector<DriveError> errors;
    REQUIRE(spec.library.load_file(kLibrary));
    // The same file through another path: a "." component.
    const std::string dotted = std::string(MBX_SOURCE_DIR) + "/samples/./library/mbx_object_library.xml";
    load_drive_text("<mechatronics>\n<library file=\"" + dotted + "\"/>\n</mechatronics>\n", "drives.xml", "", spec,
                    errors);
    CHECK(errors.empty());
    for (const LibraryError& e : spec.library.errors()) FAIL_CHECK(e.text());
    CHECK(spec.library.find(kKrs).object != nullptr);
    // A different file with the same classes is still refused, class by class.
    const std::string copy_text = "<object_library><object_folder name=\"Electromechanical\">"
                                  "<object_class name=\"Permanent magnet DC machine\" kind=\"dc_motor\"/>"
                                  "</object_folder></object_library>";
    spec.library.load_text(copy_text, "other.xml");
    REQUIRE(spec.library.errors().size() == 1);
    CHECK(spec.library.errors()[0].message.find("declared twice") != std::string::npos);
}
}  // namespace MBX_UNITY_ID
