// Colours from the host to the glTF scene (and so the view): a URDF's
// materials, named at the top or given in the visual, reach the meshes
// through mbx_mesh_desc.color (ABI 12), and the scene draws each body's parts
// in them, read back here by assimp's own glTF importer. A host colour that
// is no number in 0..1 is refused naming the part.
#include <array>
#include <map>
#include <string>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>
#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "host_adapters/memory/memory_host.h"
#include "host_adapters/urdf/urdf_adapter.h"
#include "tests/common/near.h"
#include "translation_support.h"

namespace MBX_UNITY_ID {
namespace {

// The diffuse colours (and opacity) of the meshes a node of the scene draws, by node name.
std::map<std::string, std::vector<std::array<float, 4>>> node_colours(const aiScene& scene) {
    std::map<std::string, std::vector<std::array<float, 4>>> out;
    std::vector<const aiNode*> stack{scene.mRootNode};
    while (!stack.empty()) {
        const aiNode* n = stack.back();
        stack.pop_back();
        for (unsigned i = 0; i < n->mNumChildren; ++i) stack.push_back(n->mChildren[i]);
        for (unsigned i = 0; i < n->mNumMeshes; ++i) {
            const aiMaterial* mat = scene.mMaterials[scene.mMeshes[n->mMeshes[i]]->mMaterialIndex];
            aiColor4D c(0, 0, 0, 1);
            REQUIRE(mat->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS);
            float opacity = 1;
            mat->Get(AI_MATKEY_OPACITY, opacity);
            out[n->mName.C_Str()].push_back({c.r, c.g, c.b, std::min(c.a, opacity)});
        }
    }
    return out;
}

bool has_colour(const std::vector<std::array<float, 4>>& list, std::array<float, 4> want) {
    for (const auto& c : list) {
        bool same = true;
        for (int k = 0; k < 4; ++k) same = same && std::fabs(c[size_t(k)] - want[size_t(k)]) < 1e-6;
        if (same) return true;
    }
    return false;
}

}  // namespace

TEST_CASE("urdf colours: named and inline materials colour the scene's meshes, a link without one stays grey") {
    atest::TempDir dir("mbx_urdf_colours");
    const std::string text = R"(<robot name="painted">
  <material name="red"><color rgba="1 0 0 1"/></material>
  <link name="base">
    <visual><geometry><box size="0.2 0.2 0.2"/></geometry><material name="red"/></visual>
  </link>
  <joint name="j" type="continuous"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.5"/></joint>
  <link name="arm">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <visual><geometry><cylinder radius="0.05" length="0.4"/></geometry><material name="blue"><color rgba="0 0 1 1"/></material></visual>
    <visual><origin xyz="0 0 0.3"/><geometry><sphere radius="0.08"/></geometry><material name="glass"><color rgba="0 1 0 0.5"/></material></visual>
  </link>
  <joint name="k" type="continuous"><parent link="arm"/><child link="hand"/><origin xyz="0 0 0.5"/></joint>
  <link name="hand">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>
  </link>
</robot>
)";
    atest::write_file(dir.file("painted.urdf"), text);
    const auto adapter = mbx_files::UrdfAdapter::open(dir.file("painted.urdf"));
    atest::Translation t(adapter->table(), 0);
    REQUIRE(t.status() == MBX_OK);
    mbx_export_options o{};
    o.struct_size = sizeof o;
    o.formats = MBX_EXPORT_MESHES;
    REQUIRE(mbx_mechanism_export(t.context(), t.mechanism(), &o, dir.file("out").c_str()) == MBX_OK);

    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(dir.file("out/scene.glb"), 0);
    REQUIRE_MESSAGE(scene, importer.GetErrorString());
    const auto colours = node_colours(*scene);
    // The base, fixed to the world, is the ground body's node.
    REQUIRE(colours.count("ground"));
    REQUIRE(colours.count("arm"));
    REQUIRE(colours.count("hand"));
    CHECK(colours.at("ground").size() == 1);
    CHECK(has_colour(colours.at("ground"), {1, 0, 0, 1}));
    // Two visuals in two colours: two primitives of the arm's node, the glass see-through.
    CHECK(colours.at("arm").size() == 2);
    CHECK(has_colour(colours.at("arm"), {0, 0, 1, 1}));
    CHECK(has_colour(colours.at("arm"), {0, 1, 0, 0.5f}));
    CHECK(has_colour(colours.at("hand"), {0.7f, 0.7f, 0.7f, 1}));
}

TEST_CASE("host colours: a component that is no number in 0..1 is refused naming the part") {
    mbx_memory::Assembly a;
    a.name = "painted";
    mbx_memory::Body ground;
    ground.id = ground.name = "ground";
    ground.flags = MBX_BODY_GROUND;
    ground.pose.rotation[0] = ground.pose.rotation[4] = ground.pose.rotation[8] = 1;
    a.bodies.push_back(ground);
    mbx_memory::Mesh tri;
    tri.name = "tri";
    tri.pose.rotation[0] = tri.pose.rotation[4] = tri.pose.rotation[8] = 1;
    tri.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    tri.triangles = {0, 1, 2};
    tri.color[0] = 1, tri.color[1] = 2, tri.color[2] = 0, tri.color[3] = 1;
    a.shapes["ground"].push_back(tri);
    mbx_memory::Host host(a);
    atest::Translation t(host.table(), 0);
    REQUIRE(t.status() == MBX_OK);
    mbx_shape_stats stats{};
    stats.struct_size = sizeof stats;
    CHECK(mbx_mechanism_get_shape_stats(t.context(), t.mechanism(), 0, &stats) != MBX_OK);
    const std::string error = mbx_context_last_error(t.context());
    CHECK(error.find("part 'ground'") != std::string::npos);
    CHECK(error.find("colour component that is not a number in 0..1 (component 1)") != std::string::npos);
}

}  // namespace MBX_UNITY_ID
