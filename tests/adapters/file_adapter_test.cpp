// The file adapter on the hand-written model: through the SDK, mesh files
// found, missing, broken and loaded lazily, VRML shapes matched by pose.
#include <string>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "stl_text.h"
#include "tiny_pmxml.h"
#include "translation_support.h"
#include "tests/common/near.h"
#include "tests/common/step_solids.h"

namespace MBX_UNITY_ID {

using mbx_files::FileAdapter;
using mbx_files::FileAdapterOptions;
using mbx_files::FileError;

namespace {

Eigen::Matrix3d row_major(const double* r) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m(i, j) = r[3 * i + j];
    return m;
}

// ARM's solid: a box centred on its CAD centre of mass, written in ARM's CS1
// frame in mm as SimMechanics Link writes STL.
std::string arm_stl() {
    const Eigen::Vector3d com_cs1 = atest::tiny_arm_rotation().transpose() * Eigen::Vector3d(50, 20, 10);
    return atest::stl_ascii(atest::box_triangles(com_cs1, Eigen::Vector3d(30, 12, 8)));
}

const mbx_memory::Diagnostic* diagnostic(const mbx_memory::Assembly& a, const std::string& code) {
    for (const mbx_memory::Diagnostic& d : a.diagnostics)
        if (d.code == code) return &d;
    return nullptr;
}

}  // namespace

