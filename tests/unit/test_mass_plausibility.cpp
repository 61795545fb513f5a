// Mass plausibility from the host's own numbers: the density a part's CAD mass
// and CAD volume imply, and a stated assembly mass against the parts' sum.
// Read through the host reader, so the volume's unit conversion is covered.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "core/assembly/host_reader.h"
#include "apps/stub_host/assemblies/stub_assembly.h"
#include "core/translator/translate.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

mbx_pose identity_at(double x) {
    mbx_pose p{};
    p.position[0] = x;
    p.rotation[0] = p.rotation[4] = p.rotation[8] = 1;
    return p;
}

// Ground and one 'block' part on a revolute, in `units`; the block's mass and
// volume as given (host units).
mbx_stub::Assembly block_assembly(mbx_units units, double mass, double volume, double length = 1) {
    mbx_stub::Assembly a;
    a.name = "blocks";
    mbx_stub::Body ground;
    ground.id = "ground";
    ground.flags = MBX_BODY_GROUND;
    ground.units = units;
    ground.pose = identity_at(0);
    mbx_stub::Body block = ground;
    block.id = "block";
    block.flags = 0;
    block.mass = mass;
    block.volume = volume;
    // A solid cube's tensor (m a^2 / 6), so no inertia finding interferes.
    block.inertia[0] = block.inertia[4] = block.inertia[8] = mass * length * length / 6;
    block.pose = identity_at(length);
    a.bodies = {ground, block};
    mbx_stub::Frame fg, fb;
    fg.id = "fg";
    fg.body_id = "ground";
    fb.id = "fb";
    fb.body_id = "block";
    fg.units = fb.units = units;
    fg.pose = fb.pose = identity_at(length);
    a.frames = {fg, fb};
    mbx_stub::Constraint c;
    c.id = "hinge";
    c.base_frame_id = "fg";
    c.follower_frame_id = "fb";
    c.chain = {mbx_stub::Primitive{MBX_PRIMITIVE_REVOLUTE}};
    a.constraints = {c};
    return a;
}

std::unique_ptr<Mechanism> translate(const mbx_stub::Assembly& a) {
    mbx_stub::Host host(a);
    Progress progress;
    Findings findings;
    Assembly assembly = read_host(host.table(), HostReadOptions{}, progress, findings);
    return translate_assembly(std::move(assembly), std::move(findings), TranslateOptions{}, progress);
}

std::vector<const Finding*> found(const Mechanism& m, mbx_finding_code code) {
    std::vector<const Finding*> out;
    for (const Finding& f : m.findings)
        if (f.code == code) out.push_back(&f);
    return out;
}

constexpr mbx_units kMillimetreKilogram{0.001, 1, 0};

}  // namespace

TEST_CASE("density: an aluminium part (2.7 kg in 1e6 mm^3) is plausible and its CAD volume reaches SI") {
    auto m = translate(block_assembly(kMillimetreKilogram, 2.7, 1e6, 100));
    CHECK(m->assembly.parts[1].volume == mbx_test::relative(1e-3, 1e-6));  // 1e6 mm^3 = 1e-3 m^3
    CHECK(found(*m, MBX_FINDING_IMPLAUSIBLE_DENSITY).empty());
}

TEST_CASE("density: mass numerically equal to the volume in mm^3 is the CAD default density, 1e9 kg/m^3") {
    // A 50 mm cube: 125 000 mm^3, and "125 000 kg" from a default of 1 kg/mm^3.
    auto m = translate(block_assembly(kMillimetreKilogram, 125000, 125000, 50));
    const auto f = found(*m, MBX_FINDING_IMPLAUSIBLE_DENSITY);
    REQUIRE(f.size() == 1);
    CHECK(f[0]->severity == MBX_SEVERITY_WARNING);
    CHECK(f[0]->subject.kind == MBX_SUBJECT_BODY);
    CHECK(f[0]->subject.id == "block");
    CHECK(std::string(f[0]->code_name()) == "implausible_density");
    // 125 000 kg / 1.25e-4 m^3 = 1e9 kg/m^3, named with the default-density diagnosis.
    CHECK(f[0]->message.find("density 1e+09 kg/m^3") != std::string::npos);
    CHECK(f[0]->message.find("default density of 1") != std::string::npos);
}

TEST_CASE("density: 1 lbm/in^3 (the Pro/E inch default, FOURBAR) is 27 680 kg/m^3 and flagged") {
    const mbx_units inch_pound{0.0254, 0.45359237, 0};
    auto m = translate(block_assembly(inch_pound, 3.5, 3.5, 2));
    const auto f = found(*m, MBX_FINDING_IMPLAUSIBLE_DENSITY);
    REQUIRE(f.size() == 1);
    // 0.45359237 / 0.0254^3 = 27679.9 kg/m^3.
    CHECK(f[0]->message.find("density 27679.9 kg/m^3") != std::string::npos);
    CHECK(f[0]->message.find("default density of 1") != std::string::npos);
}

