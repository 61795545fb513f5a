// Joint dynamics in the description file (<joint>, docs/mechatronics.md):
// every kind of bad entry is an error naming file, line and joint, all of an
// entry's problems at once; resolution refuses joints without a single
// coordinate, cut joints, a joint given twice and units of the wrong kind,
// and hands every value through in SI.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "assembly_builder.h"
#include "core/progress.h"
#include "core/mechatronics/drive_file.h"
#include "core/mechatronics/mounting.h"
#include "core/translator/translate.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Ground -- R1 (revolute z) -- arm -- P1 (prismatic x) -- slider -- S1 (spherical) -- ball,
// W1 welding a bracket to the arm, a chain C1 = revolute z + revolute x, and a
// four-bar off ground (K1, K2, K3, K4; K4, last in host order, is cut).
std::unique_ptr<Mechanism> test_mechanism() {
    test::AssemblyBuilder b;
    const int ground = b.part("ground", 1, {0, 0, 0}, MBX_BODY_GROUND);
    const int arm = b.part("arm", 2, {0.5, 0, 0});
    const int slider = b.part("slider", 1, {1, 0, 0});
    const int ball = b.part("ball", 0.5, {1.5, 0, 0});
    const int bracket = b.part("bracket", 0.2, {0.5, 0.2, 0});
    const int tip = b.part("tip", 0.3, {1.5, 0.5, 0});
    const int crank = b.part("crank", 1, {0, -4.5, 0});
    const int coupler = b.part("coupler", 1, {2, -3.5, 0});
    const int rocker = b.part("rocker", 1, {4, -4, 0});
    b.revolute("R1", ground, arm, {0, 0, 0});
    b.joint("P1", arm, slider, {1, 0, 0}, {MBX_PRIMITIVE_PRISMATIC}, Vec3::UnitX());
    b.joint("S1", slider, ball, {1.5, 0, 0}, {MBX_PRIMITIVE_SPHERICAL});
    b.weld("W1", arm, bracket);
    b.joint("C1", ball, tip, {1.5, 0.5, 0}, {MBX_PRIMITIVE_REVOLUTE, MBX_PRIMITIVE_REVOLUTE});
    b.revolute("K1", ground, crank, {0, -5, 0});
    b.revolute("K2", crank, coupler, {0, -4, 0});
    b.revolute("K3", coupler, rocker, {4, -3, 0});
    b.revolute("K4", ground, rocker, {4, -5, 0});
    Progress progress;
    return translate_assembly(b.a, {}, TranslateOptions{}, progress);
}

const Mechanism& mechanism() {
    static const std::unique_ptr<Mechanism> m = test_mechanism();
    return *m;
}

int joint_named(const std::string& name) {
    const Mechanism& m = mechanism();
    for (size_t j = 0; j < m.joints.size(); ++j)
        if (m.joints[j].name == name) return int(j);
    FAIL("no joint " << name);
    return -1;
}

// A description holding `body` from line 2 on.
std::string description(const std::string& body) { return "<mechatronics version=\"1\">\n" + body + "</mechatronics>\n"; }

struct Loaded {
    MechatronicSpec spec;
    std::vector<DriveError> errors;
};

Loaded load(const std::string& text) {
    Loaded l;
    load_drive_text(text, "joints.xml", "", l.spec, l.errors);
    return l;
}

// Every error of a one-entry description (its <joint> at line 2) holds one
// of `words`, in order, each at line 2, and the entry is dropped.
void expect_file_errors(const std::string& joint, const std::vector<std::string>& words) {
    const Loaded l = load(description(joint + "\n"));
    INFO(joint);
    REQUIRE(l.errors.size() == words.size());
    for (size_t i = 0; i < words.size(); ++i) {
        INFO(l.errors[i].text());
        CHECK(l.errors[i].file == "joints.xml");
        CHECK(l.errors[i].line == 2);
        CHECK(l.errors[i].text().find(words[i]) != std::string::npos);
    }
    CHECK(l.spec.joint_dynamics.empty());
}