TEST_CASE("adapter: the tiny model through the SDK, column-major to the rigid body pose") {
    atest::TempDir dir;
    const std::string text = atest::tiny_pmxml();
    atest::write_file(dir.file("tiny.xml"), text);
    const auto adapter = FileAdapter::open(dir.file("tiny.xml"));
    atest::Translation t(adapter->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    const mbx_mechanism_summary s = t.summary();
    CHECK(s.part_count == 5);
    CHECK(s.revolute_count == 2);
    CHECK(s.rigid_body_count == 2);
    CHECK(s.dof == 2);
    CHECK(s.loop_count == 0);
    CHECK(t.count(MBX_FINDING_HOST_STATUS) == 1);

    uint32_t arm = 0;
    REQUIRE(mbx_mechanism_find_part(t.mechanism(), "12", &arm) == MBX_OK);
    const mbx_rigid_body_info r = t.rigid_body(arm);
    CHECK(std::string(r.name) == "ARM");
    const Eigen::Matrix3d rotation = row_major(r.pose.rotation);
    CHECK(rotation.isApprox(atest::tiny_arm_rotation(), 1e-9));
    CHECK_FALSE(rotation.isApprox(atest::tiny_arm_rotation().transpose(), 1e-3));
    CHECK(r.pose.position[0] == mbx_test::relative(0.1, 1e-6));  // mm -> m
    CHECK(r.mass == 2.5);
    // The centre of mass back in world: CG at (150, 20, 10) mm.
    const Eigen::Vector3d com_world =
        rotation * Eigen::Vector3d(r.com[0], r.com[1], r.com[2]) + Eigen::Vector3d(r.pose.position[0], 0, 0);
    CHECK(com_world.isApprox(Eigen::Vector3d(0.15, 0.02, 0.01), 1e-9));

    uint32_t link = 0;
    REQUIRE(mbx_mechanism_find_part(t.mechanism(), "SUB/31", &link) == MBX_OK);
    const mbx_rigid_body_info l = t.rigid_body(link);
    CHECK(l.mass == mbx_test::relative(2.20462 * 0.45359237, 1e-6));
    CHECK(l.inertia[0] == mbx_test::relative(20 * 0.45359237 * 0.0254 * 0.0254, 1e-6));

    // The missing files are host diagnostics with the XML's line.
    const std::vector<atest::FindingCopy> f = t.findings();
    size_t missing = 0;
    for (const atest::FindingCopy& x : f)
        if (x.code_name == "mesh_file_missing") {
            ++missing;
            CHECK(x.file == dir.file("tiny.xml"));
            if (x.subject_id == "12") CHECK(x.line == atest::line_of(text, "\"ARM.stl\""));
            if (x.subject_id == "SUB/31") CHECK(x.line == atest::line_of(text, "\"link.stl\""));
        }
    CHECK(missing == 2);
}

TEST_CASE("adapter: a mesh file found ignoring case loads only when asked, and its centroid is the CoM") {
    atest::TempDir dir;
    atest::write_file(dir.file("tiny.xml"), atest::tiny_pmxml());
    atest::write_file(dir.file("arm.STL"), arm_stl());
    const auto adapter = FileAdapter::open(dir.file("tiny.xml"));
    REQUIRE(adapter->mesh_files().size() == 1);
    CHECK(adapter->mesh_files().at("12") == dir.file("arm.STL"));
    CHECK(diagnostic(adapter->assembly(), "mesh_file_missing") != nullptr);  // link.stl
    CHECK(adapter->assembly().shapes.empty());

    {
        atest::Translation t(adapter->table(), 0);
        REQUIRE(t.status() == MBX_OK);
        CHECK(adapter->host().shape_requests().empty());  // translation alone loads nothing
        uint32_t arm = 0;
        REQUIRE(mbx_mechanism_find_part(t.mechanism(), "12", &arm) == MBX_OK);
        mbx_shape_stats st{};
        st.struct_size = sizeof st;
        REQUIRE(mbx_mechanism_get_shape_stats(t.context(), t.mechanism(), arm, &st) == MBX_OK);
        CHECK(st.mesh_count == 1);
        CHECK(st.vertex_count == 8);
        CHECK(st.triangle_count == 12);
        CHECK(adapter->host().shape_requests() == std::vector<std::string>{"12"});
    }
    {
        // With the mass check, the mesh (in CS1, mm) must sit on the CAD CoM:
        // column-major, CS1 placement and units end to end. A tolerance of
        // 0.01 mm leaves only rounding.
        atest::Translation t(adapter->table(), MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES, 1e-5);
        REQUIRE(t.status() == MBX_OK);
        CHECK(t.count(MBX_FINDING_MASS_MISMATCH) == 0);
        CHECK(t.count(MBX_FINDING_SHAPE_NOT_CLOSED) == 0);
        atest::TempDir out;
        t.write_report(out.file("r"));
        const std::string json = atest::read_file(out.file("r/report.json"));
        CHECK(json.find("\"centroid_mismatch_mm\"") != std::string::npos);
    }
    {
        // The same mesh against a row-major misreading of the file would be
        // centimetres off: build that file and see the check fire.
        std::string text = atest::tiny_pmxml();
        const std::string col = atest::orientation_text(atest::tiny_arm_rotation());
        const std::string row = atest::orientation_text(atest::tiny_arm_rotation().transpose());
        for (size_t at = text.find(col); at != std::string::npos; at = text.find(col, at + row.size()))
            text.replace(at, col.size(), row);
        atest::TempDir other;
        atest::write_file(other.file("tiny.xml"), text);
        atest::write_file(other.file("arm.stl"), arm_stl());
        const auto wrong = FileAdapter::open(other.file("tiny.xml"));
        atest::Translation t(wrong->table(), MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES, 1e-5);
        REQUIRE(t.status() == MBX_OK);
        CHECK(t.count(MBX_FINDING_MASS_MISMATCH) == 1);
    }
}

TEST_CASE("adapter: mesh files under --mesh-dir, unreadable ones are diagnostics") {
    atest::TempDir dir, meshes;
    const std::string text = atest::tiny_pmxml();
    atest::write_file(dir.file("tiny.xml"), text);
    atest::write_file(meshes.file("ARM.stl"), arm_stl());
    atest::write_file(meshes.file("LINK.stl"), std::string(200, '\x01'));
    FileAdapterOptions options;
    options.mesh_dirs.push_back(meshes.path.string());
    const auto adapter = FileAdapter::open(dir.file("tiny.xml"), options);
    CHECK(adapter->mesh_files().size() == 1);
    const mbx_memory::Diagnostic* d = diagnostic(adapter->assembly(), "mesh_file_unreadable");
    REQUIRE(d != nullptr);
    CHECK(d->subject_kind == MBX_SUBJECT_BODY);
    CHECK(d->subject_id == "SUB/31");
    CHECK(d->subject_name == "LINK");
    CHECK(d->file == dir.file("tiny.xml"));
    CHECK(d->line == atest::line_of(text, "\"link.stl\""));
    CHECK(diagnostic(adapter->assembly(), "mesh_file_missing") == nullptr);

    atest::Translation t(adapter->table(), MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES);
    REQUIRE(t.status() == MBX_OK);
    CHECK(t.count("mesh_file_unreadable") == 1);
    CHECK(t.mesh_total() == 1);
}

TEST_CASE("adapter: a mesh that passes the probe but breaks when loaded does not fail the translation") {
    atest::TempDir dir;
    atest::write_file(dir.file("tiny.xml"), atest::replace_once(atest::tiny_pmxml(), "\"ARM.stl\"", "\"ARM.obj\""));
    atest::write_file(dir.file("ARM.obj"), "v 1 2\nf 1 2 3 4 zz\n");
    const auto adapter = FileAdapter::open(dir.file("tiny.xml"));
    REQUIRE(adapter->mesh_files().size() == 1);
    atest::Translation t(adapter->table(), MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES);
    REQUIRE(t.status() == MBX_OK);
    const std::vector<mbx_memory::Diagnostic> late = adapter->late_diagnostics();
    REQUIRE(late.size() == 1);
    CHECK(late[0].code == "mesh_file_unreadable");
    CHECK(late[0].subject_id == "12");
    CHECK(t.mesh_total() == 0);
}

TEST_CASE("adapter: errors are FileErrors with the file and line") {
    atest::TempDir dir;
    const std::string text =
        atest::replace_once(atest::tiny_pmxml(), "<Frame ref=\"16000\"></Frame>", "<Frame ref=\"99\"></Frame>");
    atest::write_file(dir.file("tiny.xml"), text);
    try {
        FileAdapter::open(dir.file("tiny.xml"));
        FAIL("no error");
    } catch (const FileError& e) {
        CHECK(e.file() == dir.file("tiny.xml"));
        CHECK(e.line() == atest::line_of(text, "<Frame ref=\"99\">"));
    }
    atest::write_file(dir.file("good.xml"), atest::tiny_pmxml());
    FileAdapterOptions options;
    options.shapes_path = dir.file("none.wrl");
    CHECK_THROWS_AS(FileAdapter::open(dir.file("good.xml"), options), FileError);
    atest::write_file(dir.file("bad.wrl"), "#VRML V2.0 utf8\nTransform {\n  translation 1 2\n");
    options.shapes_path = dir.file("bad.wrl");
    try {
        FileAdapter::open(dir.file("good.xml"), options);
        FAIL("no error");
    } catch (const FileError& e) {
        CHECK(e.file() == dir.file("bad.wrl"));
        CHECK(e.line() >= 3);
        CHECK(std::string(e.what()).find(dir.file("bad.wrl") + ":" + dir.file("bad.wrl")) == std::string::npos);
    }
}

TEST_CASE("adapter: VRML shapes attach to bodies by pose, own mesh files win") {
    atest::TempDir dir;
    atest::write_file(dir.file("tiny.xml"), atest::tiny_pmxml());
    atest::write_file(dir.file("link.stl"),
                      atest::stl_ascii(atest::box_triangles(Eigen::Vector3d(50, 0, 0), Eigen::Vector3d(20, 20, 20))));
    // ARM has no mesh file here (ARM.stl is absent): its shape comes from the
    // scene, placed at ARM's CS1 pose; LINK's scene shape is dropped for its
    // own file; a shape far from every body is unmatched.
    const Eigen::AngleAxisd aa(atest::tiny_arm_rotation());
    const std::string rotation = atest::number_text(aa.axis().x()) + " " + atest::number_text(aa.axis().y()) + " " +
                                 atest::number_text(aa.axis().z()) + " " + atest::number_text(aa.angle());
    const std::string wrl =
        "#VRML V2.0 utf8\n"
        "DEF ARM_SHAPE Transform {\n"
        "  translation 100 0 0\n"
        "  rotation " +
        rotation +
        "\n"
        "  children [ Shape { geometry Box { size 30 12 8 } } ]\n"
        "}\n"
        "DEF LINK_SHAPE Transform {\n"
        "  translation 200 0 0\n"
        "  children [ Shape { geometry Box { size 20 20 20 } } ]\n"
        "}\n"
        "DEF STRAY Transform {\n"
        "  translation 5000 5000 5000\n"
        "  children [ Shape { geometry Box { size 1 1 1 } } ]\n"
        "}\n";
    atest::write_file(dir.file("scene.wrl"), wrl);
    FileAdapterOptions options;
    options.shapes_path = dir.file("scene.wrl");
    options.match.vrml_scale = 1;
    const auto adapter = FileAdapter::open(dir.file("tiny.xml"), options);
    const mbx_memory::Assembly& a = adapter->assembly();
    REQUIRE(a.shapes.count("12") == 1);
    REQUIRE(a.shapes.at("12").size() == 1);
    CHECK(a.shapes.count("SUB/31") == 0);  // served from link.stl instead
    CHECK(adapter->superseded_vrml_meshes() == 1);
    // ARM's box in ARM's frame: centred on the origin, edges along its axes.
    const mbx_memory::Mesh& m = a.shapes.at("12")[0];
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
    for (size_t i = 0; i < m.vertices.size(); i += 3) {
        const Eigen::Vector3d v(m.vertices[i], m.vertices[i + 1], m.vertices[i + 2]);
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    CHECK(hi.isApprox(Eigen::Vector3d(15, 6, 4), 1e-6));
    CHECK(lo.isApprox(Eigen::Vector3d(-15, -6, -4), 1e-6));

    const mbx_memory::Diagnostic* stray = diagnostic(a, "vrml_unmatched_shape");
    REQUIRE(stray != nullptr);
    CHECK(stray->severity == MBX_SEVERITY_WARNING);
    CHECK(stray->subject_id == "STRAY");
    CHECK(stray->file == dir.file("scene.wrl"));
    CHECK(stray->line == atest::line_of(wrl, "DEF STRAY"));
    CHECK(diagnostic(a, "mesh_file_missing") != nullptr);  // ARM.stl

    atest::Translation t(adapter->table(), MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES);
    REQUIRE(t.status() == MBX_OK);
    CHECK(t.count("vrml_unmatched_shape") == 1);
    CHECK(t.mesh_total() == 2);
}

TEST_CASE("adapter: a body's geometry file may be STEP: meshed in the body's unit on its CAD centre of mass") {
    // ARM's box as a CAD system would export it: a STEP part in its CS1 frame,
    // here in metres while the model's lengths are millimetres.
    const Eigen::Vector3d com_cs1_m = atest::tiny_arm_rotation().transpose() * Eigen::Vector3d(50, 20, 10) * 1e-3;
    const Eigen::Vector3d half_m = 0.5e-3 * Eigen::Vector3d(30, 12, 8);
    mbx_test::StepSolidWriter writer(mbx_test::StepUnit::Metre);
    writer.box(com_cs1_m - half_m, com_cs1_m + half_m);
    atest::TempDir dir;
    atest::write_file(dir.file("tiny.xml"), atest::replace_once(atest::tiny_pmxml(), "\"ARM.stl\"", "\"ARM.STEP\""));
    atest::write_file(dir.file("arm.step"), writer.file());
    const auto adapter = FileAdapter::open(dir.file("tiny.xml"));
    REQUIRE(adapter->mesh_files().count("12") == 1);
    CHECK(adapter->mesh_files().at("12") == dir.file("arm.step"));
    atest::Translation t(adapter->table(), MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES, 1e-5);
    REQUIRE(t.status() == MBX_OK);
    uint32_t arm = 0;
    REQUIRE(mbx_mechanism_find_part(t.mechanism(), "12", &arm) == MBX_OK);
    mbx_shape_stats st{};
    st.struct_size = sizeof st;
    REQUIRE(mbx_mechanism_get_shape_stats(t.context(), t.mechanism(), arm, &st) == MBX_OK);
    CHECK(st.mesh_count == 1);
    CHECK(st.triangle_count == 12);
    // Read as millimetres (or left in metres) the box would sit far from the CAD centre of mass.
    CHECK(t.count(MBX_FINDING_MASS_MISMATCH) == 0);
    CHECK(t.count(MBX_FINDING_SHAPE_NOT_CLOSED) == 0);
}

}  // namespace MBX_UNITY_ID
