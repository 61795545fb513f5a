// Shapes to triangle meshes: IndexedFaceSet triangulation and winding,
// DEF/USE of Coordinate and geometry, primitives.
#include <cmath>

#include <doctest/doctest.h>

#include "host_adapters/common/primitive_meshes.h"
#include "vrml_test_support.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using mbx_files::VrmlMesh;
using mbx_files::VrmlScene;
using vrml_test::is_closed;
using vrml_test::read_written;
using vrml_test::signed_volume;
using vrml_test::vrml;

namespace {

const char* cube_points = R"(point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0, 0 0 1, 1 0 1, 1 1 1, 0 1 1 ])";
// Quads counter-clockwise seen from outside.
const char* cube_ccw = "0 3 2 1 -1 4 5 6 7 -1 0 1 5 4 -1 2 3 7 6 -1 1 2 6 5 -1 0 4 7 3";
// The same quads clockwise.
const char* cube_cw = "0 1 2 3 -1 4 7 6 5 -1 0 4 5 1 -1 2 6 7 3 -1 1 5 6 2 -1 0 3 7 4 -1";

VrmlMesh only_mesh(const VrmlScene& scene) {
    REQUIRE(scene.nodes.size() == 1);
    REQUIRE(scene.nodes[0].meshes.size() == 1);
    return scene.nodes[0].meshes[0];
}

VrmlScene cube(const std::string& index, const std::string& extra) {
    return read_written(vrml("Transform { children Shape { geometry DEF CUBE IndexedFaceSet { " + extra +
                             " coord Coordinate { " + cube_points + " } coordIndex [ " + index + " ] } } }\n"),
                        "cube.wrl");
}

}  // namespace

TEST_CASE("a unit cube of quads gives 12 triangles, closed, volume 1") {
    const VrmlMesh m = only_mesh(cube(cube_ccw, ""));
    CHECK(m.name == "CUBE");
    CHECK(m.vertices.size() == 24);
    CHECK(m.triangles.size() == 36);
    CHECK(is_closed(m));
    CHECK(signed_volume(m) == mbx_test::relative(1.0, 1e-12));
    // Fan from each face's first vertex: face 0 3 2 1 -> (0 3 2) (0 2 1).
    CHECK(std::vector<uint32_t>(m.triangles.begin(), m.triangles.begin() + 6) ==
          std::vector<uint32_t>{0, 3, 2, 0, 2, 1});
}

TEST_CASE("ccw FALSE flips the winding to counter-clockwise") {
    const VrmlMesh as_written = only_mesh(cube(cube_cw, ""));
    CHECK(signed_volume(as_written) == mbx_test::relative(-1.0, 1e-6));
    const VrmlMesh flipped = only_mesh(cube(cube_cw, "ccw FALSE"));
    CHECK(signed_volume(flipped) == mbx_test::relative(1.0, 1e-6));
    CHECK(is_closed(flipped));
}

TEST_CASE("faces with fewer than 3 vertices are skipped with a warning, and a last face needs no -1") {
    const VrmlScene scene = read_written(vrml(R"(
Group { children Shape { geometry IndexedFaceSet {
  coord Coordinate { point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0, 2 2 2 ] }
  coordIndex [ 0 1 -1
               -1 4 -1
               0 1 2 3 -1 1 2 4 ]
} } }
)"),
                                         "faces.wrl");
    const VrmlMesh m = only_mesh(scene);
    CHECK(m.triangles == std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 1, 2, 4});
    REQUIRE(scene.warnings.size() == 1);
    CHECK(scene.warnings[0].find("faces.wrl:5: 2 face(s) with fewer than 3 vertices") != std::string::npos);
}

TEST_CASE("a Transform with a zero scale is a warning naming what the geometry collapses to, a normal one none") {
    const VrmlScene scene = read_written(vrml(R"(
Transform { scale 1 0 1 children Shape { geometry Box { size 1 1 1 } } }
Transform { scale 0 0 0 children Shape { geometry Box { size 1 1 1 } } }
Transform { scale 2 2 2 children Shape { geometry Box { size 1 1 1 } } }
)"),
                                         "flat.wrl");
    for (const std::string& w : scene.warnings) MESSAGE(w);
    REQUIRE(scene.warnings.size() == 2);
    CHECK(scene.warnings[0].find("flat.wrl:3: Transform.scale (1 0 1) has a zero component: the geometry below it "
                                 "collapses to a plane") != std::string::npos);
    CHECK(scene.warnings[1].find("flat.wrl:4:") != std::string::npos);
    CHECK(scene.warnings[1].find("collapses to a point") != std::string::npos);
}

