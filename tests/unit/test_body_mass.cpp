// Body mass corrections in the description file (<body id mass_scale>,
// docs/mechatronics.md): parse errors name file, line and body; resolution
// finds a body by its own id or any of its parts' ids and refuses the rest;
// applying scales mass and inertia from the CAD values every time, so a
// second description does not compound the first.
#include <doctest/doctest.h>

#include <string>

#include "assembly_builder.h"
#include "core/progress.h"
#include "core/mechatronics/drive_file.h"
#include "core/translator/translate.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// ground -- R1 -- arm (with a bracket welded on) -- R2 -- forearm
std::unique_ptr<Mechanism> arm() {
    test::AssemblyBuilder b;
    const int ground = b.part("ground", 1, {0, 0, 0}, MBX_BODY_GROUND);
    const int upper = b.part("upper", 2, {0.5, 0, 0});
    const int bracket = b.part("bracket", 0.5, {0.5, 0.2, 0});
    const int fore = b.part("fore", 1, {1.5, 0, 0});
    b.revolute("R1", ground, upper, {0, 0, 0});
    b.weld("W1", upper, bracket);
    b.revolute("R2", upper, fore, {1, 0, 0});
    Progress progress;
    return translate_assembly(b.a, {}, TranslateOptions{}, progress);
}

int body_with_part(const Mechanism& m, const std::string& part) {
    for (size_t b = 0; b < m.bodies.size(); ++b)
        for (int p : m.bodies[b].parts)
            if (m.assembly.parts[size_t(p)].id == part) return int(b);
    return -1;
}

BodyMassSpec spec_of(const std::string& body, double scale, int line) {
    BodyMassSpec s;
    s.body = body, s.mass_scale = scale, s.file = "d.xml", s.line = line;
    return s;
}

std::string texts(const std::vector<DriveError>& errors) {
    std::string s;
    for (const DriveError& e : errors) s += e.text() + "\n";
    return s;
}

}  // namespace

TEST_CASE("body mass: the description's <body> elements, and what is wrong with them") {
    MechatronicSpec spec;
    std::vector<DriveError> errors;
    load_drive_text("<mechatronics version=\"1\">\n"
                    "  <body id=\"fore\" mass_scale=\"1.25\"/>\n"
                    "  <body id=\"upper\" mass_scale=\"-1\"/>\n"
                    "  <body id=\"fore\" mass_scale=\"2\"/>\n"
                    "  <body mass_scale=\"2\"/>\n"
                    "  <body id=\"x\" mass=\"2\"/>\n"
                    "  <body id=\"y\" mass_scale=\"nan\"/>\n"
                    "</mechatronics>\n",
                    "d.xml", "", spec, errors);
    const std::string all = texts(errors);
    INFO(all);
    REQUIRE(spec.body_masses.size() == 1);
    CHECK(spec.body_masses[0].body == "fore");
    CHECK(spec.body_masses[0].mass_scale == 1.25);
    CHECK(spec.body_masses[0].line == 2);
    CHECK(all.find("d.xml:3: upper: mass_scale must be positive") != std::string::npos);
    CHECK(all.find("d.xml:4: fore: a second <body> for the same body (the first is at line 2)") != std::string::npos);
    CHECK(all.find("d.xml:5: <body>: body has no id") != std::string::npos);
    CHECK(all.find("d.xml:6: x: unknown attribute 'mass' on <body>") != std::string::npos);
    CHECK(all.find("d.xml:7: y: mass_scale = 'nan' is not a number") != std::string::npos);
}

TEST_CASE("body mass: resolved by body or part id, applied from the CAD inertia") {
    std::unique_ptr<Mechanism> m = arm();
    const int upper = body_with_part(*m, "upper"), fore = body_with_part(*m, "fore");
    REQUIRE(upper >= 0);
    REQUIRE(body_with_part(*m, "bracket") == upper);  // welded: one body
    const double upper_mass = m->bodies[size_t(upper)].mass, fore_mass = m->bodies[size_t(fore)].mass;
    const Mat3 fore_inertia = m->bodies[size_t(fore)].inertia;
    REQUIRE(upper_mass == mbx_test::relative(2.5, 1e-6));

    std::vector<BodyMassSpec> specs = {spec_of("bracket", 0.8, 2), spec_of("fore", 1.5, 3)};
    std::vector<LibraryError> errors;
    const std::vector<ResolvedBodyMass> r = resolve_body_masses(specs, *m, nullptr, errors);
    CHECK(errors.empty());
    REQUIRE(r.size() == 2);
    CHECK(r[0].body == upper);
    CHECK(r[1].body == fore);

    const CadInertia cad = cad_inertia(*m);
    apply_body_masses(*m, cad, r);
    CHECK(m->bodies[size_t(upper)].mass == mbx_test::relative(0.8 * upper_mass, 1e-6));
    CHECK(m->bodies[size_t(fore)].mass == mbx_test::relative(1.5 * fore_mass, 1e-6));
    CHECK((m->bodies[size_t(fore)].inertia - 1.5 * fore_inertia).norm() < 1e-12);
    // Again, with only the forearm's: the upper arm is back to its CAD mass, nothing compounds.
    apply_body_masses(*m, cad, {r[1]});
    CHECK(m->bodies[size_t(upper)].mass == mbx_test::relative(upper_mass, 1e-6));
    CHECK(m->bodies[size_t(fore)].mass == mbx_test::relative(1.5 * fore_mass, 1e-6));

    // Unknown ids, the same body twice (through two of its parts), the ground.
    specs = {spec_of("nothing", 1.1, 4), spec_of("upper", 1.1, 5), spec_of("bracket", 1.2, 6), spec_of("ground", 2, 7)};
    errors.clear();
    const std::vector<ResolvedBodyMass> r2 = resolve_body_masses(specs, *m, nullptr, errors);
    CHECK(r2.size() == 1);
    const std::string all = texts(errors);
    INFO(all);
    CHECK(all.find("d.xml:4: nothing: no body or CAD part 'nothing'") != std::string::npos);
    CHECK(all.find("d.xml:6: bracket: body") != std::string::npos);
    CHECK(all.find("corrected twice (first at line 5)") != std::string::npos);
    CHECK(all.find("d.xml:7: ground:") != std::string::npos);
}