std::vector<ResolvedJointDynamics> resolve(const std::string& joints, std::vector<DriveError>& errors) {
    const Loaded l = load(description(joints));
    for (const DriveError& e : l.errors) FAIL_CHECK(e.text());
    return resolve_joint_dynamics(l.spec, mechanism(), errors);
}

// The single resolution error of one <joint> (line 2), holding `words`.
void expect_resolve_error(const std::string& joint, const std::string& words) {
    std::vector<DriveError> errors;
    const std::vector<ResolvedJointDynamics> out = resolve(joint + "\n", errors);
    INFO(joint);
    REQUIRE(errors.size() == 1);
    INFO(errors[0].text());
    CHECK(errors[0].file == "joints.xml");
    CHECK(errors[0].line == 2);
    CHECK(errors[0].text().find(words) != std::string::npos);
    CHECK(out.empty());
}

}  // namespace

TEST_CASE("joint dynamics file: a clean entry gives every value in SI, positions in the unit it names") {
    const Loaded l = load(description(
        "<joint constraint=\"R1\" primitive=\"0\" damping=\"0.5\" coulomb=\"2\" coulomb_velocity=\"0.6\" "
        "stiffness=\"3\" rest=\"30\" armature=\"0.01\" lower=\"-90\" upper=\"45\" unit=\"deg\"/>\n"
        "<joint constraint=\"P1\" damping=\"7\" lower=\"-20\" upper=\"250\" unit=\"mm\"/>\n"
        "<joint constraint=\"C1\" primitive=\"1\" coulomb=\"0.25\"/>\n"));
    for (const DriveError& e : l.errors) FAIL_CHECK(e.text());
    REQUIRE(l.spec.joint_dynamics.size() == 3);
    const JointDynamicsSpec& r = l.spec.joint_dynamics[0];
    CHECK(r.joint.constraint_id == "R1");
    CHECK(r.joint.primitive == 0);
    CHECK(r.line == 2);
    CHECK(r.file == "joints.xml");
    // Coefficients are per rad whatever the unit; positions and the speed follow it.
    CHECK(r.damping == 0.5);
    CHECK(r.coulomb == 2);
    CHECK(r.stiffness == 3);
    CHECK(r.armature == 0.01);
    CHECK(r.coulomb_velocity == mbx_test::relative(0.6 * kPi / 180, 1e-15));
    CHECK(r.rest == mbx_test::relative(kPi / 6, 1e-15));
    CHECK(r.limited);
    CHECK(r.lower == mbx_test::relative(-kPi / 2, 1e-15));
    CHECK(r.upper == mbx_test::relative(kPi / 4, 1e-15));
    CHECK(r.unit == "deg");
    const JointDynamicsSpec& p = l.spec.joint_dynamics[1];
    CHECK(p.joint.primitive == -1);
    CHECK(p.damping == 7);
    CHECK(p.lower == mbx_test::relative(-0.02, 1e-15));
    CHECK(p.upper == mbx_test::relative(0.25, 1e-15));
    const JointDynamicsSpec& c = l.spec.joint_dynamics[2];
    CHECK(c.coulomb == 0.25);
    CHECK(c.damping == 0);
    CHECK(c.stiffness == 0);
    CHECK_FALSE(c.limited);
}

