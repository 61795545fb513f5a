// Solids whose volume is known exactly, written as STEP by the tests
// (tests/common/step_solids.h): each meshed closed, with outward normals, and
// its volume within the bound its own chord tolerance sets (the chord times
// the surface's area: no point of the mesh is farther than the chord from
// the surface). The same solids in millimetres, metres, inches and Onshape's
// 'METRE' are one solid, and a cone's semi-angle reads right in degrees.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/geometry/mesh_properties.h"
#include "core/geometry/self_intersection.h"
#include "host_adapters/step/brep.h"
#include "host_adapters/step/part21.h"
#include "host_adapters/step/tessellate.h"
#include "tests/common/near.h"
#include "tests/common/step_solids.h"
#include "tests/step/step_test_support.h"

namespace MBX_UNITY_ID {

using namespace mbx_step;
using Eigen::Vector3d;
using mbx_test::StepSolidWriter;
using mbx_test::StepUnit;

namespace {

struct Meshed {
    double volume = 0, signed_volume = 0, chord = 0;
    Vector3d centroid = Vector3d::Zero();
    size_t triangles = 0, points = 0;
    bool closed = false;
    size_t problems = 0;
};

std::vector<Meshed> mesh_all(const std::string& text, const Tolerance& tolerance = Tolerance{}) {
    const File f = read_part21(text, "analytic.step");
    const Brep b = read_breps(f);
    for (const Problem& p : b.problems) FAIL_CHECK("#" << p.entity << ": " << p.message);
    std::vector<Meshed> out;
    for (const SolidMesh& m : tessellate(b, tolerance)) {
        for (const Problem& p : m.problems) FAIL_CHECK("#" << p.entity << ": " << p.message);
        Meshed r;
        const step_test::FlatMesh flat = step_test::flatten(m.mesh);
        mbx::SolidAccumulator acc;
        acc.add(m.mesh.points, flat.indices);
        r.volume = acc.result().volume;
        r.centroid = acc.result().centroid;
        r.signed_volume = flat.signed_volume;
        r.chord = m.chord;
        r.triangles = m.mesh.triangles.size();
        r.points = m.mesh.points.size();
        r.closed = mbx::check_closure(flat.indices).closed &&
                   mbx::find_self_intersections(m.mesh.points, flat.indices).count == 0;
        r.problems = m.problems.size();
        out.push_back(r);
    }
    return out;
}

// One solid: closed, outward, and its volume within chord x area of the exact one.
void check_exact(const Meshed& m, double volume, double area) {
    CHECK(m.closed);
    CHECK(m.problems == 0);
    CHECK(m.signed_volume > 0);
    CHECK(m.volume == mbx_test::within(volume, m.chord * area, "the chord tolerance times the surface's area"));
}

}  // namespace

TEST_CASE("step analytic solids: box, tube, sphere, torus, frustum, B-spline plane and cylinder, revolution and extrusion have their exact volumes") {
    const double pi = M_PI;
    StepSolidWriter w;
    w.box(Vector3d(-0.01, 0.02, 0.005), Vector3d(0.03, 0.05, 0.012));
    w.tube(0.02, 0.008, -0.01, 0.025);
    w.sphere(0.015, Vector3d(0.1, -0.02, 0.03));
    w.torus(0.03, 0.007);
    w.frustum(0.02, 0.008, 0.03);
    w.spline_cylinder(0.012, 0.04);
    w.box(Vector3d(0, 0, 0), Vector3d(0.04, 0.02, 0.01), true);
    w.revolved_ring(0.025, 0.006);
    w.extruded_cylinder(0.011, 0.03);
    const std::vector<Meshed> m = mesh_all(w.file());
    REQUIRE(m.size() == 9);
    check_exact(m[0], 0.04 * 0.03 * 0.007, 2 * (0.04 * 0.03 + 0.03 * 0.007 + 0.04 * 0.007));
    check_exact(m[1], pi * (0.02 * 0.02 - 0.008 * 0.008) * 0.035,
                2 * pi * (0.02 + 0.008) * 0.035 + 2 * pi * (0.02 * 0.02 - 0.008 * 0.008));
    check_exact(m[2], 4.0 / 3 * pi * std::pow(0.015, 3), 4 * pi * 0.015 * 0.015);
    CHECK((m[2].centroid - Vector3d(0.1, -0.02, 0.03)).norm() == mbx_test::within(0, 1e-4 * 0.015, "1e-4 of the radius"));
    check_exact(m[3], 2 * pi * pi * 0.03 * 0.007 * 0.007, 4 * pi * pi * 0.03 * 0.007);
    const double slant = std::hypot(0.03, 0.012);
    check_exact(m[4], pi * 0.03 / 3 * (0.02 * 0.02 + 0.02 * 0.008 + 0.008 * 0.008),
                pi * (0.02 + 0.008) * slant + pi * (0.02 * 0.02 + 0.008 * 0.008));
    // The frustum's centroid height from the formula for a truncated cone.
    const double r0 = 0.02, r1 = 0.008, h = 0.03;
    const double zc = h * (r0 * r0 + 2 * r0 * r1 + 3 * r1 * r1) / (4 * (r0 * r0 + r0 * r1 + r1 * r1));
    CHECK(m[4].centroid.z() == mbx_test::within(zc, 1e-4 * h, "1e-4 of the height"));
    check_exact(m[5], pi * 0.012 * 0.012 * 0.04, 2 * pi * 0.012 * 0.04 + 2 * pi * 0.012 * 0.012);
    check_exact(m[6], 0.04 * 0.02 * 0.01, 2 * (0.04 * 0.02 + 0.02 * 0.01 + 0.04 * 0.01));
    check_exact(m[7], 2 * pi * pi * 0.025 * 0.006 * 0.006, 4 * pi * pi * 0.025 * 0.006);
    check_exact(m[8], pi * 0.011 * 0.011 * 0.03, 2 * pi * 0.011 * 0.03 + 2 * pi * 0.011 * 0.011);
    // A looser tolerance still keeps the bound (and meshes with fewer triangles).
    Tolerance loose;
    loose.relative_chord = 1e-3;
    loose.angle = M_PI / 18;
    const std::vector<Meshed> coarse = mesh_all(w.file(), loose);
    REQUIRE(coarse.size() == 9);
    CHECK(coarse[2].triangles < m[2].triangles / 4);
    CHECK(coarse[2].closed);
    CHECK(coarse[2].volume == mbx_test::within(4.0 / 3 * pi * std::pow(0.015, 3), coarse[2].chord * 4 * pi * 0.015 * 0.015,
                                               "the chord tolerance times the surface's area"));
    CHECK(coarse[3].volume == mbx_test::within(2 * pi * pi * 0.03 * 0.007 * 0.007, coarse[3].chord * 4 * pi * pi * 0.03 * 0.007,
                                               "the chord tolerance times the surface's area"));
}

TEST_CASE("step analytic solids: one part in millimetres, metres, inches and Onshape's 'METRE' is one solid") {
    std::vector<std::vector<Meshed>> runs;
    for (StepUnit unit : {StepUnit::Millimetre, StepUnit::Metre, StepUnit::Inch, StepUnit::OnshapeMetre}) {
        StepSolidWriter w(unit);
        w.box(Vector3d(-0.01, 0.02, 0.005), Vector3d(0.03, 0.05, 0.012));
        w.tube(0.02, 0.008, -0.01, 0.025);
        runs.push_back(mesh_all(w.file()));
        REQUIRE(runs.back().size() == 2);
    }
    CHECK(runs[0][0].volume == mbx_test::relative(0.04 * 0.03 * 0.007, 1e-12));
    for (size_t k = 1; k < runs.size(); ++k) {
        CAPTURE(k);
        for (size_t s = 0; s < 2; ++s) {
            // The same metres whatever the unit: the same mesh up to rounding.
            CHECK(runs[k][s].triangles == runs[0][s].triangles);
            CHECK(runs[k][s].volume == mbx_test::relative(runs[0][s].volume, 1e-9));
            CHECK((runs[k][s].centroid - runs[0][s].centroid).norm() == mbx_test::within(0, 1e-12, "rounding"));
        }
    }
}

TEST_CASE("step analytic solids: a cone's semi-angle read in degrees where the file says so") {
    StepSolidWriter radians(StepUnit::Millimetre, false), degrees(StepUnit::Millimetre, true);
    radians.frustum(0.02, 0.008, 0.03);
    degrees.frustum(0.02, 0.008, 0.03);
    const std::string in_degrees = degrees.file();
    CHECK(in_degrees.find("'DEGREE'") != std::string::npos);
    const std::vector<Meshed> a = mesh_all(radians.file()), b = mesh_all(in_degrees);
    REQUIRE(a.size() == 1);
    REQUIRE(b.size() == 1);
    const double exact = M_PI * 0.03 / 3 * (0.02 * 0.02 + 0.02 * 0.008 + 0.008 * 0.008);
    CHECK(a[0].volume == mbx_test::relative(exact, 1e-4));
    CHECK(b[0].volume == mbx_test::relative(a[0].volume, 1e-9));
    CHECK(b[0].closed);
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("step tessellated geometry: AP242 triangulated faces, strips and fans make the closed solid they describe") {
    // A 20 x 10 x 5 mm box: 8 corners in one coordinates list (mm), its six sides as
    // two TRIANGULATED_FACEs (one through a pnindex) and a COMPLEX_TRIANGULATED_FACE
    // with a strip and a fan.
    const std::string data =
        "#1=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n"
        "#2=(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));\n"
        "#3=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#1,#2))REPRESENTATION_CONTEXT('',''));\n"
        "#10=COORDINATES_LIST('',8,((0.,0.,0.),(20.,0.,0.),(0.,10.,0.),(20.,10.,0.),(0.,0.,5.),(20.,0.,5.),(0.,10.,5.),(20.,10.,5.)));\n"
        // bottom (z = 0, normal -z) and top (z = 5, normal +z)
        "#11=TRIANGULATED_FACE('bottom and top',#10,0,(),$,(),((1,3,2),(2,3,4),(5,6,8),(5,8,7)));\n"
        // y = 0 (normal -y) through a pnindex that lists corners 1, 2, 5, 6
        "#12=TRIANGULATED_FACE('front',#10,0,(),$,(1,2,5,6),((1,2,4),(1,4,3)));\n"
        // y = 10 (normal +y) as a strip 3,7,4,8; x = 0 and x = 20 as fans
        "#13=COMPLEX_TRIANGULATED_FACE('rest',#10,0,(),$,(),((3,7,4,8)),((1,5,7,3),(2,4,8,6)));\n"
        "#20=TESSELLATED_SOLID('box',(#11,#12,#13),$);\n"
        "#30=TESSELLATED_SHAPE_REPRESENTATION('',(#20),#3);\n";
    const File f = read_part21(step_test::wrap(data, "AP242_MANAGED_MODEL_BASED_3D_ENGINEERING_MIM_LF"), "tess.stp");
    const Brep b = read_breps(f);
    for (const Problem& p : b.problems) FAIL_CHECK("#" << p.entity << ": " << p.message);
    REQUIRE(b.solids.size() == 1);
    CHECK(b.solids[0].type == "TESSELLATED_SOLID");
    const std::vector<SolidMesh> m = tessellate(b, Tolerance{});
    REQUIRE(m.size() == 1);
    CHECK(m[0].mesh.triangles.size() == 12);
    const step_test::FlatMesh flat = step_test::flatten(m[0].mesh);
    CHECK(mbx::check_closure(flat.indices).closed);
    CHECK(flat.signed_volume == mbx_test::relative(0.02 * 0.01 * 0.005, 1e-12));  // outward and in metres

    // A triangle pointing past its coordinates list: left out, and said.
    const std::string broken = std::string(data).replace(data.find("(2,3,4)"), 7, "(2,3,9)");
    const Brep bad = read_breps(read_part21(step_test::wrap(broken), "bad.stp"));
    REQUIRE(bad.solids.size() == 1);
    CHECK(bad.solids[0].tessellated.triangles.size() == 11);
    bool said = false;
    for (const Problem& p : bad.problems) said = said || (p.entity == 11 && p.message.find("outside") != std::string::npos);
    CHECK(said);
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("step tessellation of bad solids: a shell with a face missing stays open, a degenerate face is a finding") {
    StepSolidWriter w;
    w.box(Vector3d(0, 0, 0), Vector3d(0.02, 0.01, 0.005));
    std::string text = w.file();
    // The box's shell without its first face: meshed, and open where the face was.
    const size_t shell = text.find("CLOSED_SHELL('',(#");
    REQUIRE(shell != std::string::npos);
    const size_t first = text.find('#', shell), comma = text.find(',', first);
    text.erase(first, comma - first + 1);
    const Brep open_box = read_breps(read_part21(text, "open.step"));
    REQUIRE(open_box.solids.size() == 1);
    const std::vector<SolidMesh> m = tessellate(open_box, Tolerance{});
    REQUIRE(m.size() == 1);
    CHECK(m[0].faces_meshed == 5);
    const mbx::MeshClosure closure = mbx::check_closure(step_test::flatten(m[0].mesh).indices);
    CHECK_FALSE(closure.closed);
    CHECK(closure.boundary_edges == 4);  // the missing face's rim

    // A plane face bounded by two edges between the same two points (no area):
    // not meshed, and the finding names the face's entity and line.
    const std::string data =
        "#1=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n"
        "#2=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#1))REPRESENTATION_CONTEXT('',''));\n"
        "#3=CARTESIAN_POINT('',(0.,0.,0.));\n#4=CARTESIAN_POINT('',(10.,0.,0.));\n"
        "#5=VERTEX_POINT('',#3);\n#6=VERTEX_POINT('',#4);\n#7=DIRECTION('',(1.,0.,0.));\n#8=VECTOR('',#7,10.);\n"
        "#9=LINE('',#3,#8);\n#10=EDGE_CURVE('',#5,#6,#9,.T.);\n#11=EDGE_CURVE('',#6,#5,#9,.F.);\n"
        "#12=ORIENTED_EDGE('',*,*,#10,.T.);\n#13=ORIENTED_EDGE('',*,*,#11,.T.);\n#14=EDGE_LOOP('',(#12,#13));\n"
        "#15=FACE_OUTER_BOUND('',#14,.T.);\n#16=DIRECTION('',(0.,0.,1.));\n#17=AXIS2_PLACEMENT_3D('',#3,#16,#7);\n"
        "#18=PLANE('',#17);\n#19=ADVANCED_FACE('',(#15),#18,.T.);\n#20=CLOSED_SHELL('',(#19));\n"
        "#21=MANIFOLD_SOLID_BREP('',#20);\n#22=ADVANCED_BREP_SHAPE_REPRESENTATION('',(#21),#2);\n";
    const std::string file = step_test::wrap(data);
    const Brep flat_face = read_breps(read_part21(file, "flat.step"));
    const std::vector<SolidMesh> none = tessellate(flat_face, Tolerance{});
    REQUIRE(none.size() == 1);
    CHECK(none[0].faces_failed == 1);
    CHECK(none[0].mesh.triangles.empty());
    REQUIRE(none[0].problems.size() == 1);
    CHECK(none[0].problems[0].entity == 19);
    CHECK(none[0].problems[0].line == int(std::count(file.begin(), file.begin() + long(file.find("#19=")), '\n')) + 1);
    CHECK(none[0].problems[0].message.find("face not meshed") != std::string::npos);
}

// A torus ring (major radius 20 mm, minor 5 mm) whose outer bounding circle
// is centred on its own start point, 25 mm off the torus: the two faces'
// bounds are not on their surface. Refining against them used to fill the
// face budget with folds (4.8 million triangles of negative volume, 12 s;
// found by fuzz_step_mesh); each face is now a finding and nothing is
// meshed. With the circle centred where it belongs the ring meshes closed
// with the torus's volume.
TEST_CASE("step tessellation: a face whose bounds lie off its surface is a finding, not a mesh of folds") {
    const std::string data =
        "#1=CARTESIAN_POINT('',(25.,0.,0.));\n"
        "#2=VERTEX_POINT('',#1);\n"
        "#3=DIRECTION('',(1.,0.,0.));\n"
        "#4=DIRECTION('',(0.,0.,1.));\n"
        "#5=CARTESIAN_POINT('',(0.,0.,0.));\n"
        "#6=AXIS2_PLACEMENT_3D('',#1,#4,#3);\n"
        "#7=CIRCLE('',#6,25.);\n"
        "#8=EDGE_CURVE('',#2,#2,#7,.T.);\n"
        "#9=CARTESIAN_POINT('',(15.,0.,0.));\n"
        "#10=VERTEX_POINT('',#9);\n"
        "#11=DIRECTION('',(1.,0.,0.));\n"
        "#12=DIRECTION('',(0.,0.,1.));\n"
        "#13=CARTESIAN_POINT('',(0.,0.,0.));\n"
        "#14=AXIS2_PLACEMENT_3D('',#13,#12,#11);\n"
        "#15=CIRCLE('',#14,15.);\n"
        "#16=EDGE_CURVE('',#10,#10,#15,.T.);\n"
        "#17=DIRECTION('',(1.,0.,0.));\n"
        "#18=DIRECTION('',(0.,0.,1.));\n"
        "#19=CARTESIAN_POINT('',(0.,0.,0.));\n"
        "#20=AXIS2_PLACEMENT_3D('',#19,#18,#17);\n"
        "#21=TOROIDAL_SURFACE('',#20,20.,5.);\n"
        "#22=ORIENTED_EDGE('',*,*,#8,.T.);\n"
        "#23=EDGE_LOOP('',(#22));\n"
        "#24=FACE_OUTER_BOUND('',#23,.T.);\n"
        "#25=ORIENTED_EDGE('',*,*,#16,.F.);\n"
        "#26=EDGE_LOOP('',(#25));\n"
        "#27=FACE_BOUND('',#26,.T.);\n"
        "#28=ADVANCED_FACE('',(#24,#27),#21,.T.);\n"
        "#29=ORIENTED_EDGE('',*,*,#8,.F.);\n"
        "#30=EDGE_LOOP('',(#29));\n"
        "#31=FACE_OUTER_BOUND('',#30,.T.);\n"
        "#32=ORIENTED_EDGE('',*,*,#16,.T.);\n"
        "#33=EDGE_LOOP('',(#32));\n"
        "#34=FACE_BOUND('',#33,.T.);\n"
        "#35=ADVANCED_FACE('',(#31,#34),#21,.T.);\n"
        "#36=CLOSED_SHELL('',(#28,#35));\n"
        "#37=MANIFOLD_SOLID_BREP('',#36);\n"
        "#38=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n"
        "#39=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT($,.METRE.));\n"
        "#40=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n"
        "#41=(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));\n"
        "#42=(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT());\n"
        "#43=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#38,#41,#42))REPRESENTATION_CONTEXT('',''));\n"
        "#44=ADVANCED_BREP_SHAPE_REPRESENTATION('',(#37),#43);\n";
    auto meshed = [](const std::string& text) {
        const Brep b = read_breps(read_part21(step_test::wrap(text), "ring.stp"));
        REQUIRE(b.solids.size() == 1);
        const std::vector<SolidMesh> m = tessellate(b, Tolerance{});
        REQUIRE(m.size() == 1);
        return m[0];
    };
    const SolidMesh off = meshed(data);
    CHECK(off.mesh.triangles.empty());
    CHECK(off.faces_failed == 2);
    REQUIRE(off.problems.size() == 2);
    for (const auto& p : off.problems) {
        CHECK((p.entity == 28 || p.entity == 35));
        CHECK(p.message.find("off its surface") != std::string::npos);
    }
    std::string centred = data;
    const std::string placed = "#6=AXIS2_PLACEMENT_3D('',#1,#4,#3);";
    centred.replace(centred.find(placed), placed.size(), "#6=AXIS2_PLACEMENT_3D('',#5,#4,#3);");
    const SolidMesh ring = meshed(centred);
    CHECK(ring.problems.empty());
    const step_test::FlatMesh flat = step_test::flatten(ring.mesh);
    CHECK(mbx::check_closure(flat.indices).closed);
    const double torus = 2 * M_PI * M_PI * 0.020 * 0.005 * 0.005;
    CHECK(std::abs(flat.signed_volume) == mbx_test::relative(torus, 1e-3));
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("step faceted B-rep: a tetrahedron of poly loops meshes closed with its exact volume") {
    // Faces in four different planes, each bounded by a POLY_LOOP (no surface given).
    const std::string data =
        "#1=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n"
        "#3=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#1))REPRESENTATION_CONTEXT('',''));\n"
        "#10=CARTESIAN_POINT('',(0.,0.,0.));\n#11=CARTESIAN_POINT('',(30.,0.,0.));\n"
        "#12=CARTESIAN_POINT('',(0.,20.,0.));\n#13=CARTESIAN_POINT('',(0.,0.,10.));\n"
        "#20=POLY_LOOP('',(#10,#12,#11));\n#21=POLY_LOOP('',(#10,#11,#13));\n"
        "#22=POLY_LOOP('',(#10,#13,#12));\n#23=POLY_LOOP('',(#11,#12,#13));\n"
        "#30=FACE_OUTER_BOUND('',#20,.T.);\n#31=FACE_OUTER_BOUND('',#21,.T.);\n"
        "#32=FACE_OUTER_BOUND('',#22,.T.);\n#33=FACE_OUTER_BOUND('',#23,.T.);\n"
        "#40=FACE('',(#30));\n#41=FACE('',(#31));\n#42=FACE('',(#32));\n#43=FACE('',(#33));\n"
        "#50=CLOSED_SHELL('',(#40,#41,#42,#43));\n#51=FACETED_BREP('tet',#50);\n"
        "#60=FACETED_BREP_SHAPE_REPRESENTATION('',(#51),#3);\n";
    const Brep b = read_breps(read_part21(step_test::wrap(data), "tet.stp"));
    REQUIRE(b.solids.size() == 1);
    const std::vector<SolidMesh> m = tessellate(b, Tolerance{});
    REQUIRE(m.size() == 1);
    CHECK(m[0].problems.empty());
    CHECK(m[0].mesh.triangles.size() == 4);
    const step_test::FlatMesh flat = step_test::flatten(m[0].mesh);
    CHECK(mbx::check_closure(flat.indices).closed);
    CHECK(flat.signed_volume == mbx_test::relative(0.03 * 0.02 * 0.01 / 6, 1e-12));
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("step tessellation of points that are not numbers: the faces they bound are findings, no NaN reaches a mesh") {
    // (found by fuzz_step_mesh: a circle through a vertex without a coordinate
    // asked for NaN segments, and such points reached the ear clipping's grid)
    StepSolidWriter w;
    w.tube(0.02, 0.008, 0, 0.03);
    std::string text = w.file();
    const size_t vertex = text.find("VERTEX_POINT('',#");
    REQUIRE(vertex != std::string::npos);
    const std::string point = "#" + text.substr(vertex + 17, text.find(')', vertex) - vertex - 17) + "=CARTESIAN_POINT('',(";
    const size_t at = text.find(point);
    REQUIRE(at != std::string::npos);
    const size_t first = at + point.size();
    text.replace(first, text.find(',', first) - first, "$");
    const Brep b = read_breps(read_part21(text, "nan.step"));
    CHECK_FALSE(b.problems.empty());  // the point without a coordinate is said
    const std::vector<SolidMesh> m = tessellate(b, Tolerance{});
    REQUIRE(m.size() == 1);
    CHECK(m[0].faces_failed > 0);
    for (const auto& t : m[0].mesh.triangles)
        for (uint32_t corner : t) CHECK(m[0].mesh.points[corner].allFinite());
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {
namespace {

// The farthest any triangle's centroid or any edge's middle lies from the
// exact surface (distance given by the caller), in chords.
template <class Distance>
double farthest_in_chords(const SolidMesh& m, const Distance& distance) {
    double worst = 0;
    for (const auto& t : m.mesh.triangles) {
        const Vector3d a = m.mesh.points[t[0]], b = m.mesh.points[t[1]], c = m.mesh.points[t[2]];
        for (const Vector3d& p : {Vector3d((a + b + c) / 3), Vector3d((a + b) / 2), Vector3d((b + c) / 2), Vector3d((c + a) / 2)})
            worst = std::max(worst, distance(p) / m.chord);
    }
    return worst;
}

}  // namespace

TEST_CASE("step tessellation: every triangle's middle and every edge's middle lie within the chord of the exact sphere, torus, tube and cone") {
    StepSolidWriter w;
    const Vector3d centre(0.1, -0.02, 0.03);
    w.sphere(0.015, centre);
    w.torus(0.03, 0.007);
    w.tube(0.02, 0.008, -0.01, 0.025);
    w.frustum(0.02, 0.008, 0.03);
    const File f = read_part21(w.file(), "analytic.step");
    const Brep b = read_breps(f);
    // At the default tolerance, and at a coarse one where the triangles are large.
    Tolerance coarse;
    coarse.relative_chord = 1e-3;
    coarse.angle = M_PI / 12;
    for (const Tolerance& tolerance : {Tolerance{}, coarse}) {
        const std::vector<SolidMesh> m = tessellate(b, tolerance);
        REQUIRE(m.size() == 4);
        for (const SolidMesh& s : m) REQUIRE(s.problems.empty());
        // (planar faces lie exactly on their planes; the curved ones are measured)
        const double sphere = farthest_in_chords(m[0], [&](const Vector3d& p) { return std::abs((p - centre).norm() - 0.015); });
        const double torus = farthest_in_chords(m[1], [](const Vector3d& p) {
            return std::abs(std::hypot(std::hypot(p.x(), p.y()) - 0.03, p.z()) - 0.007);
        });
        const double tube = farthest_in_chords(m[2], [](const Vector3d& p) {
            const double rho = std::hypot(p.x(), p.y());
            const bool on_cap = std::abs(p.z() + 0.01) < 1e-12 || std::abs(p.z() - 0.025) < 1e-12;
            return on_cap ? 0.0 : std::min(std::abs(rho - 0.02), std::abs(rho - 0.008));
        });
        // The frustum's side runs from radius 0.02 at z = 0 to 0.008 at z = 0.03.
        const double slant = std::hypot(0.012, 0.03);
        const double frustum = farthest_in_chords(m[3], [&](const Vector3d& p) {
            if (std::abs(p.z()) < 1e-12 || std::abs(p.z() - 0.03) < 1e-12) return 0.0;
            return std::abs((std::hypot(p.x(), p.y()) - (0.02 - 0.4 * p.z())) * 0.03 / slant);
        });
        MESSAGE("farthest in chords: sphere " << sphere << ", torus " << torus << ", tube " << tube << ", frustum " << frustum);
        CHECK(sphere <= 1.0);
        CHECK(torus <= 1.0);
        CHECK(tube <= 1.0);
        CHECK(frustum <= 1.0);
    }
}

TEST_CASE("step tessellation: a face that would need more triangles than the budget is meshed coarser, closed, with a finding naming it") {
    StepSolidWriter w;
    w.sphere(0.015, Vector3d::Zero());
    const File f = read_part21(w.file(), "analytic.step");
    const Brep b = read_breps(f);
    Tolerance tight;
    tight.face_triangle_budget = 500;
    const std::vector<SolidMesh> m = tessellate(b, tight);
    REQUIRE(m.size() == 1);
    // Both hemispheres stop at their budget; each is named by its entity and line.
    REQUIRE(m[0].problems.size() == 2);
    for (const Problem& p : m[0].problems) {
        CHECK(p.message.find("coarser than the chord tolerance") != std::string::npos);
        CHECK(p.line > 0);
        bool is_face = false;
        for (const Face& face : b.faces) is_face = is_face || face.id == p.entity;
        CHECK(is_face);
    }
    // (a round of splits under way finishes: the budget is checked between rounds)
    const size_t unlimited = tessellate(b, Tolerance{})[0].mesh.triangles.size();
    CHECK(m[0].mesh.triangles.size() < unlimited / 4);
    const step_test::FlatMesh flat = step_test::flatten(m[0].mesh);
    CHECK(mbx::check_closure(flat.indices).closed);
    CHECK(flat.signed_volume > 0);
}

}  // namespace MBX_UNITY_ID
