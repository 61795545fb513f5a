// Host ABI 4 mass data through the plugin: the body volume and the stated
// assembly mass, read only from tables that declare them, and the findings
// they give (see also tests/unit/test_mass_plausibility.cpp).
#include <doctest/doctest.h>

#include <cstring>
#include <string>
#include <vector>

#include "../common/file_text.h"
#include "support/plugin_fixture.h"
#include "support/temp_dir.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace itest;

namespace {

std::vector<mbx_finding> findings(const mbx_mechanism* m, mbx_finding_code code) {
    std::vector<mbx_finding> out;
    for (uint32_t i = 0; i < api().mechanism_finding_count(m); ++i) {
        mbx_finding f{};
        f.struct_size = sizeof f;
        REQUIRE(api().mechanism_get_finding(m, i, &f) == MBX_OK);
        if (f.code == code) out.push_back(f);
    }
    return out;
}

// The fourbar builtin (mm, g) with every real part's volume that of aluminium,
// 2.7e-3 g/mm^3, in the host's units.
mbx_stub::Assembly aluminium_fourbar(double& parts_kg) {
    mbx_stub::Assembly a = builtin("fourbar");
    parts_kg = 0;
    for (auto& b : a.bodies) {
        REQUIRE(b.units.length_to_m == 0.001);
        REQUIRE(b.units.mass_to_kg == 0.001);
        if (b.mass > 0) b.volume = b.mass / 2.7e-3;
        parts_kg += b.mass * b.units.mass_to_kg;
    }
    return a;
}

struct Translated {
    std::unique_ptr<mbx_stub::Host> host;
    ContextPtr ctx = make_context();
    MechanismPtr mech;

    Translated(mbx_stub::Assembly a, uint32_t table_size = sizeof(mbx_host)) {
        host = std::make_unique<mbx_stub::Host>(std::move(a));
        mbx_host table = *host->table();
        table.struct_size = table_size;
        mbx_mechanism* raw = nullptr;
        REQUIRE(api().translate(ctx.get(), &table, nullptr, &raw) == MBX_OK);
        mech.reset(raw);
    }
};

}  // namespace

TEST_CASE("host mass data: aluminium parts pass, one left at 1 g/mm^3 is named with 1e6 kg/m^3") {
    double parts_kg = 0;
    mbx_stub::Assembly a = aluminium_fourbar(parts_kg);
    CHECK(findings(Translated(a).mech.get(), MBX_FINDING_IMPLAUSIBLE_DENSITY).empty());

    std::string crank;
    for (auto& b : a.bodies)
        if (b.name == "Crank") b.volume = b.mass, crank = b.id;  // the CAD default: 1 g/mm^3
    Translated t(a);
    const auto f = findings(t.mech.get(), MBX_FINDING_IMPLAUSIBLE_DENSITY);
    REQUIRE(f.size() == 1);
    CHECK(f[0].severity == MBX_SEVERITY_WARNING);
    CHECK(f[0].subject_kind == MBX_SUBJECT_BODY);
    CHECK(std::string(f[0].subject_id) == crank);
    CHECK(std::string(f[0].code_name) == "implausible_density");
    CHECK(std::string(f[0].message).find("density 1e+06 kg/m^3") != std::string::npos);
    CHECK(std::string(f[0].message).find("default density of 1") != std::string::npos);

    TempDir dir;
    REQUIRE(api().mechanism_write_report(t.ctx.get(), t.mech.get(), dir.path.string().c_str()) == MBX_OK);
    const std::string json = mbx_test::read_file(dir.path / "report.json");
    // Each part's density is in the report; the crank's is 1e6 kg/m^3 (to rounding).
    const size_t at = json.find("\"id\": \"" + crank + "\"");
    REQUIRE(at != std::string::npos);
    const std::string key = "\"cad_density_kg_m3\": ";
    const size_t d = json.find(key, at);
    REQUIRE(d != std::string::npos);
    CHECK(std::stod(json.substr(d + key.size(), 32)) == mbx_test::relative(1e6, 1e-12));
    CHECK(json.find("\"implausible_density\"") != std::string::npos);
}

TEST_CASE("host mass data: a stated assembly mass 50 % above the parts' sum is named, a version-3 table is not asked") {
    double parts_kg = 0;
    mbx_stub::Assembly a = aluminium_fourbar(parts_kg);
    a.mass = 1.5 * parts_kg;
    const Translated t(a);  // the findings' strings live as long as the mechanism
    const auto f = findings(t.mech.get(), MBX_FINDING_ASSEMBLY_MASS_MISMATCH);
    REQUIRE(f.size() == 1);
    CHECK(f[0].subject_kind == MBX_SUBJECT_MODEL);
    CHECK(std::string(f[0].message).find("33.3 % apart") != std::string::npos);  // |1.5 - 1| / 1.5

    a.mass = parts_kg * 1.001;  // within rounding of a CAD sum
    CHECK(findings(Translated(a).mech.get(), MBX_FINDING_ASSEMBLY_MASS_MISMATCH).empty());

    // The same host compiled against version 3: its table ends before
    // get_assembly_mass, which must not be read.
    a.mass = 1.5 * parts_kg;
    const uint32_t v3_size = uint32_t(offsetof(mbx_host, get_diagnostic) + sizeof(void*));
    CHECK(findings(Translated(a, v3_size).mech.get(), MBX_FINDING_ASSEMBLY_MASS_MISMATCH).empty());
}
}  // namespace MBX_UNITY_ID