TEST_CASE("joint dynamics file: every problem is an error naming file, line and joint, all of an entry's at once") {
    expect_file_errors("<joint constraint=\"R1\" damping=\"1\" dampign=\"2\"/>", {"R1: unknown attribute 'dampign' on <joint>"});
    expect_file_errors("<joint constraint=\"R1\" damping=\"lots\"/>", {"damping = 'lots' is not a number"});
    expect_file_errors("<joint constraint=\"R1\" coulomb=\"inf\"/>", {"coulomb = 'inf' is not a number"});
    expect_file_errors("<joint constraint=\"R1\" stiffness=\"nan\"/>", {"stiffness = 'nan' is not a number"});
    for (const char* name : {"damping", "coulomb", "coulomb_velocity", "stiffness", "armature"})
        expect_file_errors("<joint constraint=\"R1\" " + std::string(name) + "=\"-1\"/>",
                           {std::string(name) + " must not be negative"});
    expect_file_errors("<joint constraint=\"R1\" lower=\"-1\"/>", {"needs both lower and upper (upper is missing)"});
    expect_file_errors("<joint constraint=\"R1\" upper=\"1\"/>", {"(lower is missing)"});
    expect_file_errors("<joint constraint=\"R1\" lower=\"1\" upper=\"-1\"/>", {"lower = 1 is above upper = -1"});
    expect_file_errors("<joint constraint=\"R1\" unit=\"grad\"/>", {"unit 'grad' is not rad, deg, m or mm"});
    expect_file_errors("<joint constraint=\"R1\" primitive=\"1.5\"/>", {"primitive must be a whole number >= 0"});
    expect_file_errors("<joint damping=\"1\"/>", {"<joint>: joint has no constraint"});
    expect_file_errors("<joint constraint=\"R1\"><damping value=\"1\"/></joint>",
                       {"unknown element <damping> in a joint"});
    // All of one entry's problems, in attribute order.
    expect_file_errors("<joint constraint=\"R1\" damping=\"-1\" coulomb=\"x\" armature=\"-2\" lower=\"3\" upper=\"2\" "
                       "speed=\"1\"/>",
                       {"unknown attribute 'speed'", "coulomb = 'x' is not a number", "damping must not be negative",
                        "armature must not be negative", "lower = 3 is above upper = 2"});

    // A second entry for the same joint names the first one's line; the good
    // entries of a file with a bad one are kept.
    const Loaded twice = load(description("<joint constraint=\"R1\" damping=\"1\"/>\n"
                                          "<joint constraint=\"P1\" damping=\"-1\"/>\n"
                                          "<joint constraint=\"R1\" damping=\"2\"/>\n"));
    REQUIRE(twice.errors.size() == 2);
    CHECK(twice.errors[0].line == 3);
    CHECK(twice.errors[1].line == 4);
    CHECK(twice.errors[1].text().find("a second <joint> for the same joint (the first is at line 2)") != std::string::npos);
    REQUIRE(twice.spec.joint_dynamics.size() == 1);
    CHECK(twice.spec.joint_dynamics[0].damping == 1);

    // The root names <joint> among the elements it knows.
    const Loaded unknown = load(description("<joints/>\n"));
    REQUIRE(unknown.errors.size() == 1);
    CHECK(unknown.errors[0].text().find("unknown element <joints> (library, drive, joint, body, mounting, collision, contact)") != std::string::npos);
}

TEST_CASE("description file: <mounting> reads its tilt in its unit, and refuses what is no tilt with the line") {
    const Loaded deg = load(description("<mounting tilt_x=\"2\" tilt_y=\"-1\" unit=\"deg\"/>\n"));
    REQUIRE(deg.errors.empty());
    CHECK(deg.spec.mounting.given);
    CHECK(deg.spec.mounting.tilt_x == mbx_test::relative(2 * M_PI / 180, 1e-15));
    CHECK(deg.spec.mounting.tilt_y == mbx_test::relative(-M_PI / 180, 1e-15));
    // Gravity turned 2 degrees about x, then -1 about y: its components are the rotations' (analytic).
    const Vec3 g = tilted_gravity(Vec3(0, 0, -9.81), deg.spec.mounting);
    const double a = 2 * M_PI / 180, b = -M_PI / 180;
    CHECK(g.x() == mbx_test::relative(-9.81 * std::sin(b), 1e-12));
    CHECK(g.y() == mbx_test::relative(9.81 * std::cos(b) * std::sin(a), 1e-12));
    CHECK(g.z() == mbx_test::relative(-9.81 * std::cos(b) * std::cos(a), 1e-12));
    CHECK(load(description("<mounting tilt_x=\"0.01\"/>\n")).spec.mounting.tilt_x == 0.01);  // rad by default
    struct Bad {
        const char* text;
        const char* words;
    };
    for (const Bad& bad : {Bad{"<mounting tilt_x=\"abc\"/>", "tilt_x = 'abc' is not a number"},
                           Bad{"<mounting tilt_x=\"2\" unit=\"grad\"/>", "unit = 'grad' is not rad or deg"},
                           Bad{"<mounting tilt_y=\"100\" unit=\"deg\"/>", "at most 90 degrees"},
                           Bad{"<mounting tilt_x=\"nan\"/>", "mounting"},
                           Bad{"<mounting tilt=\"1\"/>", "unknown attribute 'tilt'"},
                           Bad{"<mounting><x/></mounting>", "unknown element <x> in <mounting>"},
                           Bad{"<mounting/>\n<mounting/>", "a second <mounting> (the first is at line 2)"}}) {
        const Loaded l = load(description(std::string(bad.text) + "\n"));
        CAPTURE(bad.text);
        REQUIRE(!l.errors.empty());
        CHECK(l.errors.back().text().find(bad.words) != std::string::npos);
        CHECK(l.errors.back().text().find("joints.xml:") != std::string::npos);
    }
}

