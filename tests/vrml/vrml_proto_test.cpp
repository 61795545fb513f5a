// PROTO expansion (IS defaults and overrides), EXTERNPROTO, and the part
// names CAD exporters put in Model_Info-style nodes and WorldInfo.
#include <doctest/doctest.h>

#include "vrml_test_support.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using mbx_files::VrmlScene;
using vrml_test::find_node;
using vrml_test::read_written;
using vrml_test::signed_volume;
using vrml_test::vrml;

TEST_CASE("PROTO instances take IS fields from the instance, else the interface default") {
    const VrmlScene scene = read_written(vrml(R"(
PROTO Placed [
  field SFVec3f pos 0 0 0
  field SFRotation rot 0 0 1 0
  field SFVec3f boxSize 2 2 2
  field MFNode extra [ ]
  eventIn SFBool set_on
] {
  DEF BODY Transform { translation IS pos rotation IS rot
    children [ Shape { geometry Box { size IS boxSize } } Group { children IS extra } ] }
  Group { }  # not the first body node: not rendered
}
DEF P1 Placed { }
DEF P2 Placed { pos 1 2 3 boxSize 1 1 4 extra [ DEF X Transform { translation 0 0 1 } ] }
)"),
                                         "proto.wrl");
    // P1, BODY, Group | P2, BODY, Group, X
    REQUIRE(scene.nodes.size() == 7);
    CHECK(scene.nodes[0].kind == "Placed");
    CHECK(scene.nodes[0].name == "P1");
    CHECK(scene.nodes[0].line == 14);
    CHECK(scene.nodes[1].name == "BODY");
    CHECK(scene.nodes[1].parent == 0);
    CHECK(scene.nodes[1].line == 10);  // body nodes keep their place in the PROTO
    CHECK(scene.nodes[1].world.translation().isZero());
    REQUIRE(scene.nodes[1].meshes.size() == 1);
    CHECK(signed_volume(scene.nodes[1].meshes[0]) == mbx_test::relative(8.0, 1e-6));
    CHECK(scene.nodes[3].name == "P2");
    CHECK(scene.nodes[4].world.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
    CHECK(signed_volume(scene.nodes[4].meshes[0]) == mbx_test::relative(4.0, 1e-6));
    CHECK(scene.nodes[6].name == "X");
    CHECK(scene.nodes[6].parent == 5);
    CHECK(scene.nodes[6].world.translation().isApprox(Eigen::Vector3d(1, 2, 4)));
}

TEST_CASE("IS passes through nested PROTOs, and PROTOs work as geometry and coord") {
    const VrmlScene scene = read_written(vrml(R"(
PROTO Inner [ field SFVec3f p 0 0 0 ] { Transform { translation IS p } }
PROTO Outer [ field SFVec3f q 7 7 7 ] { Inner { p IS q } }
PROTO Tri [ field MFVec3f pts [ 0 0 0, 1 0 0, 0 1 0 ] ] {
  IndexedFaceSet { coord Coordinate { point IS pts } coordIndex [ 0 1 2 ] }
}
PROTO Pts [ ] { Coordinate { point [ 0 0 0, 0 0 1, 0 1 0 ] } }
DEF O1 Outer { }
DEF O2 Outer { q 1 2 3 }
Group { children [
  Shape { geometry Tri { } }
  Shape { geometry Tri { pts [ 0 0 0, 2 0 0, 0 2 0 ] } }
  Shape { geometry IndexedFaceSet { coord Pts { } coordIndex [ 0 1 2 ] } }
] }
)"),
                                         "nested.wrl");
    // O1, Inner, Transform | O2, Inner, Transform | Group
    REQUIRE(scene.nodes.size() == 7);
    CHECK(scene.nodes[2].world.translation().isApprox(Eigen::Vector3d(7, 7, 7)));
    CHECK(scene.nodes[5].world.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
    const auto& meshes = scene.nodes[6].meshes;
    REQUIRE(meshes.size() == 3);
    CHECK(meshes[0].vertices[3] == 1);
    CHECK(meshes[1].vertices[3] == 2);
    CHECK(meshes[2].vertices[5] == 1);
}

TEST_CASE("EXTERNPROTO instances are empty groups, with a warning") {
    const VrmlScene scene = read_written(vrml(R"(
EXTERNPROTO Gear [ field SFFloat teeth field MFNode children ] [ "gears.wrl#Gear" "http://x/gears.wrl#Gear" ]
Transform { children DEF G Gear { teeth 12 children [ Transform { } ] } }
)"),
                                         "ext.wrl");
    REQUIRE(scene.nodes.size() == 2);
    CHECK(scene.nodes[1].kind == "Gear");
    CHECK(scene.nodes[1].name == "G");
    REQUIRE(scene.warnings.size() == 1);
    CHECK(scene.warnings[0].find("ext.wrl:3: EXTERNPROTO 'Gear' is not loaded") != std::string::npos);
}

TEST_CASE("a Model_Info-style PROTO names its enclosing node and all below it") {
    const VrmlScene scene = read_written(vrml(R"(
PROTO Model_Info [ field SFString name "" field SFString units "mm" ] { WorldInfo { } }
DEF ASM Transform { children [
  DEF PART Group { children [
    DEF BEFORE Transform { children Shape { geometry Box { } } }
    Model_Info { name "PRT0001" }
    DEF AFTER Transform { children [ DEF DEEP Group { } ] }
  ] }
  DEF OTHER Group { children [ Model_Info { } ] }
  DEF THIRD Group { children [ Model_Info { name "PRT0003" } Model_Info { name "LATER" } ] }
] }
)"),
                                         "names.wrl");
    auto part_of = [&](const char* def) {
        const int i = find_node(scene, def);
        REQUIRE(i >= 0);
        return scene.nodes[static_cast<size_t>(i)].part_name;
    };
    CHECK(part_of("ASM").empty());
    CHECK(part_of("PART") == "PRT0001");
    CHECK(part_of("BEFORE") == "PRT0001");  // sibling order does not matter
    CHECK(part_of("AFTER") == "PRT0001");
    CHECK(part_of("DEEP") == "PRT0001");
    CHECK(part_of("OTHER").empty());       // the default "" names nothing
    CHECK(part_of("THIRD") == "PRT0003");  // the first name found wins
    int info_nodes = 0;
    for (const auto& n : scene.nodes)
        if (n.kind == "Model_Info") {
            ++info_nodes;
            if (n.parent == find_node(scene, "PART")) CHECK(n.part_name == "PRT0001");
        }
    CHECK(info_nodes == 4);
}

TEST_CASE("a PROTO with a partName field names itself, and WorldInfo titles name the group they are in") {
    const VrmlScene scene = read_written(vrml(R"(
WorldInfo { title "Assembly A" info [ "exported by test" ] }
WorldInfo { title "ignored: only the first top-level WorldInfo is the scene's" }
PROTO CadPart [ field SFString part_name "UNNAMED" exposedField MFNode children [ ] ] {
  Group { children IS children }
}
PROTO Label [ field SFString title "not a name" ] { Group { } }
DEF P CadPart { part_name "ARM-01" children [
  DEF INSIDE Transform { children [ WorldInfo { title "INNER_NAME" } DEF INNER_CHILD Group { } ] } ] }
DEF D CadPart { }
DEF L Group { children [ Label { } ] }
DEF W Group { children [ WorldInfo { title "W_PART" } DEF WC Group { } ] }
)"),
                                         "names2.wrl");
    CHECK(scene.title == "Assembly A");
    CHECK(scene.info == std::vector<std::string>{"exported by test"});
    auto part_of = [&](const char* def) {
        const int i = find_node(scene, def);
        REQUIRE(i >= 0);
        return scene.nodes[static_cast<size_t>(i)].part_name;
    };
    CHECK(part_of("P") == "ARM-01");
    CHECK(part_of("INSIDE") == "INNER_NAME");  // a deeper name overrides the inherited one
    CHECK(part_of("INNER_CHILD") == "INNER_NAME");
    CHECK(part_of("D") == "UNNAMED");  // the interface default counts
    CHECK(part_of("L").empty());       // "title" only names in *Info PROTOs
    CHECK(part_of("W") == "W_PART");
    CHECK(part_of("WC") == "W_PART");
}

TEST_CASE("a Model_Info at the top of a file names the file's top-level nodes") {
    const VrmlScene scene = read_written(vrml(R"(
PROTO Model_Info [ field SFString model_name "" ] { Group { } }
DEF A Transform { }
Model_Info { model_name "SINGLE_PART" }
DEF B Transform { children DEF C Group { } }
)"),
                                         "single.wrl");
    for (const auto& n : scene.nodes) CHECK(n.part_name == "SINGLE_PART");
    CHECK(scene.nodes.size() == 5);
}
}  // namespace MBX_UNITY_ID
