// `mbx translate` with XML inputs: the exit codes, the error line, and that a
// failure writes nothing.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "cli_support.h"
#include "stl_text.h"
#include "tiny_pmxml.h"

namespace MBX_UNITY_ID {

namespace {

using Run = atest::CliRun;
using atest::run_cli;

}  // namespace

TEST_CASE("cli: an XML input translates with the mass check on by default") {
    atest::TempDir dir;
    atest::write_file(dir.file("tiny.xml"), atest::tiny_pmxml());
    const Eigen::Vector3d com_cs1 = atest::tiny_arm_rotation().transpose() * Eigen::Vector3d(50, 20, 10);
    atest::write_file(dir.file("arm.stl"), atest::stl_ascii(atest::box_triangles(com_cs1, Eigen::Vector3d(30, 12, 8))));

    const Run r = run_cli(dir, "translate '" + dir.file("tiny.xml") + "' -o '" + dir.file("out") + "'");
    CHECK(r.code == 0);
    CHECK(r.out.find("4 parts") != std::string::npos);
    const std::string json = atest::read_file(dir.file("out/report.json"));
    CHECK(json.find("\"centroid_mismatch_mm\"") != std::string::npos);
    CHECK(json.find("mesh_file_missing") != std::string::npos);

    const Run off =
        run_cli(dir, "translate '" + dir.file("tiny.xml") + "' --no-mass-check -o '" + dir.file("out2") + "'");
    CHECK(off.code == 0);
    CHECK(atest::read_file(dir.file("out2/report.json")).find("\"centroid_mismatch_mm\"") == std::string::npos);
}

TEST_CASE("cli: a broken XML file is 'mbx: file:line: message', exit 1, nothing written") {
    atest::TempDir dir;
    const std::string text = atest::replace_once(atest::tiny_pmxml(), "<mass>2.5</mass>", "<mass>2.5kg</mass>");
    atest::write_file(dir.file("bad.xml"), text);
    const Run r = run_cli(dir, "translate '" + dir.file("bad.xml") + "' -o '" + dir.file("out") + "'");
    CHECK(r.code == 1);
    const std::string expected =
        "mbx: " + dir.file("bad.xml") + ":" + std::to_string(atest::line_of(text, "2.5kg")) + ": body 'ARM': ";
    CHECK(r.err.rfind(expected, 0) == 0);
    CHECK_FALSE(std::filesystem::exists(dir.file("out")));

    atest::write_file(dir.file("good.xml"), atest::tiny_pmxml());
    const Run w = run_cli(dir, "translate '" + dir.file("good.xml") + "' --shapes '" + dir.file("no.wrl") + "' -o '" +
                                   dir.file("out") + "'");
    CHECK(w.code == 1);
    CHECK(w.err.rfind("mbx: " + dir.file("no.wrl") + ":", 0) == 0);
    CHECK_FALSE(std::filesystem::exists(dir.file("out")));
}

TEST_CASE("cli: usage mentions the file options, they need an XML input") {
    atest::TempDir dir;
    const Run help = run_cli(dir, "translate --help");
    CHECK(help.code == 0);
    for (const char* option : {"--shapes", "--mesh-dir", "--no-mass-check", ".xml"}) {
        CAPTURE(option);
        CHECK(help.out.find(option) != std::string::npos);
    }
    const Run misuse = run_cli(dir, "translate fourbar --shapes x.wrl -o '" + dir.file("out") + "'");
    CHECK(misuse.code == 2);
    const Run builtin = run_cli(dir, "translate fourbar -o '" + dir.file("out") + "'");
    CHECK(builtin.code == 0);
}

TEST_CASE("cli: --format picks the exports, default all, none writes only the report") {
    atest::TempDir dir;
    atest::write_file(dir.file("tiny.xml"), atest::tiny_pmxml());
    namespace fs = std::filesystem;
    const std::string xml = "'" + dir.file("tiny.xml") + "'";

    const Run all = run_cli(dir, "translate " + xml + " -o '" + dir.file("all") + "'");
    REQUIRE(all.code == 0);
    CHECK(fs::exists(dir.file("all/modelica/Tiny/package.mo")));
    CHECK(fs::exists(dir.file("all/mjcf/tiny.xml")));
    CHECK(fs::exists(dir.file("all/urdf/tiny.urdf")));
    CHECK(all.out.find("mjcf: ") != std::string::npos);

    const Run some = run_cli(dir, "translate " + xml + " --format mjcf,urdf --name Arm -o '" + dir.file("some") + "'");
    REQUIRE(some.code == 0);
    CHECK(fs::exists(dir.file("some/mjcf/Arm.xml")));
    CHECK(fs::exists(dir.file("some/urdf/Arm.urdf")));
    CHECK_FALSE(fs::exists(dir.file("some/modelica")));

    const Run none = run_cli(dir, "translate " + xml + " --format none -o '" + dir.file("none") + "'");
    REQUIRE(none.code == 0);
    size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir.file("none"))) entries += e.path().filename() != "";
    CHECK(entries == 2);  // report.json, report.txt

    const Run bad = run_cli(dir, "translate " + xml + " --format step -o '" + dir.file("bad") + "'");
    CHECK(bad.code == 2);
    CHECK(bad.err.find("--format") != std::string::npos);
    CHECK_FALSE(fs::exists(dir.file("bad")));
    const Run bad_mesh = run_cli(dir, "translate " + xml + " --mesh-format ply -o '" + dir.file("bad") + "'");
    CHECK(bad_mesh.code == 2);
}

