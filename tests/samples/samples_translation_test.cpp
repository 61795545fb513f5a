// Every committed sample through the file adapter and the C API, with the
// mass check on: the counts its README derives by hand, every VRML shape on
// the body it belongs to, every part's mass data consistent with its shapes.
#include <cmath>

#include <doctest/doctest.h>

#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "sample_expectations.h"
#include "temp_dir.h"
#include "translation.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace samples_test;

namespace {

std::map<std::string, size_t> meshes_by_body_name(const mbx_memory::Assembly& a) {
    std::map<std::string, size_t> out;
    for (const mbx_memory::Body& b : a.bodies) {
        auto it = a.shapes.find(b.id);
        if (it != a.shapes.end() && !it->second.empty()) out[b.name] += it->second.size();
    }
    return out;
}

void check_sample(const SampleExpectation& e) {
    const std::string dir = std::string(MBX_SAMPLES_DIR) + "/" + e.folder;
    mbx_files::FileAdapterOptions options;
    options.shapes_path = dir + "/" + e.wrl;
    std::unique_ptr<mbx_files::FileAdapter> adapter;
    try {
        adapter = mbx_files::FileAdapter::open(dir + "/" + e.xml, options);
    } catch (const std::exception& ex) {
        FAIL("cannot open " << e.folder << ": " << ex.what());
    }

    const mbx_files::MatchResult& m = adapter->matching();
    for (const auto& issue : m.issues) MESSAGE(issue.message);
    CHECK(m.issues.empty());
    CHECK(m.vrml_scale == mbx_test::relative(e.vrml_scale, 1e-6));
    CHECK(meshes_by_body_name(adapter->assembly()) == e.meshes);

    Translation t(adapter->table());
    REQUIRE_MESSAGE(t.ok(), t.error());
    const mbx_mechanism_summary s = t.summary();
    CHECK(s.part_count == e.parts);
    CHECK(s.rigid_body_count == e.rigid_bodies);
    CHECK(s.joint_node_count == e.joint_nodes);
    CHECK(s.joint_count == e.joints);
    CHECK(s.revolute_count == e.revolute);
    CHECK(s.prismatic_count == e.prismatic);
    CHECK(s.spherical_count == e.spherical);
    CHECK(s.weld_count == e.welds);
    CHECK(s.cut_joint_count == e.cut_joints);
    CHECK(s.loop_count == e.loops);
    CHECK(s.planar_loop_count == e.planar_loops);
    CHECK(s.dof == e.dof);
    CHECK(s.gruebler_dof == e.gruebler_dof);
    CHECK(s.redundant_constraint_count == e.redundant);
    CHECK(s.floating_body_count == 0);
    CHECK(s.error_count == 0);
    // All findings, exactly: no vrml_unmatched_shape / vrml_ambiguous_shape,
    // no mass_mismatch, no shape_not_closed, no rotation repair.
    const std::map<std::string, int> findings = t.finding_counts();
    if (findings != e.findings)
        for (const std::string& f : t.finding_messages()) MESSAGE(f);
    CHECK(findings == e.findings);

    // The mass check ran on every part with shapes (one per body with
    // meshes), found each CAD centre of mass on its mesh centroid, and the
    // mass is the density times the mesh volume.
    TempDir out("sample_report");
    const std::string json = t.report_json(out.path());
    REQUIRE(!json.empty());
    const std::vector<double> mismatch = json_numbers(json, "centroid_mismatch_mm");
    const std::vector<double> density = json_numbers(json, "density_kg_m3");
    CHECK(mismatch.size() == e.meshes.size());
    REQUIRE(density.size() == mismatch.size());
    for (size_t i = 0; i < mismatch.size(); ++i) {
        CHECK(mismatch[i] < 0.01);
        CHECK(density[i] == mbx_test::relative(e.density_kg_m3, 1e-5));
    }
}

}  // namespace

TEST_CASE("sample fourbar_imperial translates as its README says") { check_sample(sample_expectations()[0]); }
TEST_CASE("sample double_cardan translates as its README says") { check_sample(sample_expectations()[1]); }
TEST_CASE("sample five_axis_arm translates as its README says") { check_sample(sample_expectations()[2]); }
TEST_CASE("sample joints_showcase translates as its README says") { check_sample(sample_expectations()[3]); }
}  // namespace MBX_UNITY_ID
