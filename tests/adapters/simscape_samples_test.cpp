// The Simscape twins of the PMXML samples (samples/<name>/simscape/): the
// four-bar with its loop, the double cardan's nested sub-assembly and the
// arm's rigid sub-assembly arrive through the Simscape adapter as the same
// mechanisms their PMXML + VRML files give; their STEP parts are, by
// OpenCASCADE's integrals, the solids their mass properties describe; and a
// part with three products of inertia shows the order and sign of the file's
// six numbers against OpenCASCADE.
#include <cmath>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "host_adapters/inputs/input_formats.h"
#include "host_adapters/simscape/data_units_inference.h"
#include "host_adapters/simscape/simscape_adapter.h"
#include "host_adapters/simscape/simscape_reader.h"
#include "mechanism_dynamics.h"
#include "samples/tools/step_writer.h"
#include "tests/common/near.h"
#include "tests/step/step_test_support.h"
#include "translation_support.h"

namespace MBX_UNITY_ID {
namespace {

struct Twin {
    const char* folder;
    const char* stem;
    uint32_t nv;
    // The PMXML sample's numbers have this many significant digits (the
    // Simscape twin's ten), so the two mechanisms agree to about this.
    double tolerance;
};

// The double cardan's torques are about 1e-4 N m: on its balanced shafts
// gravity's terms from forces of 15 N cancel to that, and carry the PMXML's
// rounding of positions near 0.5 m at ten digits (5e-11 m), 1e-6 of it.
const Twin kTwins[] = {{"fourbar_imperial", "fourbar", 3, 2e-5},
                       {"double_cardan", "double_cardan", 5, 1e-6},
                       {"five_axis_arm", "five_axis_arm", 5, 1e-8}};

std::string sample_path(const Twin& t, bool simscape) {
    return std::string(MBX_SAMPLES_DIR) + "/" + t.folder + (simscape ? "/simscape/" : "/") + t.stem + ".xml";
}

bool has_code(const std::vector<atest::FindingCopy>& findings, const std::string& code) {
    for (const atest::FindingCopy& f : findings)
        if (f.code_name == code) return true;
    return false;
}

}  // namespace

TEST_CASE("simscape samples: the four-bar's loop, the double cardan's nested sub-assembly and the arm's rigid sub-assembly give the mechanisms of their PMXML samples") {
    for (const Twin& twin : kTwins) {
        const std::string folder = twin.folder;
        CAPTURE(folder);
        mbx_files::FileInputOptions pmxml_options;
        pmxml_options.shapes_path = std::string(MBX_SAMPLES_DIR) + "/" + twin.folder + "/" + twin.stem + "_a.wrl";
        const auto pmxml = mbx_files::open_input(sample_path(twin, false), pmxml_options);
        const auto simscape = mbx_files::open_input(sample_path(twin, true));
        REQUIRE(dynamic_cast<const mbx_files::SimscapeAdapter*>(simscape.get()) != nullptr);

        const atest::Translation from_pmxml(pmxml->table(), 0), from_simscape(simscape->table(), 0);
        REQUIRE(from_pmxml.status() == MBX_OK);
        REQUIRE(from_simscape.status() == MBX_OK);
        const mbx_mechanism_summary a = from_pmxml.summary(), b = from_simscape.summary();
        CHECK(b.rigid_body_count == a.rigid_body_count);
        CHECK(b.joint_count == a.joint_count);
        CHECK(b.revolute_count == a.revolute_count);
        CHECK(b.redundant_constraint_count == a.redundant_constraint_count);
        CHECK(b.cut_joint_count == a.cut_joint_count);
        CHECK(b.loop_count == a.loop_count);
        CHECK(b.dof == a.dof);
        // Every part's STEP file was found, meshed closed and centred on its mass properties.
        const std::vector<atest::FindingCopy> findings = from_simscape.findings();
        for (const atest::FindingCopy& f : findings) CAPTURE(f.code_name + ": " + f.message);
        CHECK_FALSE(has_code(findings, "mesh_file_missing"));
        CHECK_FALSE(has_code(findings, "mesh_file_unreadable"));
        CHECK_FALSE(has_code(findings, "shape_not_closed"));
        CHECK_FALSE(has_code(findings, "mass_mismatch"));

        atest::check_same(atest::dynamics(simscape->table(), twin.nv), atest::dynamics(pmxml->table(), twin.nv),
                          twin.tolerance);
    }
}

TEST_CASE("simscape samples: each part's mass properties are OpenCASCADE's integrals of its STEP file") {
    for (const Twin& twin : kTwins) {
        const std::string folder = twin.folder;
        CAPTURE(folder);
        const std::string path = sample_path(twin, true);
        const mbx_files::SimscapeModel m = mbx_files::read_simscape(path);
        double density = 0;
        for (const mbx_files::SimscapePart& p : m.parts) {
            CAPTURE(p.name);
            const std::string step = path.substr(0, path.rfind('/') + 1) + p.geometry_file;
            const step_test::Oracle o = step_test::occt(step);
            REQUIRE(!o.solids.empty());
            // A part of several disjoint solids: their volumes, centroid and
            // inertia about the common centroid.
            double volume = 0;
            Eigen::Vector3d moment = Eigen::Vector3d::Zero();
            for (const step_test::OracleSolid& s : o.solids) {
                volume += s.volume;
                moment += s.volume * s.centroid;
            }
            const Eigen::Vector3d centroid = moment / volume;
            Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
            for (const step_test::OracleSolid& s : o.solids) {
                const Eigen::Vector3d d = s.centroid - centroid;
                inertia += s.inertia + s.volume * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
            }
            const double mass = p.mass * m.mass_to_kg, l = m.length_to_m;
            // One material per sample: every part's mass over its volume is the same density.
            if (density == 0) density = mass / volume;
            CHECK(mass / volume == mbx_test::relative(density, 1e-8));
            for (int k = 0; k < 3; ++k)
                CHECK(p.com[k] * l == mbx_test::within(centroid[k], 1e-9 * std::sqrt(inertia.trace() / volume), "10 digits"));
            const Eigen::Matrix3d read = p.inertia * m.mass_to_kg * l * l;
            const double scale = density * inertia.norm();
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) {
                    CAPTURE(r);
                    CAPTURE(c);
                    CHECK(read(r, c) == mbx_test::within(density * inertia(r, c), 1e-8 * scale, "10 digits"));
                }
        }
    }
}