TEST_CASE("joint dynamics: resolution puts each entry's SI values on its Mechanism joint") {
    std::vector<DriveError> errors;
    const std::vector<ResolvedJointDynamics> out =
        resolve("<joint constraint=\"R1\" damping=\"0.5\" coulomb=\"2\" coulomb_velocity=\"0.01\" stiffness=\"3\" rest=\"0.2\" "
                "armature=\"0.01\" lower=\"-1.5\" upper=\"1.5\" unit=\"rad\"/>\n"
                "<joint constraint=\"P1\" damping=\"7\" lower=\"-20\" upper=\"250\" unit=\"mm\"/>\n"
                "<joint constraint=\"C1\" primitive=\"1\" coulomb=\"0.25\"/>\n"
                "<joint constraint=\"K2\" stiffness=\"4\"/>\n",
                errors);
    for (const DriveError& e : errors) FAIL_CHECK(e.text());
    REQUIRE(out.size() == 4);
    const ResolvedJointDynamics& r = out[0];
    CHECK(r.joint == joint_named("R1"));
    CHECK(r.source == 0);
    CHECK(r.name == "R1");
    CHECK_FALSE(r.linear);
    CHECK(r.damping == 0.5);
    CHECK(r.coulomb == 2);
    CHECK(r.coulomb_velocity == 0.01);
    CHECK(r.stiffness == 3);
    CHECK(r.rest == 0.2);
    CHECK(r.armature == 0.01);
    CHECK(r.limited);
    CHECK(r.lower == -1.5);
    CHECK(r.upper == 1.5);
    CHECK(out[1].joint == joint_named("P1"));
    CHECK(out[1].linear);
    CHECK(out[1].upper == mbx_test::relative(0.25, 1e-15));
    // The chain's second primitive (its first is J_N next to the base).
    const Mechanism& m = mechanism();
    const Joint& c1 = m.joints[size_t(out[2].joint)];
    CHECK(m.assembly.constraints[size_t(c1.constraint)].id == "C1");
    CHECK(c1.primitive_index == 1);
    CHECK(out[2].coulomb == 0.25);
    // A tree joint of the loop takes them.
    CHECK(out[3].joint == joint_named("K2"));
    CHECK_FALSE(m.joints[size_t(out[3].joint)].cut);
}