TEST_CASE("cli: mbx library shows derived motor constants, and names file and line of a bad entry") {
    atest::TempDir dir;
    const Run good = run_cli(dir, std::string("library '") + MBX_SAMPLES_DIR + "/library/mbx_object_library.xml'");
    CHECK(good.code == 0);
    CHECK(good.out.find("KRS-784ICS") != std::string::npos);
    CHECK(good.out.find("k 0.008226 N m/A") != std::string::npos);  // (8 - 0.78 * 1.2) / (8200 rpm)
    atest::write_file(dir.file("bad.xml"),
                      "<object_library>\n<object_folder name=\"E\">\n<object_class name=\"C\">\n"
                      "<parameter name=\"x\" unit=\"furlong\"/>\n</object_class>\n</object_folder>\n</object_library>\n");
    const Run bad = run_cli(dir, "library '" + dir.file("bad.xml") + "'");
    CHECK(bad.code == 1);
    CHECK(bad.err.find(dir.file("bad.xml") + ":4: C: parameter 'x' has unknown unit 'furlong'") != std::string::npos);
    CHECK(run_cli(dir, "library").code == 2);
}

TEST_CASE("cli: --drives exports the arm with its drives in every format, a bad drive file writes nothing") {
    atest::TempDir dir;
    const std::string arm = std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm.xml";
    const std::string drives = std::string(MBX_SAMPLES_DIR) + "/mechatronics/five_axis_arm_drives.xml";
    const Run r = run_cli(dir, "translate '" + arm + "' --drives '" + drives + "' --name arm -o '" + dir.file("out") + "'");
    REQUIRE(r.code == 0);
    CHECK(r.out.find("drive waist: RE40-class 150 W 48 V + Strain-wave 100:1, ratio 100") != std::string::npos);
    CHECK(r.out.find("drive wrist_roll: KRS-784ICS, ratio 251") != std::string::npos);
    const std::string mjcf = atest::read_file(dir.file("out/mjcf/arm.xml"));
    size_t actuators = 0;
    for (size_t at = mjcf.find("<general "); at != std::string::npos; at = mjcf.find("<general ", at + 1)) ++actuators;
    CHECK(actuators == 5);
    const std::string urdf = atest::read_file(dir.file("out/urdf/arm.urdf"));
    size_t transmissions = 0;
    for (size_t at = urdf.find("<transmission "); at != std::string::npos; at = urdf.find("<transmission ", at + 1))
        ++transmissions;
    CHECK(transmissions == 5);
    CHECK(std::filesystem::exists(dir.file("out/modelica/Arm/Mechatronic.mo")));
    CHECK(atest::read_file(dir.file("out/report.json")).find("\"drives\"") != std::string::npos);

    // A drive file with a typo: file, line and drive on stderr, exit 1, no output.
    atest::write_file(dir.file("bad.xml"),
                      "<mechatronics>\n<drive name=\"waist\" constraint=\"40:-:41\" motor=\"X\">\n"
                      "<controller kp=\"1\" kdd=\"2\"/>\n</drive>\n</mechatronics>\n");
    const Run bad = run_cli(dir, "translate '" + arm + "' --drives '" + dir.file("bad.xml") + "' -o '" + dir.file("out2") + "'");
    CHECK(bad.code == 1);
    CHECK(bad.err.find(dir.file("bad.xml") + ":3: waist: unknown attribute 'kdd' on <controller>") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("out2")));

    // A drive that does not fit the mechanism: the constraint id names the problem.
    atest::write_file(dir.file("misfit.xml"),
                      "<mechatronics>\n<library file=\"" + std::string(MBX_SAMPLES_DIR) +
                          "/library/mbx_object_library.xml\"/>\n"
                          "<drive constraint=\"99:-:98\" motor=\"628F99AAAA7444D5A2A36A6FA1175594\">\n"
                          "<controller kp=\"1\"/>\n</drive>\n</mechatronics>\n");
    const Run misfit =
        run_cli(dir, "translate '" + arm + "' --drives '" + dir.file("misfit.xml") + "' -o '" + dir.file("out3") + "'");
    CHECK(misfit.code == 1);
    CHECK(misfit.err.find(dir.file("misfit.xml") + ":3: 99:-:98: no constraint with id '99:-:98'") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("out3/report.json")));
}
}  // namespace MBX_UNITY_ID
