// Hierarchy and transforms: world matrices, grouping nodes, Switch/LOD,
// DEF/USE of whole nodes, lexical details.
#include <cmath>

#include <doctest/doctest.h>

#include "vrml_test_support.h"

namespace MBX_UNITY_ID {

using mbx_files::read_vrml;
using mbx_files::read_vrml_text;
using mbx_files::VrmlScene;
using vrml_test::find_node;
using vrml_test::read_written;
using vrml_test::TempDir;
using vrml_test::vrml;

namespace {

void check_matrix(const Eigen::Affine3d& got, const Eigen::Matrix4d& want) {
    INFO("got\n" << got.matrix() << "\nwant\n" << want);
    CHECK((got.matrix() - want).cwiseAbs().maxCoeff() < 1e-12);
}

}  // namespace

TEST_CASE("nested Transforms accumulate T*C*R*S*-C into world") {
    // Outer: translate (1,2,3), rotate 90 deg about z. Inner: translate
    // (0,0,1), centre (1,0,0), rotate 90 deg about x, scale 2. By hand:
    // inner = [2*Rx | (-1,0,1)], world = outer*inner = [2*Rz*Rx | (1,1,4)].
    const TempDir dir;
    const std::string path = dir.write("t.wrl", vrml(R"(
DEF OUTER Transform {
  translation 1 2 3
  rotation 0 0 1 1.5707963267948966
  children [
    DEF INNER Transform {
      translation 0 0 1
      center 1 0 0
      rotation 1 0 0 1.5707963267948966
      scale 2 2 2
      children [ Shape { geometry Box { } } ]
    }
  ]
}
)"));
    const VrmlScene scene = read_vrml(path);
    REQUIRE(scene.nodes.size() == 2);
    CHECK(scene.nodes[0].name == "OUTER");
    CHECK(scene.nodes[0].kind == "Transform");
    CHECK(scene.nodes[0].parent == -1);
    CHECK(scene.nodes[0].line == 3);
    CHECK(scene.nodes[0].file == path);
    CHECK(scene.nodes[1].name == "INNER");
    CHECK(scene.nodes[1].parent == 0);
    CHECK(scene.nodes[1].line == 7);
    Eigen::Matrix4d outer;
    outer << 0, -1, 0, 1,  //
        1, 0, 0, 2,        //
        0, 0, 1, 3,        //
        0, 0, 0, 1;
    check_matrix(scene.nodes[0].world, outer);
    Eigen::Matrix4d world;
    world << 0, 0, 2, 1,  //
        2, 0, 0, 1,       //
        0, 2, 0, 4,       //
        0, 0, 0, 1;
    check_matrix(scene.nodes[1].world, world);
    // The mesh stays in the inner node's coordinates.
    REQUIRE(scene.nodes[1].meshes.size() == 1);
    CHECK(scene.nodes[0].meshes.empty());
    CHECK(scene.nodes[1].meshes[0].vertices[0] == -1.0);
}

TEST_CASE("scaleOrientation turns the scale axes") {
    // Scale 2 along x, with the scale frame turned 90 deg about z: the
    // stretch lands on y. SR*S*SR^-1 = diag(1,2,1).
    const VrmlScene scene = read_written(vrml(R"(
Transform { scale 2 1 1 scaleOrientation 0 0 1 1.5707963267948966 center 0 1 0 }
)"),
                                         "so.wrl");
    REQUIRE(scene.nodes.size() == 1);
    // With centre (0,1,0): p -> C + diag(1,2,1)(p - C), translation (0,-1,0).
    Eigen::Matrix4d want;
    want << 1, 0, 0, 0,  //
        0, 2, 0, -1,     //
        0, 0, 1, 0,      //
        0, 0, 0, 1;
    check_matrix(scene.nodes[0].world, want);
}

TEST_CASE("grouping nodes each give a node, parents first, meshes on the nearest") {
    const VrmlScene scene = read_written(vrml(R"(
DEF G Group { children [
  DEF A Anchor { url "x.html" children [ DEF B Billboard { children [
    DEF C Collision { children [ Shape { geometry Sphere { radius 0.5 } } ] } ] } ] }
  Viewpoint { position 0 0 10 }
  DirectionalLight { direction 0 -1 0 }
  NavigationInfo { type [ "EXAMINE" "ANY" ] }
  Background { skyColor [ 0 0 0, 0.1 0.1 0.1 ] }
  Shape { appearance Appearance { material Material { diffuseColor 1 0 0 } texture ImageTexture { url "t.png" } }
          geometry Cone { } }
] }
)"),
                                         "g.wrl");
    REQUIRE(scene.nodes.size() == 4);
    CHECK(scene.nodes[0].kind == "Group");
    CHECK(scene.nodes[1].kind == "Anchor");
    CHECK(scene.nodes[2].kind == "Billboard");
    CHECK(scene.nodes[3].kind == "Collision");
    for (int i = 1; i < 4; ++i) CHECK(scene.nodes[static_cast<size_t>(i)].parent == i - 1);
    CHECK(scene.nodes[0].meshes.size() == 1);  // the Cone
    CHECK(scene.nodes[3].meshes.size() == 1);  // the Sphere
    CHECK(scene.warnings.empty());
}

TEST_CASE("Switch keeps only whichChoice, LOD only its first level") {
    const VrmlScene scene = read_written(vrml(R"(
Switch { whichChoice 1 choice [ DEF S0 Group {} DEF S1 Group {} DEF S2 Group {} ] }
Switch { choice [ DEF N0 Group {} ] }
Switch { whichChoice -1 choice [ DEF N1 Group {} ] }
Switch { whichChoice 5 choice [ DEF N2 Group {} ] }
LOD { range [ 10 ] level [ DEF L0 Group {} DEF L1 Group {} ] }
)"),
                                         "s.wrl");
    CHECK(find_node(scene, "S1") >= 0);
    for (const char* absent : {"S0", "S2", "N0", "N1", "N2", "L1"}) CHECK(find_node(scene, absent) == -1);
    const int l0 = find_node(scene, "L0");
    REQUIRE(l0 >= 0);
    CHECK(scene.nodes[static_cast<size_t>(scene.nodes[static_cast<size_t>(l0)].parent)].kind == "LOD");
    REQUIRE(scene.warnings.size() == 1);
    CHECK(scene.warnings[0].find(":6: Switch.whichChoice 5 is out of range") != std::string::npos);
}

TEST_CASE("USE of a whole node repeats it under each parent") {
    const VrmlScene scene = read_written(vrml(R"(
Transform { translation 1 0 0 children DEF PART Transform { translation 0 1 0 children Shape { geometry Box {} } } }
Transform { translation 5 0 0 children USE PART }
)"),
                                         "u.wrl");
    REQUIRE(scene.nodes.size() == 4);
    CHECK(scene.nodes[1].name == "PART");
    CHECK(scene.nodes[3].name == "PART");
    CHECK(scene.nodes[3].parent == 2);
    CHECK(scene.nodes[1].world.translation().isApprox(Eigen::Vector3d(1, 1, 0)));
    CHECK(scene.nodes[3].world.translation().isApprox(Eigen::Vector3d(5, 1, 0)));
    CHECK(scene.nodes[3].meshes.size() == 1);
}

TEST_CASE("comments, commas, string escapes and hex integers") {
    const VrmlScene scene = read_written(vrml(R"(# a comment line
WorldInfo { title "say \"hi\" # not a comment \\ done" # trailing comment
            info [ "one", "two",, ] }
Transform { translation 1,2,3, # commas are whitespace
  rotation 0,1,0,0 children [
    Shape { geometry Box { size 1 1 1 } },
    Shape { appearance Appearance { texture PixelTexture { image 1 1 3 0xFF00aa } } }
  ] }
ROUTE A.b TO C.d
)"),
                                         "c.wrl");
    CHECK(scene.title == "say \"hi\" # not a comment \\ done");
    CHECK(scene.info == std::vector<std::string>{"one", "two"});
    REQUIRE(scene.nodes.size() == 1);
    CHECK(scene.nodes[0].world.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
    CHECK(scene.nodes[0].meshes.size() == 1);
    CHECK(scene.nodes[0].line == 5);
}

TEST_CASE("top-level Shapes of the main file go to one implicit Group") {
    const VrmlScene scene = read_written(vrml(R"(
Shape { geometry Box {} }
DEF T Transform {}
Shape { geometry Sphere {} }
)"),
                                         "top.wrl");
    REQUIRE(scene.nodes.size() == 2);
    CHECK(scene.nodes[0].kind == "Group");
    CHECK(scene.nodes[0].line == 3);
    CHECK(scene.nodes[0].meshes.size() == 2);
    CHECK(scene.nodes[1].name == "T");
}

TEST_CASE("unsupported content is dropped with a warning, never silently") {
    const VrmlScene scene = read_written(vrml(R"(
Group { children [
  Shape { geometry ElevationGrid { xDimension 2 zDimension 2 height [ 0 0 0 0 ] } }
  FancyNode { foo 1 bar [ Group {} ] }
  Transform { translaton 1 2 3 }
] }
)"),
                                         "w.wrl");
    REQUIRE(scene.warnings.size() == 3);
    CHECK(scene.warnings[0].find(":5: unknown node type 'FancyNode'") != std::string::npos);
    CHECK(scene.warnings[1].find(":6: Transform has no field 'translaton'") != std::string::npos);
    CHECK(scene.warnings[2].find(":4: geometry node 'ElevationGrid' is not supported") != std::string::npos);
}

TEST_CASE("read_vrml_text reads text in memory as read_vrml reads the file") {
    const TempDir dir;
    dir.write("part.wrl", vrml("WorldInfo { title \"P\" }\nShape { geometry Box { } }\n"));
    const std::string text = vrml("DEF T Transform { translation 1 2 3 children Inline { url \"part.wrl\" } }\n");
    const std::string path = dir.path() + "/memory.wrl";  // never written: Inlines resolve from its folder
    const VrmlScene from_text = read_vrml_text(text, path);
    const VrmlScene from_file = read_vrml(dir.write("file.wrl", text));
    REQUIRE(from_text.nodes.size() == 2);
    REQUIRE(from_file.nodes.size() == 2);
    CHECK(from_text.nodes[0].file == path);
    CHECK(from_file.nodes[0].file == dir.path() + "/file.wrl");
    for (size_t i = 0; i < 2; ++i) {
        CHECK(from_text.nodes[i].world.isApprox(from_file.nodes[i].world));
        CHECK(from_text.nodes[i].part_name == from_file.nodes[i].part_name);
        CHECK(from_text.nodes[i].meshes.size() == from_file.nodes[i].meshes.size());
    }
    CHECK(from_text.nodes[1].part_name == "P");
    CHECK(from_text.nodes[1].world.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
}
}  // namespace MBX_UNITY_ID