TEST_CASE("joint dynamics: resolution refuses joints that have no single coordinate, each with the entry's line") {
    REQUIRE(mechanism().joints[size_t(joint_named("K4"))].cut);
    expect_resolve_error("<joint constraint=\"NOPE\" damping=\"1\"/>", "NOPE: no constraint with id 'NOPE'");
    expect_resolve_error("<joint constraint=\"S1\" damping=\"1\"/>", "no prismatic or revolute primitive");
    expect_resolve_error("<joint constraint=\"S1\" primitive=\"0\" damping=\"1\"/>",
                         "joint 'S1' is spherical: joint dynamics act on one coordinate");
    expect_resolve_error("<joint constraint=\"W1\" damping=\"1\"/>", "no prismatic or revolute primitive");
    expect_resolve_error("<joint constraint=\"W1\" primitive=\"0\" damping=\"1\"/>", "no such primitive joint");
    expect_resolve_error("<joint constraint=\"C1\" damping=\"1\"/>", "say which with a primitive index");
    expect_resolve_error("<joint constraint=\"K4\" damping=\"1\"/>", "joint 'K4' closes a loop (cut joint)");
    expect_resolve_error("<joint constraint=\"P1\" rest=\"10\" unit=\"deg\"/>",
                         "positions in 'deg' for the prismatic joint 'P1'");
    expect_resolve_error("<joint constraint=\"R1\" rest=\"10\" unit=\"mm\"/>",
                         "positions in 'mm' for the revolute joint 'R1'");

    // The same joint by default and by chain index: the second names the first's line.
    std::vector<DriveError> errors;
    const auto twice = resolve("<joint constraint=\"R1\" damping=\"1\"/>\n<joint constraint=\"R1\" primitive=\"0\" damping=\"2\"/>\n",
                               errors);
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].line == 3);
    CHECK(errors[0].text().find("joint 'R1' is given joint dynamics twice (the first at line 2)") != std::string::npos);
    REQUIRE(twice.size() == 1);
    CHECK(twice[0].damping == 1);

    // Specs from the C API skip the file reader: resolution checks the values
    // again, reporting all of them, and keeps the good entries.
    MechatronicSpec spec;
    JointDynamicsSpec bad;
    bad.joint.constraint_id = "R1";
    bad.damping = -1;
    bad.stiffness = std::nan("");
    bad.rest = INFINITY;
    bad.limited = true;
    bad.lower = 1, bad.upper = 0;
    spec.joint_dynamics.push_back(bad);
    JointDynamicsSpec good;
    good.joint.constraint_id = "P1";
    good.armature = 2;
    spec.joint_dynamics.push_back(good);
    errors.clear();
    const auto mixed = resolve_joint_dynamics(spec, mechanism(), errors);
    REQUIRE(errors.size() == 4);
    CHECK(errors[0].text().find("R1: damping of joint 'R1' must be finite and not negative") != std::string::npos);
    CHECK(errors[1].text().find("R1: stiffness of joint 'R1' must be finite and not negative") != std::string::npos);
    CHECK(errors[2].text().find("R1: rest of joint 'R1' must be finite") != std::string::npos);
    CHECK(errors[3].text().find("R1: limits of joint 'R1' must be finite with lower <= upper") != std::string::npos);
    REQUIRE(mixed.size() == 1);
    CHECK(mixed[0].joint == joint_named("P1"));
    CHECK(mixed[0].armature == 2);
    CHECK(mixed[0].source == 1);
}