TEST_CASE("body mass: a centre of mass moved and an inertia changed, read, checked and applied from the CAD values") {
    MechatronicSpec spec;
    std::vector<DriveError> errors;
    load_drive_text("<mechatronics version=\"1\">\n"
                    "  <body id=\"fore\" mass_scale=\"2\" com_shift=\" 0.01 -0.02\t0.03 \" inertia_change=\"1e-3 2e-3 0 0 0 -1e-4\"/>\n"
                    "  <body id=\"upper\" com_shift=\"0.01 0.02\"/>\n"
                    "  <body id=\"bracket\" inertia_change=\"1 2 3 4 5 6 7\"/>\n"
                    "  <body id=\"x\" com_shift=\"0 nan 0\"/>\n"
                    "</mechatronics>\n",
                    "d.xml", "", spec, errors);
    const std::string all = texts(errors);
    INFO(all);
    REQUIRE(spec.body_masses.size() == 1);
    const BodyMassSpec& s = spec.body_masses[0];
    CHECK(s.mass_scale == 2);
    CHECK(s.com_shift == Vec3(0.01, -0.02, 0.03));
    CHECK(s.inertia_change == InertiaEntries{1e-3, 2e-3, 0, 0, 0, -1e-4});
    CHECK(all.find("d.xml:3: upper: com_shift = '0.01 0.02' is not 3 numbers") != std::string::npos);
    CHECK(all.find("d.xml:4: bracket: inertia_change = '1 2 3 4 5 6 7' is not 6 numbers") != std::string::npos);
    CHECK(all.find("d.xml:5: x: com_shift = '0 nan 0' is not 3 numbers") != std::string::npos);

    std::unique_ptr<Mechanism> m = arm();
    const int fore = body_with_part(*m, "fore");
    const RigidBody cad = m->bodies[size_t(fore)];
    std::vector<LibraryError> lib_errors;
    const std::vector<ResolvedBodyMass> r = resolve_body_masses(spec.body_masses, *m, nullptr, lib_errors);
    REQUIRE(lib_errors.empty());
    REQUIRE(r.size() == 1);
    const CadInertia base = cad_inertia(*m);
    for (int twice = 0; twice < 2; ++twice) {  // from the CAD values each time
        apply_body_masses(*m, base, r);
        const RigidBody& b = m->bodies[size_t(fore)];
        CHECK(b.mass == mbx_test::relative(2 * cad.mass, 1e-6));
        CHECK((b.com - (cad.com + Vec3(0.01, -0.02, 0.03))).norm() < 1e-15);
        Mat3 change;
        change << 1e-3, 0, 0, 0, 2e-3, -1e-4, 0, -1e-4, 0;
        CHECK((b.inertia - (2 * cad.inertia + change)).norm() < 1e-15);
    }

    // A change no rigid body can have is refused by name: negative, or one
    // principal moment above the sum of the other two.
    const std::pair<InertiaEntries, const char*> bad[] = {
        {InertiaEntries{-1e6, 0, 0, 0, 0, 0}, "not positive definite"},
        {InertiaEntries{0, 0, 1e3, 0, 0, 0}, "exceeds the sum of the other two"}};
    for (const auto& [change, why] : bad) {
        BodyMassSpec b = spec_of("fore", 1, 9);
        b.inertia_change = change;
        lib_errors.clear();
        CHECK(resolve_body_masses({b}, *m, &base, lib_errors).empty());
        REQUIRE(lib_errors.size() == 1);
        CHECK(lib_errors[0].object == "fore");
        CHECK(lib_errors[0].line == 9);
        CHECK(lib_errors[0].message.find(why) != std::string::npos);
    }
}
}  // namespace MBX_UNITY_ID