TEST_CASE("simscape: a part with three products of inertia, its six numbers written in the exporters' order from OpenCASCADE's integrals, is the body of that inertia") {
    // A parallelepiped sheared along all three axes and off its frame's
    // origin: every product of inertia differs from the others and from zero.
    mbx_samples::Solid solid = mbx_samples::box(Eigen::Vector3d(0.08, 0.05, 0.03));
    Eigen::Matrix3d shear;
    shear << 1, 0.4, -0.3, 0.2, 1, 0.5, -0.6, 0.1, 1;
    for (Eigen::Vector3d& v : solid.vertices) v = shear * v + Eigen::Vector3d(0.01, -0.02, 0.005);
    atest::TempDir dir("mbx_simscape_products");
    mbx_samples::write_step_part(dir.file("skewed.step"), "SKEWED", {solid}, mbx_samples::step_millimetre());
    const step_test::Oracle o = step_test::occt(dir.file("skewed.step"));
    REQUIRE(o.solids.size() == 1);
    const step_test::OracleSolid& s = o.solids[0];
    CHECK(o.faces == 6);
    const double density = 7850;
    const Eigen::Matrix3d I = density * s.inertia;
    REQUIRE(std::abs(I(0, 1)) > 1e-3 * I.norm());
    REQUIRE(std::abs(I(0, 2)) > 1e-3 * I.norm());
    REQUIRE(std::abs(I(1, 2)) > 1e-3 * I.norm());

    // Written as the exporters do: Ixx Iyy Izz Iyz Izx Ixy, products as tensor entries.
    char numbers[400];
    std::snprintf(numbers, sizeof numbers,
                  "<Mass>%.17g</Mass><CenterOfMass>%.17g %.17g %.17g</CenterOfMass>"
                  "<Inertia>%.17g %.17g %.17g %.17g %.17g %.17g</Inertia>",
                  density * s.volume, s.centroid.x(), s.centroid.y(), s.centroid.z(), I(0, 0), I(1, 1), I(2, 2), I(1, 2),
                  I(2, 0), I(0, 1));
    const std::string xml =
        std::string("<SimscapeMultibodyImportXML version=\"2.0\"><DataUnits length=\"meter\" mass=\"kilogram\"/>"
                    "<RootAssembly name=\"r\" uid=\"R\"><InstanceTree><Instance entityUid=\"P\" name=\"p\" uid=\"I\">"
                    "<Transform><Rotation>1 0 0 0 1 0 0 0 1</Rotation><Translation>0 0 0</Translation></Transform>"
                    "</Instance></InstanceTree><Joints/></RootAssembly><Parts><Part name=\"skewed\" uid=\"P\">"
                    "<MassProperties>") +
        numbers + "</MassProperties><GeometryFile name=\"skewed.step\" type=\"STEP\"/></Part></Parts>"
                  "</SimscapeMultibodyImportXML>";
    atest::write_file(dir.file("skewed.xml"), xml);
    const auto adapter = mbx_files::SimscapeAdapter::open(dir.file("skewed.xml"));
    const mbx_memory::Assembly& a = adapter->assembly();
    REQUIRE(a.bodies.size() == 1);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) CHECK(a.bodies[0].inertia[3 * r + c] == mbx_test::relative(I(r, c), 1e-15));

    // And mbx's own mesh of the STEP file gives the same solid: centred on the
    // centre of mass, the density of the mass properties.
    const atest::Translation t(adapter->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    const std::vector<atest::FindingCopy> findings = t.findings();
    CHECK_FALSE(has_code(findings, "mass_mismatch"));
    CHECK_FALSE(has_code(findings, "mesh_file_missing"));
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {
namespace {

// A box of edges a, b, c (m) of density rho (kg/m^3), its mass properties
// written in a length unit of `unit_m` metres and a mass unit of `unit_kg`.
mbx_files::UnitEvidence box_evidence(double a, double b, double c, double rho, double unit_m, double unit_kg) {
    mbx_files::UnitEvidence e;
    e.part_name = "box";
    e.volume = a * b * c;
    e.inertia_per_density = e.volume / 12 * Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b).asDiagonal();
    e.mass = rho * e.volume / unit_kg;
    e.inertia = rho * e.inertia_per_density / (unit_kg * unit_m * unit_m);
    return e;
}

}  // namespace

TEST_CASE("simscape units without DataUnits: the parts' STEP solids tell the length by the radius of gyration and the mass by the density") {
    struct Case {
        double unit_m, unit_kg, rho;
        const char *length, *mass;
    };
    for (const Case& c : {Case{1e-3, 1, 2700, "millimetres", "kilograms"}, Case{0.0254, 0.45359237, 7850, "inches", "pounds"},
                          Case{1, 1, 1200, "metres", "kilograms"}, Case{1e-2, 1e-3, 8700, "centimetres", "grams"},
                          Case{0.3048, 0.45359237, 4430, "feet", "pounds"}}) {
        CAPTURE(c.length);
        // Three parts of different shapes and sizes, one of them 10 % denser than the rest.
        const std::vector<mbx_files::UnitEvidence> evidence = {box_evidence(0.3, 0.02, 0.04, c.rho, c.unit_m, c.unit_kg),
                                                               box_evidence(0.05, 0.05, 0.05, 1.1 * c.rho, c.unit_m, c.unit_kg),
                                                               box_evidence(0.12, 0.2, 0.01, c.rho, c.unit_m, c.unit_kg)};
        // ModelUnits that say something else do not sway it.
        const mbx_files::InferredUnits u = mbx_files::infer_data_units(evidence, "inch", "lbm");
        CHECK(u.from_geometry);
        CHECK(u.length_to_m == c.unit_m);
        CHECK(u.mass_to_kg == c.unit_kg);
        CHECK(u.reason.find(std::string(c.length) + " and " + c.mass) != std::string::npos);
        CHECK(u.reason.find("'inch' and 'lbm'") != std::string::npos);
    }
    // Nothing to tell by, or mass properties that fit no length unit: metres and kilograms, said so.
    const mbx_files::InferredUnits none = mbx_files::infer_data_units({}, "", "");
    CHECK_FALSE(none.from_geometry);
    CHECK(none.length_to_m == 1);
    CHECK(none.reason.find("no part with mass properties and a readable STEP file") != std::string::npos);
    const mbx_files::InferredUnits odd = mbx_files::infer_data_units({box_evidence(0.1, 0.2, 0.3, 2700, 0.5, 1)}, "", "");
    CHECK_FALSE(odd.from_geometry);
    CHECK(odd.length_to_m == 1);
    CHECK(odd.reason.find("fit no length unit") != std::string::npos);
    CHECK(odd.reason.find("0.5 m per unit") != std::string::npos);
}

TEST_CASE("simscape units without DataUnits: the four-bar's twin in inches and pounds, its DataUnits taken away, is the same mechanism") {
    const std::string dir = std::string(MBX_SAMPLES_DIR) + "/fourbar_imperial/simscape";
    std::string text = atest::read_file(dir + "/fourbar.xml");
    const size_t at = text.find("   <DataUnits");
    REQUIRE(at != std::string::npos);
    text.erase(at, text.find('\n', at) + 1 - at);
    atest::TempDir tmp("mbx_simscape_no_units");
    atest::write_file(tmp.file("fourbar.xml"), text);
    mbx_files::FileInputOptions o;
    o.mesh_dirs.push_back(dir);
    const auto bare = mbx_files::SimscapeAdapter::open(tmp.file("fourbar.xml"), o);
    const auto written = mbx_files::SimscapeAdapter::open(dir + "/fourbar.xml");
    CHECK(bare->model().length_to_m == 0.0254);
    CHECK(bare->model().mass_to_kg == 0.45359237);
    bool said = false;
    for (const mbx_memory::Diagnostic& d : bare->model().diagnostics)
        if (d.code == "simscape_no_data_units") {
            said = true;
            CHECK(d.message.find("inches and pounds") != std::string::npos);
            CHECK(d.message.find("3 parts' STEP solids") != std::string::npos);
        }
    CHECK(said);
    atest::check_same(atest::dynamics(bare->table(), 3), atest::dynamics(written->table(), 3), 1e-12);
    // The shapes read to tell the units are the shapes the translation gets: centred on the mass properties.
    const atest::Translation t(bare->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    const std::vector<atest::FindingCopy> findings = t.findings();
    CHECK_FALSE(has_code(findings, "mass_mismatch"));
    CHECK(has_code(findings, "simscape_no_data_units"));
}

}  // namespace MBX_UNITY_ID