TEST_CASE("joint dynamics file: offset, asymmetric friction and Stribeck parse in SI and resolve to both directions") {
    const Loaded l = load(description(
        "<joint constraint=\"P1\" damping=\"3\" damping_negative=\"1.5\" coulomb=\"2\" coulomb_negative=\"0.5\" "
        "stribeck=\"0.7\" stribeck_velocity=\"20\" offset=\"-3.16\" unit=\"mm\"/>\n"
        "<joint constraint=\"R1\" coulomb=\"0.4\" offset=\"0.25\"/>\n"));
    for (const DriveError& e : l.errors) FAIL_CHECK(e.text());
    REQUIRE(l.spec.joint_dynamics.size() == 2);
    const JointDynamicsSpec& p = l.spec.joint_dynamics[0];
    REQUIRE(p.coulomb_negative.has_value());
    REQUIRE(p.damping_negative.has_value());
    CHECK(*p.coulomb_negative == 0.5);
    CHECK(*p.damping_negative == 1.5);
    CHECK(p.stribeck == 0.7);
    CHECK(p.stribeck_velocity == mbx_test::relative(0.02, 1e-15));  // 20 mm/s: speeds follow `unit`
    CHECK(p.offset == -3.16);
    const JointDynamicsSpec& r = l.spec.joint_dynamics[1];
    CHECK_FALSE(r.coulomb_negative.has_value());
    CHECK_FALSE(r.damping_negative.has_value());

    std::vector<DriveError> errors;
    const std::vector<ResolvedJointDynamics> out = resolve_joint_dynamics(l.spec, mechanism(), errors);
    for (const DriveError& e : errors) FAIL_CHECK(e.text());
    REQUIRE(out.size() == 2);
    CHECK(out[0].coulomb == 2);
    CHECK(out[0].coulomb_negative == 0.5);
    CHECK(out[0].damping_negative == 1.5);
    CHECK(out[0].offset == -3.16);
    CHECK(out[0].asymmetric());
    CHECK(out[0].symmetric_coulomb() == 1.25);
    CHECK(out[0].symmetric_damping() == 2.25);
    // Absent, the negative direction takes the positive one's values.
    CHECK(out[1].coulomb_negative == 0.4);
    CHECK(out[1].damping_negative == 0);
    CHECK_FALSE(out[1].asymmetric());
    CHECK(out[1].offset == 0.25);
}

TEST_CASE("joint dynamics file: bad offset, asymmetric or Stribeck values are errors with file and line") {
    for (const char* name : {"coulomb_negative", "damping_negative", "stribeck", "stribeck_velocity"})
        expect_file_errors("<joint constraint=\"R1\" " + std::string(name) + "=\"-1\"" +
                               (std::string(name) == "stribeck_velocity" ? "" : " stribeck_velocity=\"1\"") + "/>",
                           {std::string(name) + " must not be negative"});
    expect_file_errors("<joint constraint=\"R1\" stribeck=\"0.5\"/>", {"stribeck needs a positive stribeck_velocity"});
    expect_file_errors("<joint constraint=\"R1\" stribeck=\"0.5\" stribeck_velocity=\"0\"/>",
                       {"stribeck needs a positive stribeck_velocity"});
    expect_file_errors("<joint constraint=\"R1\" offset=\"inf\"/>", {"offset = 'inf' is not a number"});
    expect_file_errors("<joint constraint=\"R1\" offset=\"nan\"/>", {"offset = 'nan' is not a number"});
    // A negative offset is a load the other way, not an error.
    const Loaded negative = load(description("<joint constraint=\"R1\" offset=\"-2\"/>\n"));
    CHECK(negative.errors.empty());

    // Through the C API's path (no file reader) resolution checks them again.
    MechatronicSpec spec;
    JointDynamicsSpec bad;
    bad.joint.constraint_id = "R1";
    bad.offset = INFINITY;
    bad.coulomb_negative = -1;
    bad.stribeck = 1;
    spec.joint_dynamics.push_back(bad);
    std::vector<DriveError> errors;
    const auto out = resolve_joint_dynamics(spec, mechanism(), errors);
    CHECK(out.empty());
    REQUIRE(errors.size() == 3);
    CHECK(errors[0].text().find("coulomb_negative of joint 'R1' must be finite and not negative") != std::string::npos);
    CHECK(errors[1].text().find("joint 'R1': offset must be finite") != std::string::npos);
    CHECK(errors[2].text().find("joint 'R1': stribeck needs a positive stribeck_velocity") != std::string::npos);
}

