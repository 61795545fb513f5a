// Mass plausibility on PMXML: the adapter hands <volume> across the host table
// (host ABI 4) in the body's length unit, and the SDK names parts whose CAD
// mass / CAD volume is no real material's density. The real exports are all
// within the range of real materials (each file's range is printed), but the
// 2015 legs give their eight mirrored left-leg parts exactly 1e-5 kg/mm^3, a
// typed placeholder; a part given the CAD default density of 1 kg/mm^3 is caught. Also: a mesh file that passes the open-time
// probe but breaks when loaded becomes a finding once it is loaded.
#include <algorithm>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <pugixml.hpp>

#include "adapter_test_support.h"
#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "tiny_pmxml.h"
#include "translation_support.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using mbx_files::FileAdapter;

namespace {

// Densities written in a report.json (parts with a CAD volume).
std::vector<double> report_densities(const std::string& json) {
    std::vector<double> out;
    static const std::regex density("\"cad_density_kg_m3\": ([-0-9.eE+]+)");
    for (std::sregex_iterator it(json.begin(), json.end(), density), end; it != end; ++it)
        out.push_back(std::stod((*it)[1].str()));
    return out;
}

// The same, straight from the XML: every file in the corpus is in kg and mm^3.
std::vector<double> xml_densities(const std::string& path) {
    pugi::xml_document doc;
    REQUIRE(doc.load_file(path.c_str()));
    std::vector<double> out;
    for (const pugi::xpath_node& n : doc.select_nodes("//Body")) {
        const pugi::xml_node b = n.node();
        REQUIRE(std::string(b.child_value("massUnits")) == "\"kg\"");
        const double mass = std::stod(b.child_value("mass")), volume = std::stod(b.child_value("volume"));
        if (volume <= 0) continue;
        REQUIRE(std::string(b.child_value("volumeUnits")) == "\"mm^3\"");
        out.push_back(mass / (volume * 1e-9));
    }
    return out;
}

std::vector<atest::FindingCopy> findings_of(const atest::Translation& t, mbx_finding_code code) {
    std::vector<atest::FindingCopy> out;
    for (const atest::FindingCopy& f : t.findings())
        if (f.code == code) out.push_back(f);
    return out;
}

}  // namespace

TEST_CASE("mass plausibility: real exports' densities are as their XML says, only LEGS15's placeholder is named") {
    const std::string data = atest::pmxml_data_dir();
    if (data.empty()) return;
    for (const char* file : {"ergocub/SIM_ERGOCUB_1-0.xml", "ironcub/IRONCUB-MK1_SIM_MODEL.xml",
                             "ironcub/IRONCUB-MK1_1_SIM_MODEL.xml", "legs_mechanism_2014/LEGS_MECHANISM.xml",
                             "legs_mechanism_2015/LEGS_MECHANISM.xml"}) {
        INFO(std::string(file));
        const std::string path = data + "/" + file;
        const auto adapter = FileAdapter::open(path);
        atest::Translation t(adapter->table(), 0);
        REQUIRE(t.status() == MBX_OK);
        const auto flagged = findings_of(t, MBX_FINDING_IMPLAUSIBLE_DENSITY);
        if (std::string(file) == "legs_mechanism_2015/LEGS_MECHANISM.xml") {
            // SIM_SEA_L_HIP_1 ... SIM_SEA_L_SOLE: mass = volume x 1e-5 to the digit, while the
            // right-leg twins of the same volumes weigh 2 to 8 times less.
            REQUIRE(flagged.size() == 8);
            for (const atest::FindingCopy& f : flagged) {
                CHECK(f.subject_name.rfind("SIM_SEA_L_", 0) == 0);
                CHECK(f.message.find("density 10000 kg/m^3, exactly 1e-05 in the host's units") != std::string::npos);
            }
        } else {
            CHECK(flagged.empty());
        }
        atest::TempDir dir;
        t.write_report(dir.path.string());
        std::vector<double> got = report_densities(atest::read_file((dir.path / "report.json").string()));
        std::vector<double> want = xml_densities(path);
        std::sort(got.begin(), got.end());
        std::sort(want.begin(), want.end());
        REQUIRE(got.size() == want.size());
        REQUIRE(!got.empty());
        for (size_t i = 0; i < got.size(); ++i) CHECK(got[i] == mbx_test::relative(want[i], 1e-12));
        MESSAGE(std::string(file) << ": " << got.size() << " parts, density " << got.front() << " to " << got.back() << " kg/m^3");
    }
}

