// `mbx geometry <file.step>`: each placed solid's volume, centroid and
// closure printed, meshes written as files, and bad input refused clearly.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "cli_support.h"
#include "tests/common/near.h"
#include "tests/common/step_solids.h"

namespace MBX_UNITY_ID {

namespace {

// The number printed after `key` in `text`.
double number_after(const std::string& text, const std::string& key) {
    const size_t at = text.find(key);
    if (at == std::string::npos) return NAN;
    return std::strtod(text.c_str() + at + key.size(), nullptr);
}

}  // namespace

TEST_CASE("cli: mbx geometry prints each solid of a STEP file and writes its meshes") {
    atest::TempDir dir;
    mbx_test::StepSolidWriter writer(mbx_test::StepUnit::Inch);
    writer.box(Eigen::Vector3d(0.01, 0.02, 0.03), Eigen::Vector3d(0.05, 0.04, 0.035));
    writer.sphere(0.01, Eigen::Vector3d(0.2, 0, 0));
    atest::write_file(dir.file("parts.step"), writer.file());
    const atest::CliRun r = atest::run_cli(dir, "geometry '" + dir.file("parts.step") + "' -o '" + dir.file("out") + "'");
    CAPTURE(r.out);
    CAPTURE(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("2 solids, 2 placed") != std::string::npos);
    // The box exactly (planes only), in cubic metres whatever the file's unit.
    CHECK(number_after(r.out, "volume ") == mbx_test::relative(0.04 * 0.02 * 0.005, 1e-9));
    const size_t second = r.out.find("volume ", r.out.find("volume ") + 1);
    REQUIRE(second != std::string::npos);
    CHECK(number_after(r.out.substr(second), "volume ") == mbx_test::relative(4.0 / 3 * M_PI * 1e-6, 1e-4));
    CHECK(number_after(r.out.substr(second), "centroid ") == mbx_test::within(0.2, 1e-6, "1e-4 of the radius"));
    CHECK(r.out.find("not closed") == std::string::npos);
    // One binary STL per placed solid: the box's is its twelve triangles.
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.file("out"))) {
        ++files;
        CHECK(e.path().extension() == ".stl");
        if (std::filesystem::file_size(e.path()) == 84 + 50 * 12) continue;
        CHECK(std::filesystem::file_size(e.path()) > 84 + 50 * 1000);  // the sphere
    }
    CHECK(files == 2);
}

TEST_CASE("cli: mbx geometry refuses what is not STEP and options out of range") {
    atest::TempDir dir;
    atest::write_file(dir.file("notes.step"), "solid cube\nendsolid\n");
    atest::CliRun r = atest::run_cli(dir, "geometry '" + dir.file("notes.step") + "'");
    CHECK(r.code == 1);
    CHECK(r.err.find("notes.step:1") != std::string::npos);
    r = atest::run_cli(dir, "geometry '" + dir.file("notes.step") + "' --angle 0");
    CHECK(r.code == 2);
    r = atest::run_cli(dir, "geometry '" + dir.file("notes.step") + "' --chord nan");
    CHECK(r.code == 2);
    r = atest::run_cli(dir, "geometry '" + dir.file("notes.step") + "' --format dxf");
    CHECK(r.code == 2);
    atest::write_file(dir.file("empty.step"), mbx_test::StepSolidWriter().file());
    r = atest::run_cli(dir, "geometry '" + dir.file("empty.step") + "' -o '" + dir.file("out") + "'");
    CHECK(r.code == 1);
    CHECK(r.err.find("no solid") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("out")));
}

}  // namespace MBX_UNITY_ID