TEST_CASE("joint dynamics file: a <transmission> in a joint gives its coefficients in SI, the dead band in the joint's unit") {
    const Loaded l = load(description("<joint constraint=\"R1\" damping=\"1\" unit=\"deg\">\n"
                                      "  <transmission stiffness=\"2000\" damping=\"0.5\" motor_inertia=\"0.01\" backlash=\"0.5\"/>\n"
                                      "</joint>\n<joint constraint=\"P1\" damping=\"2\"/>\n"));
    for (const DriveError& e : l.errors) FAIL_CHECK(e.text());
    REQUIRE(l.spec.joint_dynamics.size() == 2);
    REQUIRE(l.spec.joint_dynamics[0].transmission);
    const TransmissionSpec& t = *l.spec.joint_dynamics[0].transmission;
    CHECK(t.stiffness == 2000);
    CHECK(t.damping == 0.5);
    CHECK(t.motor_inertia == 0.01);
    CHECK(t.backlash == mbx_test::relative(0.5 * kPi / 180, 1e-15));
    CHECK(t.line == 3);
    CHECK_FALSE(l.spec.joint_dynamics[1].transmission);
    std::vector<DriveError> errors;
    const std::vector<ResolvedJointDynamics> out = resolve_joint_dynamics(l.spec, mechanism(), errors);
    CHECK(errors.empty());
    REQUIRE(out.size() == 2);
    REQUIRE(out[0].transmission);
    CHECK(out[0].transmission->stiffness == 2000);
    CHECK_FALSE(out[1].transmission);
}

TEST_CASE("joint dynamics file: a bad <transmission> is an error at its own line, naming the joint") {
    auto expect = [](const std::string& transmission, const std::vector<std::string>& words) {
        const Loaded l = load(description("<joint constraint=\"R1\">\n" + transmission + "\n</joint>\n"));
        INFO(transmission);
        REQUIRE(l.errors.size() == words.size());
        for (size_t i = 0; i < words.size(); ++i) {
            INFO(l.errors[i].text());
            CHECK(l.errors[i].file == "joints.xml");
            CHECK(l.errors[i].line == 3);
            CHECK(l.errors[i].text().find("R1") != std::string::npos);
            CHECK(l.errors[i].text().find(words[i]) != std::string::npos);
        }
        CHECK(l.spec.joint_dynamics.empty());
    };
    expect("<transmission stiffness=\"-1\" motor_inertia=\"0.1\"/>", {"transmission stiffness must be finite and not negative"});
    expect("<transmission stiffness=\"10\" damping=\"-1\" motor_inertia=\"0.1\"/>", {"transmission damping must be finite and not negative"});
    expect("<transmission stiffness=\"10\" motor_inertia=\"0\"/>", {"transmission motor_inertia must be positive"});
    expect("<transmission stiffness=\"10\"/>", {"transmission needs motor_inertia", "motor_inertia must be positive"});
    expect("<transmission motor_inertia=\"0.1\"/>", {"needs a positive stiffness, or a backlash"});
    expect("<transmission stiffness=\"stiff\" motor_inertia=\"0.1\"/>", {"stiffness = 'stiff' is not a number", "needs a positive stiffness"});
    expect("<transmission stiffness=\"10\" motor_inertia=\"0.1\" gear=\"3\"/>", {"unknown attribute 'gear' on <transmission>"});
    // A second one names the first's line.
    const Loaded twice = load(description("<joint constraint=\"R1\">\n<transmission stiffness=\"1\" motor_inertia=\"1\"/>\n"
                                          "<transmission stiffness=\"2\" motor_inertia=\"1\"/>\n</joint>\n"));
    REQUIRE(twice.errors.size() == 1);
    CHECK(twice.errors[0].line == 4);
    CHECK(twice.errors[0].text().find("a second <transmission> in the joint (the first is at line 3)") != std::string::npos);

    // Through the C API's path (no file reader) resolution checks it again.
    MechatronicSpec spec;
    JointDynamicsSpec bad;
    bad.joint.constraint_id = "R1";
    bad.transmission = TransmissionSpec{};
    bad.transmission->stiffness = NAN;
    bad.transmission->motor_inertia = 1;
    spec.joint_dynamics.push_back(bad);
    std::vector<DriveError> errors;
    CHECK(resolve_joint_dynamics(spec, mechanism(), errors).empty());
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].text().find("joint 'R1': transmission stiffness must be finite and not negative") != std::string::npos);
}
}  // namespace MBX_UNITY_ID