TEST_CASE("DEF/USE reuses a Coordinate and a whole geometry node") {
    const VrmlScene scene = read_written(vrml(R"(
Group { children [
  Shape { geometry IndexedFaceSet { coord DEF PTS Coordinate { point [ 0 0 0, 1 0 0, 0 1 0, 0 0 1 ] }
                                    coordIndex [ 0 2 1 -1 ] } }
  Shape { geometry IndexedFaceSet { coord USE PTS coordIndex [ 0 1 3 -1 0 3 2 -1 1 2 3 ] } }
  DEF S Shape { geometry DEF G IndexedFaceSet { coord USE PTS coordIndex [ 1 2 3 ] } }
  Shape { geometry USE G }
] }
)"),
                                         "use.wrl");
    REQUIRE(scene.nodes.size() == 1);
    const auto& meshes = scene.nodes[0].meshes;
    REQUIRE(meshes.size() == 4);
    for (const VrmlMesh& m : meshes) CHECK(m.vertices == meshes[0].vertices);
    CHECK(meshes[1].triangles.size() == 9);
    CHECK(meshes[2].name == "S");  // the Shape's DEF name wins over the geometry's
    CHECK(meshes[3].name == "G");
    CHECK(meshes[3].triangles == meshes[2].triangles);
    // The four faces of meshes 0 and 1 close the tetrahedron.
    VrmlMesh tetra = meshes[1];
    tetra.triangles.insert(tetra.triangles.end(), meshes[0].triangles.begin(), meshes[0].triangles.end());
    CHECK(is_closed(tetra));
    CHECK(signed_volume(tetra) == mbx_test::relative(1.0 / 6, 1e-6));
}

TEST_CASE("Box is exact, and Sphere, Cylinder and Cone are closed and near their volume") {
    const VrmlScene scene = read_written(vrml(R"(
Group { children [
  Shape { geometry Box { size 2 3 4 } }
  Shape { geometry Sphere { radius 2 } }
  Shape { geometry Cylinder { radius 1 height 3 } }
  Shape { geometry Cone { bottomRadius 2 height 3 } }
  Shape { geometry Box { } }
  Shape { geometry Cylinder { top FALSE } }
] }
)"),
                                         "prim.wrl");
    const double pi = std::acos(-1.0);
    REQUIRE(scene.nodes.size() == 1);
    const auto& m = scene.nodes[0].meshes;
    REQUIRE(m.size() == 6);
    for (size_t i = 0; i < 5; ++i) {
        INFO("mesh " << i);
        CHECK(is_closed(m[i]));
    }
    CHECK(m[0].triangles.size() == 36);
    CHECK(signed_volume(m[0]) == mbx_test::relative(24.0, 1e-14));
    CHECK(signed_volume(m[4]) == mbx_test::relative(8.0, 1e-14));  // default size 2 2 2
    // Inscribed facets: a little below the analytic volume, never above.
    const double sphere = 4.0 / 3 * pi * 8, cylinder = pi * 3, cone = pi * 4 * 3 / 3;
    CHECK(signed_volume(m[1]) < sphere);
    CHECK(signed_volume(m[1]) > 0.95 * sphere);
    CHECK(signed_volume(m[2]) < cylinder);
    CHECK(signed_volume(m[2]) > 0.98 * cylinder);
    CHECK(signed_volume(m[3]) < cone);
    CHECK(signed_volume(m[3]) > 0.98 * cone);
    // Sphere centred on the origin with radius 2; cylinder spans y in [-1.5, 1.5].
    for (size_t v = 0; v < m[1].vertices.size(); v += 3) {
        const double r = std::sqrt(m[1].vertices[v] * m[1].vertices[v] + m[1].vertices[v + 1] * m[1].vertices[v + 1] +
                                   m[1].vertices[v + 2] * m[1].vertices[v + 2]);
        CHECK(r == mbx_test::relative(2.0, 1e-6));
    }
    double ymin = 1e9, ymax = -1e9;
    for (size_t v = 1; v < m[2].vertices.size(); v += 3) {
        ymin = std::min(ymin, m[2].vertices[v]);
        ymax = std::max(ymax, m[2].vertices[v]);
    }
    CHECK(ymin == -1.5);
    CHECK(ymax == 1.5);
    CHECK(!is_closed(m[5]));  // top FALSE leaves it open
    CHECK(m[5].triangles.size() == m[2].triangles.size() - 3 * mbx_files::vrml::primitive_segments);
}

TEST_CASE("an IndexedFaceSet without coord or coordIndex gives no mesh") {
    const VrmlScene scene = read_written(vrml(R"(
Group { children [
  Shape { geometry IndexedFaceSet { coordIndex [ 0 1 2 ] } }
  Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0 1 0 0 0 1 0 ] } } }
  Shape { geometry NULL }
  Shape { }
] }
)"),
                                         "empty.wrl");
    REQUIRE(scene.nodes.size() == 1);
    CHECK(scene.nodes[0].meshes.empty());
}
}  // namespace MBX_UNITY_ID
