// Inline: a CAD-style assembly file placing part files (in subfolders)
// with Transforms, as Pro/E and stl2vrml write them.
#include <doctest/doctest.h>

#include "vrml_test_support.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using mbx_files::read_vrml;
using mbx_files::VrmlScene;
using vrml_test::signed_volume;
using vrml_test::TempDir;
using vrml_test::vrml;

namespace {

std::string part(const std::string& name, double size) {
    return vrml("WorldInfo { title \"" + name + "\" }\nDEF " + name + "_SHAPE Shape { geometry Box { size " +
                std::to_string(size) + " 1 1 } }\n");
}

}  // namespace

TEST_CASE("an assembly inlines part files from subfolders, relative to each including file") {
    const TempDir dir;
    dir.write("parts/link_a.wrl", part("LINK_A", 2));
    dir.write("parts/Link_B.wrl", part("LINK_B", 3));
    // A sub-assembly one folder down, inlining a part with "../".
    dir.write("sub/arm_a.wrl", vrml(R"(
DEF ARM_OFFSET Transform { translation 0 0 10 children [
  Inline { url "../parts/link_a.wrl" }
] }
)"));
    const std::string assembly = dir.write("asm/top.wrl", vrml(R"(
DEF BASE Transform { translation 1 0 0 children [
  Inline { url "../parts/link_a.wrl" }
] }
DEF ARM Transform { translation 0 2 0 rotation 0 0 1 3.141592653589793 children [
  Inline { url [ "http://example.com/link_b.wrl" "missing.wrl" "file:../parts/link_b.wrl" ] }
] }
DEF SUB Transform { translation 0 0 5 children Inline { url "../sub/arm_a.wrl" } }
)"));
    const VrmlScene scene = read_vrml(assembly);
    // BASE, Inline(a), ARM, Inline(b), SUB, Inline(arm_a), ARM_OFFSET, Inline(a)
    REQUIRE(scene.nodes.size() == 8);
    const std::vector<std::string> kinds = {"Transform", "Inline", "Transform", "Inline",
                                            "Transform", "Inline", "Transform", "Inline"};
    const std::vector<int> parents = {-1, 0, -1, 2, -1, 4, 5, 6};
    for (size_t i = 0; i < kinds.size(); ++i) {
        INFO("node " << i);
        CHECK(scene.nodes[i].kind == kinds[i]);
        CHECK(scene.nodes[i].parent == parents[i]);
    }
    // Inline nodes name the inlined file (found case-insensitively for
    // Link_B.wrl); its meshes keep their local coordinates.
    CHECK(scene.nodes[1].file == dir.path() + "/parts/link_a.wrl");
    CHECK(scene.nodes[1].line == 1);
    CHECK(scene.nodes[3].file == dir.path() + "/parts/Link_B.wrl");
    CHECK(scene.nodes[5].file == dir.path() + "/sub/arm_a.wrl");
    CHECK(scene.nodes[6].file == dir.path() + "/sub/arm_a.wrl");
    CHECK(scene.nodes[7].file == dir.path() + "/parts/link_a.wrl");
    REQUIRE(scene.nodes[3].meshes.size() == 1);
    CHECK(scene.nodes[3].meshes[0].name == "LINK_B_SHAPE");
    CHECK(signed_volume(scene.nodes[3].meshes[0]) == mbx_test::relative(3.0, 1e-6));
    CHECK(scene.nodes[3].world.translation().isApprox(Eigen::Vector3d(0, 2, 0)));
    CHECK(scene.nodes[3].world.linear().isApprox(Eigen::Vector3d(-1, -1, 1).asDiagonal().toDenseMatrix(), 1e-12));
    CHECK(scene.nodes[7].world.translation().isApprox(Eigen::Vector3d(0, 0, 15)));
    // Part files' WorldInfo titles name their Inline node and what is below.
    CHECK(scene.nodes[1].part_name == "LINK_A");
    CHECK(scene.nodes[3].part_name == "LINK_B");
    CHECK(scene.nodes[7].part_name == "LINK_A");
    CHECK(scene.nodes[0].part_name.empty());
    CHECK(scene.nodes[6].part_name.empty());
    CHECK(scene.title.empty());  // the assembly has no WorldInfo of its own
    // The remote url is reported, then the missing one is passed over.
    REQUIRE(scene.warnings.size() == 1);
    CHECK(scene.warnings[0].find("top.wrl:7: Inline url 'http://example.com/link_b.wrl' is remote") !=
          std::string::npos);
}

TEST_CASE("an Inline with no readable file is skipped with a warning") {
    const TempDir dir;
    const std::string path = dir.write("a.wrl", vrml("\nGroup { children Inline { url [ \"nope.wrl\" ] } }\n"));
    const VrmlScene scene = read_vrml(path);
    REQUIRE(scene.nodes.size() == 1);
    REQUIRE(scene.warnings.size() == 1);
    CHECK(scene.warnings[0].find("a.wrl:3: Inline skipped: no readable local file among " + dir.path() + "/nope.wrl") !=
          std::string::npos);
}

TEST_CASE("a part inlined many times is read once and placed each time") {
    const TempDir dir;
    dir.write("bolt.wrl", part("BOLT", 1));
    std::string body;
    for (int i = 0; i < 50; ++i)
        body += "Transform { translation " + std::to_string(i) + " 0 0 children Inline { url \"bolt.wrl\" } }\n";
    const VrmlScene scene = read_vrml(dir.write("many.wrl", vrml(body)));
    REQUIRE(scene.nodes.size() == 100);
    CHECK(scene.nodes[99].world.translation().x() == 49);
    CHECK(scene.nodes[99].meshes.size() == 1);
    CHECK(scene.nodes[99].part_name == "BOLT");
}
}  // namespace MBX_UNITY_ID