TEST_CASE("density: the range bounds, osmium passes, too light and too heavy are named without the default diagnosis") {
    // Osmium, 22 590 kg/m^3: 22.59 kg in 1e6 mm^3.
    CHECK(found(*translate(block_assembly(kMillimetreKilogram, 22.59, 1e6, 100)), MBX_FINDING_IMPLAUSIBLE_DENSITY)
              .empty());
    // Balsa, 120 kg/m^3, passes; 20 kg/m^3 (below 50) does not.
    CHECK(found(*translate(block_assembly(kMillimetreKilogram, 0.12, 1e6, 100)), MBX_FINDING_IMPLAUSIBLE_DENSITY)
              .empty());
    auto light = translate(block_assembly(kMillimetreKilogram, 0.02, 1e6, 100));
    auto f = found(*light, MBX_FINDING_IMPLAUSIBLE_DENSITY);
    REQUIRE(f.size() == 1);
    CHECK(f[0]->message.find("density 20 kg/m^3") != std::string::npos);
    CHECK(f[0]->message.find("default density of 1") == std::string::npos);
    // 30 000 kg/m^3: denser than any element.
    auto heavy = translate(block_assembly(kMillimetreKilogram, 30, 1e6, 100));
    REQUIRE(found(*heavy, MBX_FINDING_IMPLAUSIBLE_DENSITY).size() == 1);
}

TEST_CASE("density: no volume (an older host) or no mass means no check, a negative volume is refused") {
    CHECK(found(*translate(block_assembly(kMillimetreKilogram, 125000, 0, 50)), MBX_FINDING_IMPLAUSIBLE_DENSITY)
              .empty());
    CHECK(found(*translate(block_assembly(kMillimetreKilogram, 0, 125000, 50)), MBX_FINDING_IMPLAUSIBLE_DENSITY)
              .empty());
    mbx_stub::Host host(block_assembly(kMillimetreKilogram, 1, -5, 50));
    Progress progress;
    Findings findings;
    try {
        read_host(host.table(), HostReadOptions{}, progress, findings);
        FAIL("a negative volume was accepted");
    } catch (const Error& e) {
        CHECK(e.status() == MBX_ERROR_INVALID_INPUT);
        CHECK(e.subject().id == "block");
        CHECK(std::string(e.what()).find("negative volume") != std::string::npos);
    }
}

TEST_CASE("assembly mass: a stated mass within 2 % of the parts' sum passes, 10 % off is named") {
    mbx_stub::Assembly a = block_assembly(kMillimetreKilogram, 2.7, 1e6, 100);
    a.bodies[0].mass = 1.3;  // ground part counts as well: sum 4.0 kg
    a.bodies[0].inertia[0] = a.bodies[0].inertia[4] = a.bodies[0].inertia[8] = 1;
    a.mass = 4.05;  // 1.2 % apart
    CHECK(found(*translate(a), MBX_FINDING_ASSEMBLY_MASS_MISMATCH).empty());
    a.mass = 4.4;  // 9.1 % apart
    auto m = translate(a);
    const auto f = found(*m, MBX_FINDING_ASSEMBLY_MASS_MISMATCH);
    REQUIRE(f.size() == 1);
    CHECK(f[0]->subject.kind == MBX_SUBJECT_MODEL);
    CHECK(f[0]->message.find("4.4 kg") != std::string::npos);
    CHECK(f[0]->message.find("2 parts add up to 4 kg") != std::string::npos);
    CHECK(f[0]->message.find("9.09 % apart") != std::string::npos);
    // No stated mass: nothing to compare.
    a.mass = 0;
    CHECK(found(*translate(a), MBX_FINDING_ASSEMBLY_MASS_MISMATCH).empty());
}

TEST_CASE("density: a power of ten typed in the host's units is a placeholder even inside the range") {
    // LEGS15's SIM_SEA_L_HIP_1: 1.88034 kg in 188034 mm^3, exactly 1e-5 kg/mm^3 = 10 000 kg/m^3.
    auto m = translate(block_assembly(kMillimetreKilogram, 1.88034, 188034, 57));
    auto f = found(*m, MBX_FINDING_IMPLAUSIBLE_DENSITY);
    REQUIRE(f.size() == 1);
    CHECK(f[0]->severity == MBX_SEVERITY_WARNING);
    CHECK(f[0]->message.find("density 10000 kg/m^3, exactly 1e-05 in the host's units") != std::string::npos);
    // Its right-leg twin, 0.9279 kg in the same volume (4934.75 kg/m^3), is a real material.
    CHECK(found(*translate(block_assembly(kMillimetreKilogram, 0.9279, 188034, 57)), MBX_FINDING_IMPLAUSIBLE_DENSITY)
              .empty());
    // Six printed digits: 1.88036 is 1.1e-5 off 1e-5 and still the typed value; 1.8807 (2e-4 off) is not.
    CHECK(found(*translate(block_assembly(kMillimetreKilogram, 1.88036, 188034, 57)), MBX_FINDING_IMPLAUSIBLE_DENSITY)
              .size() == 1);
    CHECK(found(*translate(block_assembly(kMillimetreKilogram, 1.8807, 188034, 57)), MBX_FINDING_IMPLAUSIBLE_DENSITY)
              .empty());
    // The same placeholder in metres and kilograms: 10 000 kg/m^3 typed as 1e4.
    const mbx_units metre_kilogram{1, 1, 0};
    CHECK(found(*translate(block_assembly(metre_kilogram, 1.88034, 1.88034e-4, 0.057)), MBX_FINDING_IMPLAUSIBLE_DENSITY)
              .size() == 1);
}
}  // namespace MBX_UNITY_ID
