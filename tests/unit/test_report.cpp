// The translation report: JSON fields, text layout, determinism, scale.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "core/report/report.h"
#include "../common/file_text.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using nlohmann::json;

namespace {

// Ground + crank + slider; a revolute and a prismatic tree joint, and a cut
// revolute closing the loop back to ground. A helper part is dropped and
// a pin is welded into the crank. Findings: a warning first, then an error.
mbx::Mechanism four_part_mechanism() {
    mbx::Mechanism m;
    m.assembly.name = "Slider \"crank\"";
    m.assembly.source = "C:\\cad\\slider.asm";
    auto part = [&](const char* id, const char* name, uint32_t flags, double mass) {
        mbx::Part p;
        p.id = id;
        p.name = name;
        p.flags = flags;
        p.mass = mass;
        m.assembly.parts.push_back(p);
    };
    part("p-base", "Base", MBX_BODY_GROUND, 10);
    part("p-crank", "Crank", 0, 2);
    part("p-pin", "Pin", 0, 0.25);
    part("p-slider", "Slider", 0, 1);
    part("p-root", "RootPart", MBX_BODY_HELPER | MBX_BODY_GROUND, 0);
    m.part_body = {0, 1, 1, 2, -1};

    mbx::Constraint hinge, slide, closure;
    hinge.id = "c-hinge";
    hinge.name = "Hinge";
    slide.id = "c-slide";
    slide.name = "Slide";
    closure.id = "c-close";
    closure.name = "Closure";
    m.assembly.constraints = {hinge, slide, closure};

    mbx::RigidBody ground;
    ground.kind = MBX_RIGID_BODY_GROUND;
    ground.id = "p-base";
    ground.name = "Base";
    ground.parts = {0};
    ground.mass = 10;
    mbx::RigidBody crank;
    crank.id = "p-crank";
    crank.name = "Crank";
    crank.parts = {1, 2};
    crank.mass = 2.25;
    crank.com = mbx::Vec3(0.1, 0, 0);
    crank.inertia << 1, 2, 3, 2, 4, 5, 3, 5, 6;
    crank.pose.position = mbx::Vec3(0.5, -0.25, 1e-300);
    crank.pose.rotation << 0, -1, 0, 1, 0, 0, 0, 0, 1;
    crank.parent_joint = 0;
    crank.depth = 1;
    mbx::RigidBody slider;
    slider.id = "p-slider";
    slider.name = "Slider";
    slider.parts = {3};
    slider.mass = 1;
    slider.parent_joint = 1;
    slider.depth = 2;
    m.bodies = {ground, crank, slider};

    mbx::Joint j0;
    j0.type = MBX_PRIMITIVE_REVOLUTE;
    j0.name = "Hinge";
    j0.constraint = 0;
    j0.parent = 0;
    j0.child = 1;
    j0.axis = mbx::Vec3(0, 0, 1);
    j0.has_limits = true;
    j0.lower = -1.5;
    j0.upper = 1.5;
    mbx::Joint j1;
    j1.type = MBX_PRIMITIVE_PRISMATIC;
    j1.name = "Slide";
    j1.constraint = 1;
    j1.parent = 1;
    j1.child = 2;
    j1.axis = mbx::Vec3(1, 0, 0);
    j1.frame.position = mbx::Vec3(0.5, 0, 0);
    mbx::Joint j2;
    j2.type = MBX_PRIMITIVE_REVOLUTE;
    j2.name = "Closure";
    j2.constraint = 2;
    j2.parent = 2;
    j2.child = 0;
    j2.cut = true;
    j2.reversed = true;
    j2.loop = 0;
    m.joints = {j0, j1, j2};

    mbx::Loop loop;
    loop.cut_joint = 2;
    loop.joints = {0, 1, 2};
    loop.signs = {1, 1, -1};
    loop.dof = 1;
    loop.gruebler_dof = 1;
    loop.planar = true;
    loop.planar_normal = mbx::Vec3(0, 0, 1);
    m.loops = {loop};

    m.weld_count = 1;
    m.dof = 1;
    m.gruebler_dof = 1;
    m.length_tolerance = 1e-6;
    m.add(MBX_SEVERITY_WARNING, MBX_FINDING_HELPER_BODY_DROPPED, mbx::Subject::body("p-root", "RootPart"),
          "Helper part 'RootPart' has no mass and was dropped.");
    m.add(MBX_SEVERITY_ERROR, MBX_FINDING_MOBILITY_MISMATCH, mbx::Subject::loop("0"),
          "Loop 0 has mobility 1 but Gruebler predicts 1.");
    return m;
}

// A chain of n bodies hanging from ground by revolutes, with one cut joint.
mbx::Mechanism chain(std::size_t n) {
    mbx::Mechanism m;
    m.assembly.name = "chain";
    m.bodies.resize(n + 1);
    m.bodies[0].kind = MBX_RIGID_BODY_GROUND;
    m.bodies[0].name = "ground";
    for (std::size_t i = 1; i <= n; ++i) {
        mbx::RigidBody& b = m.bodies[i];
        b.id = "b" + std::to_string(i);
        b.name = "Link " + std::to_string(i);
        b.mass = 1.0 / static_cast<double>(i);
        b.inertia = mbx::Mat3::Identity() * 0.1;
        b.pose.position = mbx::Vec3(0.1 * static_cast<double>(i), 1.0 / 3.0, 0);
        b.parent_joint = static_cast<int>(i - 1);
        b.depth = static_cast<int>(i);
        mbx::Joint j;
        j.name = "J" + std::to_string(i);
        j.parent = static_cast<int>(i - 1);
        j.child = static_cast<int>(i);
        m.joints.push_back(j);
    }
    mbx::Joint cut;
    cut.name = "Close";
    cut.parent = static_cast<int>(n);
    cut.child = 0;
    cut.cut = true;
    cut.loop = 0;
    m.joints.push_back(cut);
    mbx::Loop loop;
    loop.cut_joint = static_cast<int>(n);
    m.loops.push_back(loop);
    return m;
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

}  // namespace

TEST_CASE("report json: header, model and summary") {
    const json j = json::parse(mbx::report_json(four_part_mechanism()));
    CHECK(j["mbx_version"] == MBX_VERSION_STRING);
    CHECK(j["model"]["name"] == "Slider \"crank\"");
    CHECK(j["model"]["source"] == "C:\\cad\\slider.asm");
    const json& s = j["summary"];
    CHECK(s["parts"] == 5);
    CHECK(s["rigid_bodies"] == 2);
    CHECK(s["joint_nodes"] == 0);
    CHECK(s["joints"] == json{{"revolute", 2}, {"prismatic", 1}, {"spherical", 0}, {"total", 3}});
    CHECK(s["welds_merged"] == 1);
    CHECK(s["cut_joints"] == 1);
    CHECK(s["loops"] == 1);
    CHECK(s["planar_loops"] == 1);
    CHECK(s["collapsed_weld_loops"] == 0);
    CHECK(s["floating_bodies"] == 0);
    CHECK(s["dof"] == 1);
    CHECK(s["gruebler_dof"] == 1);
    CHECK(s["redundant_constraints"] == 0);
    CHECK(s["warnings"] == 1);
    CHECK(s["errors"] == 1);
    CHECK(s["length_tolerance_m"].get<double>() == 1e-6);
    // Key order is the order of writing, as documented (json sorts its keys,
    // so look at the text).
    const std::string text = mbx::report_json(four_part_mechanism());
    CHECK(text.find("\"mbx_version\"") < text.find("\"model\""));
    CHECK(text.find("\"bodies\"") < text.find("\"joints\": ["));
    CHECK(text.find("\"loops\": [") < text.find("\"findings\""));
    CHECK(text.back() == '\n');
}

TEST_CASE("report json: parts and bodies") {
    const json j = json::parse(mbx::report_json(four_part_mechanism()));
    const json& parts = j["parts"];
    REQUIRE(parts.size() == 5);
    CHECK(parts[0] == json{{"id", "p-base"}, {"name", "Base"}, {"flags", {"ground"}}, {"mass", 10}, {"rigid_body", 0},
                           {"cad_volume_m3", nullptr}, {"cad_density_kg_m3", nullptr}, {"shape_check", nullptr}});
    CHECK(parts[2]["rigid_body"] == 1);
    CHECK(parts[4]["flags"] == json{"ground", "helper"});
    CHECK(parts[4]["rigid_body"].is_null());
    CHECK(parts[1]["flags"] == json::array());

    // With a mesh check, the part carries its numbers in report units.
    mbx::Mechanism checked = four_part_mechanism();
    checked.shape_checks.resize(checked.assembly.parts.size());
    checked.shape_checks[2] = {true, 2e-6, 0.0031, 2700, 0.001};
    const json c = json::parse(mbx::report_json(checked))["parts"][2]["shape_check"];
    CHECK(c["centroid_mismatch_mm"].get<double>() == mbx_test::relative(3.1, 1e-6));
    CHECK(c["tolerance_mm"].get<double>() == mbx_test::relative(1.0, 1e-6));
    CHECK(c["mesh_volume_m3"].get<double>() == mbx_test::relative(2e-6, 1e-6));
    CHECK(c["density_kg_m3"].get<double>() == mbx_test::relative(2700, 1e-6));
    CHECK(mbx::report_text(checked).find("3.1 mm (above 1 mm)") != std::string::npos);

    const json& bodies = j["bodies"];
    REQUIRE(bodies.size() == 3);
    CHECK(bodies[0]["kind"] == "ground");
    CHECK(bodies[0]["parent_joint"].is_null());
    const json& crank = bodies[1];
    CHECK(crank["index"] == 1);
    CHECK(crank["kind"] == "dynamic");
    CHECK(crank["id"] == "p-crank");
    CHECK(crank["name"] == "Crank");
    CHECK(crank["parts"] == json{"p-crank", "p-pin"});
    CHECK(crank["mass"].get<double>() == 2.25);
    CHECK(crank["com"] == json{0.1, 0, 0});
    CHECK(crank["inertia"] == json{1, 2, 3, 2, 4, 5, 3, 5, 6});
    CHECK(crank["position"][2].get<double>() == 1e-300);
    // Row-major: R(0,1) = -1 comes second, R(1,0) = 1 fourth.
    CHECK(crank["rotation"] == json{0, -1, 0, 1, 0, 0, 0, 0, 1});
    CHECK(crank["parent_joint"] == 0);
    CHECK(crank["depth"] == 1);
}

TEST_CASE("report json: joints, tree, loops and findings") {
    const json j = json::parse(mbx::report_json(four_part_mechanism()));
    const json& joints = j["joints"];
    REQUIRE(joints.size() == 3);
    CHECK(joints[0]["type"] == "revolute");
    CHECK(joints[0]["constraint_id"] == "c-hinge");
    CHECK(joints[0]["limits"] == json{{"lower", -1.5}, {"upper", 1.5}});
    CHECK(joints[0]["loop"].is_null());
    CHECK(joints[0]["cut"] == false);
    CHECK(joints[1]["type"] == "prismatic");
    CHECK(joints[1]["axis"] == json{1, 0, 0});
    CHECK(joints[1]["position"] == json{0.5, 0, 0});
    CHECK(joints[1]["limits"].is_null());
    const json& cut = joints[2];
    CHECK(cut["index"] == 2);
    CHECK(cut["name"] == "Closure");
    CHECK(cut["primitive_index"] == 0);
    CHECK(cut["parent"] == 2);
    CHECK(cut["child"] == 0);
    CHECK(cut["cut"] == true);
    CHECK(cut["reversed"] == true);
    CHECK(cut["loop"] == 0);

    // Cut joints are not tree edges.
    CHECK(j["tree"] == json{json{1}, json{2}, json::array()});

    REQUIRE(j["loops"].size() == 1);
    const json& loop = j["loops"][0];
    CHECK(loop["cut_joint"] == 2);
    CHECK(loop["joints"] == json{0, 1, 2});
    CHECK(loop["signs"] == json{1, 1, -1});
    CHECK(loop["dof"] == 1);
    CHECK(loop["planar"] == true);
    CHECK(loop["planar_normal"] == json{0, 0, 1});

    REQUIRE(j["findings"].size() == 2);
    const json& f = j["findings"][0];
    CHECK(f["severity"] == "warning");
    CHECK(f["code"] == "helper_body_dropped");
    CHECK(f["subject"] == json{{"kind", "body"}, {"id", "p-root"}, {"name", "RootPart"}});
    CHECK(f["message"] == "Helper part 'RootPart' has no mass and was dropped.");
    CHECK(j["findings"][1]["severity"] == "error");
    CHECK(j["findings"][1]["subject"]["kind"] == "loop");
}

TEST_CASE("report json: a non-planar loop has a null normal, NaN masses become null") {
    mbx::Mechanism m = four_part_mechanism();
    m.loops[0].planar = false;
    m.bodies[2].mass = std::nan("");
    const json j = json::parse(mbx::report_json(m));
    CHECK(j["loops"][0]["planar_normal"].is_null());
    CHECK(j["bodies"][2]["mass"].is_null());
}

TEST_CASE("report json: an empty mechanism is still a valid report") {
    const json j = json::parse(mbx::report_json(mbx::Mechanism{}));
    CHECK(j["bodies"] == json::array());
    CHECK(j["summary"]["joints"]["total"] == 0);
    CHECK_FALSE(mbx::report_text(mbx::Mechanism{}).empty());
}

TEST_CASE("report text: outline, cut marker, findings error-first") {
    const std::string text = mbx::report_text(four_part_mechanism());
    CAPTURE(text);
    CHECK(text.find("Slider \"crank\"") != std::string::npos);
    CHECK(text.find("    Crank [2.25 kg] <- revolute 'Hinge' axis (0, 0, 1) limits [-1.5, 1.5]\n") !=
          std::string::npos);
    CHECK(text.find("      Slider [1 kg] <- prismatic 'Slide' axis (1, 0, 0)\n") != std::string::npos);
    CHECK(text.find("        -> Base [ground] <- revolute 'Closure' axis (0, 0, 1) (cut, closes loop 0)\n") !=
          std::string::npos);
    CHECK(text.find("loop 0: cut joint 'Closure', 3 joints, DoF 1 (Gruebler 1), redundant 0, planar") !=
          std::string::npos);
    const auto error = text.find("error mobility_mismatch loop (0): Loop 0 has mobility 1");
    const auto warning = text.find("warning helper_body_dropped body 'RootPart' (p-root): Helper part");
    REQUIRE(error != std::string::npos);
    REQUIRE(warning != std::string::npos);
    CHECK(error < warning);
    for (const std::string& line : lines_of(text)) CHECK(line.size() < 120);
}

TEST_CASE("report text: long and hostile strings keep lines short and intact") {
    mbx::Mechanism m = four_part_mechanism();
    m.bodies[1].name = std::string(300, 'x') + "\n\xFF";
    m.findings[0].message = "word " + std::string(500, 'w') + " and then a rather long tail of ordinary words that "
                            "needs wrapping because it goes on and on and on and on and on and on and on";
    const std::string text = mbx::report_text(m);
    for (const std::string& line : lines_of(text)) CHECK(line.size() < 120);
    CHECK(text.find('\xFF') == std::string::npos);
    CHECK(text.find("goes on and on") != std::string::npos);  // wrapped, not cut
}

TEST_CASE("report text: deep or long tree lines keep their cut marker") {
    mbx::Mechanism m = chain(60);
    m.bodies[0].name = std::string(200, 'g');
    const std::string text = mbx::report_text(m);
    CHECK(text.find("[depth 61] -> ggg") != std::string::npos);
    CHECK(text.find("... (cut, closes loop 0)\n") != std::string::npos);
    for (const std::string& line : lines_of(text)) CHECK(line.size() < 120);
}

TEST_CASE("report: output is deterministic") {
    const mbx::Mechanism m = four_part_mechanism();
    CHECK(mbx::report_json(m) == mbx::report_json(four_part_mechanism()));
    CHECK(mbx::report_text(m) == mbx::report_text(four_part_mechanism()));
}

TEST_CASE("report text: huge trees are cut at 2000 lines") {
    const mbx::Mechanism m = chain(3000);
    const std::string text = mbx::report_text(m);
    // 3001 bodies + 1 cut line = 3002 tree lines; 2000 are shown.
    CHECK(text.find("  ... 1002 more (the full tree is in report.json)\n") != std::string::npos);
    CHECK(text.find("Link 1999 ") != std::string::npos);
    CHECK(text.find("Link 2000 ") == std::string::npos);
    CHECK(text.find("[depth 1999] Link 1999") != std::string::npos);
    const auto lines = lines_of(text);
    CHECK(lines.size() < 2100);
    for (const std::string& line : lines) CHECK(line.size() < 120);
    CHECK(text.find("Findings (0)\n  none") != std::string::npos);
}

TEST_CASE("report: floating roots are shown after ground") {
    mbx::Mechanism m = chain(3);
    m.joints[1].parent = -1;  // body 2 now hangs from nothing
    m.bodies[2].parent_joint = -1;
    const std::string text = mbx::report_text(m);
    CHECK(text.find("Link 2 [0.5 kg] (floating, not attached to ground)") != std::string::npos);
    CHECK(text.find("    Link 3 [0.333333 kg] <- revolute 'J3'") != std::string::npos);
}

TEST_CASE("report: a long chain is complete and its size grows linearly") {
    // Speed is measured by bench_translate; here: nothing is dropped or
    // duplicated at scale, and bytes per body stay constant.
    const mbx::Mechanism small = chain(2000), large = chain(20000);
    const std::string js = mbx::report_json(small), jl = mbx::report_json(large);
    const double per_body_small = double(js.size()) / 2000, per_body_large = double(jl.size()) / 20000;
    CHECK(per_body_large < 1.1 * per_body_small);
    const json parsed = json::parse(jl);
    CHECK(parsed["bodies"].size() == 20001);
    CHECK(parsed["tree"][19999] == json{20000});
    CHECK(mbx::report_text(large).find("... ") != std::string::npos);
}

TEST_CASE("report: write_report writes both files into a new directory") {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("mbx_report_test_" + std::to_string(::getpid())) / "nested" / "out";
    std::filesystem::remove_all(dir.parent_path().parent_path());
    const mbx::Mechanism m = four_part_mechanism();
    mbx::write_report(m, dir.string());
    CHECK(mbx_test::read_file(dir / "report.json") == mbx::report_json(m));
    CHECK(mbx_test::read_file(dir / "report.txt") == mbx::report_text(m));
    std::size_t files = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
    CHECK(files == 2);
    std::filesystem::remove_all(dir.parent_path().parent_path());
}

TEST_CASE("report text: the spread of CAD densities, only when parts have a CAD volume") {
    mbx::Mechanism m = four_part_mechanism();
    CHECK(mbx::report_text(m).find("CAD densities") == std::string::npos);
    m.assembly.parts[1].volume = 2 / 2700.0;   // Crank: aluminium
    m.assembly.parts[2].volume = 0.25 / 1e9;   // Pin: the 1 kg/mm^3 default
    m.assembly.parts[0].volume = 1;            // ground: not a moving part, not counted
    const std::string text = mbx::report_text(m);
    CHECK(text.find("CAD densities (2 parts with a CAD volume; 50 to 25000 kg/m^3 accepted): lightest 'Crank' 2700 "
                    "kg/m^3, densest 'Pin'\n    1e+09 kg/m^3, 1 outside\n") != std::string::npos);
}
}  // namespace MBX_UNITY_ID