TEST_CASE("mass plausibility: a real part given the CAD default density of 1 kg/mm^3 is named with 1e9 kg/m^3") {
    const std::string data = atest::pmxml_data_dir();
    if (data.empty()) return;
    // ICUB3_WAIST_PITCH (nodeID 468): 0.70323 kg in 251154 mm^3; make the mass equal the volume.
    const std::string text = atest::replace_once(
        atest::read_file(data + "/legs_mechanism_2014/LEGS_MECHANISM.xml"), "<mass>0.70323</mass>", "<mass>251154</mass>");
    atest::TempDir dir;
    const std::string xml = (dir.path / "LEGS_MECHANISM.xml").string();
    atest::write_file(xml, text);
    const auto adapter = FileAdapter::open(xml);
    atest::Translation t(adapter->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    const auto f = findings_of(t, MBX_FINDING_IMPLAUSIBLE_DENSITY);
    REQUIRE(f.size() == 1);
    CHECK(f[0].severity == MBX_SEVERITY_WARNING);
    CHECK(f[0].subject_id == "468");
    CHECK(f[0].subject_name == "ICUB3_WAIST_PITCH");
    CHECK(f[0].code_name == "implausible_density");
    CHECK(f[0].message.find("density 1e+09 kg/m^3") != std::string::npos);
    CHECK(f[0].message.find("default density of 1") != std::string::npos);
}

TEST_CASE("mass plausibility: the volume's own unit is honoured (in^3 in a mm file)") {
    // ARM: 1.5e5 mm^3 written as 9.15356 in^3; 2.5 kg stays 16 667 kg/m^3, plausible.
    const std::string in3 = atest::replace_once(
        atest::replace_once(atest::tiny_pmxml(), "<volume>1.5e+005</volume>", "<volume>9.15356</volume>"),
        "<volumeUnits>\"mm^3\"</volumeUnits>", "<volumeUnits>\"in^3\"</volumeUnits>");
    atest::TempDir dir;
    atest::write_file((dir.path / "tiny.xml").string(), in3);
    {
        const auto adapter = FileAdapter::open((dir.path / "tiny.xml").string());
        // Served in the body's length unit (mm): 9.15356 in^3 = 150 000 mm^3 to 6 digits.
        bool found = false;
        for (const auto& b : adapter->assembly().bodies)
            if (b.id == "12") {
                found = true;
                CHECK(b.volume == mbx_test::relative(1.5e5, 1e-5));
            }
        CHECK(found);
        atest::Translation t(adapter->table(), 0);
        REQUIRE(t.status() == MBX_OK);
        CHECK(t.count(MBX_FINDING_IMPLAUSIBLE_DENSITY) == 0);
    }
    // 9.15356 lbm in 9.15356 in^3: Pro/E's inch default, 1 lbm/in^3 = 27 680 kg/m^3.
    atest::write_file((dir.path / "tiny.xml").string(),
                      atest::replace_once(in3, "<mass>2.5</mass>\n        <massUnits>\"kg\"</massUnits>",
                                          "<mass>9.15356</mass>\n        <massUnits>\"lbm\"</massUnits>"));
    const auto adapter = FileAdapter::open((dir.path / "tiny.xml").string());
    atest::Translation t(adapter->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    const auto f = findings_of(t, MBX_FINDING_IMPLAUSIBLE_DENSITY);
    REQUIRE(f.size() == 1);
    CHECK(f[0].subject_id == "12");
    CHECK(f[0].message.find("density 27679.9 kg/m^3") != std::string::npos);
}

TEST_CASE("late mesh failure: a mesh that passes the probe and breaks at load is a finding in the report") {
    atest::TempDir dir;
    const std::string text = atest::replace_once(atest::tiny_pmxml(), "\"ARM.stl\"", "\"ARM.obj\"");
    const std::string xml = (dir.path / "tiny.xml").string();
    atest::write_file(xml, text);
    atest::write_file((dir.path / "ARM.obj").string(), "v 1 2\nf 1 2 3 4 zz\n");
    const auto adapter = FileAdapter::open(xml);
    REQUIRE(adapter->mesh_files().size() == 1);  // it passed the open-time probe
    atest::Translation t(adapter->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    CHECK(t.count("mesh_file_unreadable") == 0);  // not loaded yet
    CHECK(t.mesh_total() == 0);                   // loads every body's shapes
    REQUIRE(t.count("mesh_file_unreadable") == 1);
    for (const atest::FindingCopy& f : t.findings())
        if (f.code_name == "mesh_file_unreadable") {
            CHECK(f.code == MBX_FINDING_HOST_DIAGNOSTIC);
            CHECK(f.subject_id == "12");
            CHECK(f.file == xml);
            CHECK(f.line == atest::line_of(text, "\"ARM.obj\""));
        }
    atest::TempDir out;
    t.write_report(out.path.string());
    CHECK(atest::read_file((out.path / "report.json").string()).find("\"mesh_file_unreadable\"") != std::string::npos);
    CHECK(adapter->late_diagnostics().size() == 1);
}
}  // namespace MBX_UNITY_ID
