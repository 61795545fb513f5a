// Fuzzing with a fixed seed: a valid scene that uses most of the reader,
// truncated at every byte and mutated at random. Each case must end in
// success or a VrmlError; sanitizer builds (MBX_SANITIZE) run the same cases.
#include <cmath>
#include <cstdlib>
#include <random>

#include <doctest/doctest.h>

#include "vrml_test_support.h"

namespace MBX_UNITY_ID {

using mbx_files::read_vrml_text;
using mbx_files::VrmlError;
using mbx_files::VrmlScene;
using vrml_test::TempDir;
using vrml_test::vrml;

namespace {

const std::string base_scene = vrml(R"(# fuzz base
WorldInfo { title "fuzz \"base\"" info [ "a", "b" ] }
PROTO Model_Info [ field SFString name "" exposedField MFNode children [ ] eventIn SFBool set_x ] {
  Group { children IS children }
}
PROTO Tri [ field MFVec3f p [ 0 0 0, 1 0 0, 0 1 0 ] field SFBool c TRUE ] {
  IndexedFaceSet { ccw IS c coord Coordinate { point IS p } coordIndex [ 0 1 2 -1 ] }
}
EXTERNPROTO Ext [ field SFFloat x ] "ext.wrl#Ext"
DEF ROOT Transform {
  translation 1 2 3 rotation 0 1 0 0.5 scale 1 2 1 scaleOrientation 1 0 0 0.3 center 0.5 0 0
  children [
    Model_Info { name "PART_1" children [
      DEF S Shape { appearance Appearance { material Material { diffuseColor 1 0 0 } }
        geometry DEF IFS IndexedFaceSet { ccw FALSE
          coord DEF C Coordinate { point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0, 0.5 0.5 1e-3 ] }
          coordIndex [ 0 1 2 3 -1, 0 1 4 -1 2 3 4 ] } }
      Shape { geometry IndexedFaceSet { coord USE C coordIndex [ 4 3 2 ] } }
    ] }
    Switch { whichChoice 0 choice [ Shape { geometry Box { size 1 2 3 } } Group { } ] }
    LOD { range [ 10 ] level [ Shape { geometry Sphere { radius 0.5 } } Group { } ] }
    Shape { geometry Cylinder { radius 1 height 2 top FALSE } }
    Shape { geometry Cone { } }
    Shape { geometry Tri { c FALSE } }
    Ext { x 1 }
    Inline { url [ "http://example.com/x.wrl" "part.wrl" ] }
    Viewpoint { position 0 0 10 description "view" }
    USE S
    Script { field SFInt32 n 0xFF eventIn SFTime t url "javascript: function t() {}" }
  ]
}
ROUTE ROOT.translation TO ROOT.set_translation
)");

const std::string part_scene = vrml(R"(
WorldInfo { title "PART" }
Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0 1 0 0 0 1 0 ] } coordIndex [ 0 1 2 ] } }
)");

// What any successful read must satisfy.
void check_scene(const VrmlScene& scene) {
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const auto& n = scene.nodes[i];
        REQUIRE(n.parent < static_cast<int>(i));
        REQUIRE(n.world.matrix().allFinite());
        for (const auto& m : n.meshes) {
            REQUIRE(m.vertices.size() % 3 == 0);
            REQUIRE(m.triangles.size() % 3 == 0);
            for (double v : m.vertices) REQUIRE(std::isfinite(v));
            for (uint32_t t : m.triangles) REQUIRE(t < m.vertices.size() / 3);
        }
    }
}

// Reads `text`; true on success, false on VrmlError. Anything else fails the test.
bool read_case(const std::string& text, const std::string& path) {
    try {
        check_scene(read_vrml_text(text, path));
        return true;
    } catch (const VrmlError& e) {
        REQUIRE(e.line() >= 0);
        REQUIRE(!e.file().empty());
        return false;
    }
}

}  // namespace

TEST_CASE("fuzz: the base scene reads, and every truncation of it ends cleanly") {
    const TempDir dir;
    dir.write("part.wrl", part_scene);
    const std::string path = dir.path() + "/base.wrl";
    {
        const VrmlScene scene = read_vrml_text(base_scene, path);
        check_scene(scene);
        CHECK(scene.title == "fuzz \"base\"");
        // ROOT, Model_Info and its body Group, Switch, LOD, Ext, Inline.
        REQUIRE(scene.nodes.size() == 7);
        CHECK(scene.nodes[0].meshes.size() == 4);  // Cylinder, Cone, Tri, USE S
        CHECK(scene.nodes[2].meshes.size() == 2);
        CHECK(scene.nodes[2].part_name == "PART_1");
        CHECK(scene.nodes[6].part_name == "PART");
        CHECK(scene.warnings.size() == 2);  // EXTERNPROTO, remote Inline url
    }
    size_t ok = 0;
    for (size_t cut = 0; cut < base_scene.size(); ++cut) {
        INFO("truncated at byte " << cut);
        ok += read_case(base_scene.substr(0, cut), path);
    }
    MESSAGE(base_scene.size() << " truncations, " << ok << " read without error");
}

TEST_CASE("fuzz: random byte mutations end in success or VrmlError") {
    const TempDir dir;
    dir.write("part.wrl", part_scene);
    const std::string path = dir.path() + "/base.wrl";
    std::mt19937 rng(20240611);
    // Bytes that matter to the grammar, and some that should never appear.
    const std::string palette = "{}[]\"#\\,.-+0123456789eExX IS DEF USE NULL TRUE\n\x00\x01\x7f\xff";
    auto pick = [&](size_t n) { return static_cast<size_t>(rng() % n); };
    size_t ok = 0;
    int cases = 3000;  // MBX_VRML_FUZZ_CASES runs more, with the same seed
    if (const char* env = std::getenv("MBX_VRML_FUZZ_CASES")) cases = std::atoi(env);
    for (int c = 0; c < cases; ++c) {
        std::string text = base_scene;
        const int edits = 1 + static_cast<int>(pick(4));
        for (int e = 0; e < edits; ++e) {
            const size_t at = 16 + pick(text.size() - 16);  // keep the header mostly
            switch (pick(5)) {
                case 0: text[at] = palette[pick(palette.size())]; break;
                case 1: text[at] = static_cast<char>(rng() & 0xff); break;
                case 2: text.insert(at, 1, palette[pick(palette.size())]); break;
                case 3: text.erase(at, 1 + pick(8)); break;
                default: {  // copy a chunk elsewhere: nests or unbalances brackets
                    const size_t from = pick(text.size()), len = 1 + pick(64);
                    text.insert(at, text.substr(from, len));
                }
            }
        }
        INFO("case " << c);
        ok += read_case(text, path);
    }
    MESSAGE(cases << " mutated files, " << ok << " read without error");
}
}  // namespace MBX_UNITY_ID
