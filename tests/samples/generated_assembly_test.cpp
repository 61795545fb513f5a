// The synthetic PMXML + VRML generator: the counts it promises are the ones
// the SDK finds, every shape is matched and passes the mass check, and the
// output depends on the seed only.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <doctest/doctest.h>

#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "samples/tools/generate_pmxml.h"
#include "temp_dir.h"
#include "translation.h"

namespace MBX_UNITY_ID {

using namespace samples_test;

namespace {

std::string read_all(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void check_generated(size_t parts, mbx_samples::GeneratorOptions options) {
    TempDir dir("generated");
    REQUIRE(!dir.path().empty());
    options.parts = parts;
    const mbx_samples::GeneratedCounts c = mbx_samples::generate_pmxml(dir.path(), "gen", options);
    CHECK(c.parts == parts);

    mbx_files::FileAdapterOptions adapter_options;
    adapter_options.shapes_path = c.wrl_path;
    const auto adapter = mbx_files::FileAdapter::open(c.xml_path, adapter_options);
    const mbx_files::MatchResult& m = adapter->matching();
    CHECK(m.issues.empty());
    CHECK(m.meshes.size() == c.parts);  // one bar each
    CHECK(adapter->model().bodies.size() == c.parts + c.root_parts + 1);  // + RootGround
    CHECK(adapter->model().joints.size() == c.simple_joints);
    // What keeps matching unambiguous at any size: part frames far apart
    // compared with the matching tolerance (1e-4 of the assembly's extent).
    if (parts <= 2000) {
        std::vector<Eigen::Vector3d> frames;
        for (const mbx_files::PmxmlBody& b : adapter->model().bodies)
            if (!(b.flags & (MBX_BODY_GROUND | MBX_BODY_HELPER)))
                frames.push_back(adapter->model().frames[size_t(b.cs1)].position);
        double closest = INFINITY;
        for (size_t i = 0; i < frames.size(); ++i)
            for (size_t j = 0; j < i; ++j) closest = std::min(closest, (frames[i] - frames[j]).norm());
        if (frames.size() > 1) CHECK(closest >= 40 - 1e-3);
    }

    Translation t(adapter->table());
    REQUIRE_MESSAGE(t.ok(), t.error());
    const mbx_mechanism_summary s = t.summary();
    CHECK(s.part_count == c.parts + c.root_parts + 1);
    CHECK(s.rigid_body_count == c.rigid_bodies);
    CHECK(s.weld_count == c.welds);
    CHECK(s.revolute_count == c.revolutes);
    CHECK(s.joint_count == c.revolutes);
    CHECK(s.loop_count == c.loops);
    CHECK(s.planar_loop_count == c.loops);
    CHECK(s.dof == c.dof);
    CHECK(s.redundant_constraint_count == uint32_t(c.redundant));
    CHECK(s.floating_body_count == 0);
    CHECK(s.warning_count == 0);
    CHECK(s.error_count == 0);
    const std::map<std::string, int> findings = t.finding_counts();
    CHECK(findings.size() <= 1);
    if (c.loops > 0) CHECK(findings.at("planar_loop") == int(c.loops));
}

}  // namespace

TEST_CASE("generated assemblies translate to the counts the generator promises") {
    mbx_samples::GeneratorOptions options;
    SUBCASE("one part") { check_generated(1, options); }
    SUBCASE("a few parts") { check_generated(7, options); }
    SUBCASE("2000 parts, shared geometry files") { check_generated(2000, options); }
    SUBCASE("500 parts, geometry in place, 6 digits, small sub-assemblies") {
        options.inline_geometry = true;
        options.digits = 6;
        options.subsystem_size = 7;
        options.seed = 99;
        check_generated(500, options);
    }
}

TEST_CASE("the generator's output depends on the seed only") {
    TempDir a("gen_a"), b("gen_b"), c("gen_c");
    mbx_samples::GeneratorOptions options;
    options.parts = 300;
    options.seed = 5;
    const auto first = mbx_samples::generate_pmxml(a.path(), "g", options);
    const auto again = mbx_samples::generate_pmxml(b.path(), "g", options);
    options.seed = 6;
    const auto other = mbx_samples::generate_pmxml(c.path(), "g", options);
    CHECK(read_all(first.xml_path) == read_all(again.xml_path));
    CHECK(read_all(first.wrl_path) == read_all(again.wrl_path));
    CHECK(read_all(first.xml_path) != read_all(other.xml_path));
    CHECK(first.parts == other.parts);
}
}  // namespace MBX_UNITY_ID
