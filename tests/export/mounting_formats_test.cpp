// The description's <mounting> tilt in the exports that carry gravity, each
// read back by its consumer: MuJoCo's compiled gravity for MJCF and the MSL
// World's direction for Modelica, against the rotations written out here
// (gravity turned about world x by tilt_x after world y by tilt_y).
#include <cmath>

#include "modelica_support.h"
#include "mujoco_helpers.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// Rx(a) Ry(b) (0, 0, -1), expanded by hand.
Vec3 turned_down(double a, double b) {
    return Vec3(-std::sin(b), std::cos(b) * std::sin(a), -std::cos(b) * std::cos(a));
}

ExportSettings tilted(double tilt_x, double tilt_y) {
    ExportSettings s;
    s.model_name = "fourbar";
    s.mounting.given = true;
    s.mounting.tilt_x = tilt_x, s.mounting.tilt_y = tilt_y;
    return s;
}

}  // namespace

TEST_CASE("mounting: MuJoCo compiles the MJCF's gravity turned by the description's tilt") {
    auto t = xtest::translate_builtin("fourbar");
    mbx_test::TempDir dir("mounting_mjcf");
    const double a = 0.03, b = -0.05;
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir, tilted(a, b));
    const Vec3 expected = 9.81 * turned_down(a, b);
    for (int k = 0; k < 3; ++k) CHECK(run.model->opt.gravity[k] == mbx_test::within(expected[k], 1e-12, "the turned gravity"));
    // Without a mounting the gravity is MuJoCo's default, straight down.
    mbx_test::TempDir level_dir("mounting_mjcf_level");
    xtest::MuJoCoRun level = xtest::load_mjcf(*t, level_dir, tilted(0, 0));
    CHECK(level.model->opt.gravity[0] == 0);
    CHECK(level.model->opt.gravity[1] == 0);
    CHECK(level.model->opt.gravity[2] == -9.81);
}

TEST_CASE("mounting: the Modelica World's gravity direction is turned by the description's tilt") {
    auto t = xtest::translate_builtin("fourbar");
    const double a = -0.02, b = 0.04;
    const mtest::Package p = mtest::export_package(*t, tilted(a, b));
    mtest::check_package(*t, p);
    const msl::Component* world = p.mechanics.find("world");
    REQUIRE(world);
    const Vec3 n = msl::parse_vector(world->value("n"));
    CHECK((n - turned_down(a, b)).norm() == mbx_test::within(0.0, 1e-12, "the World's n"));
    CHECK(world->value("g").empty());  // the magnitude stays the MSL's 9.81
    CHECK(world->description.find("mounting") != std::string::npos);

    const mtest::Package level = mtest::export_package(*t, tilted(0, 0));
    const msl::Component* level_world = level.mechanics.find("world");
    REQUIRE(level_world);
    CHECK((msl::parse_vector(level_world->value("n")) - Vec3(0, 0, -1)).norm() == 0);
}

}  // namespace MBX_UNITY_ID
