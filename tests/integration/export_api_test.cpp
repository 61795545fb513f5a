// mbx_mechanism_export through the plugin table, as a CAD host calls it:
// option checking, which files each format bit produces, all-or-nothing
// writes, the user model surviving a re-export, and export notes joining the
// mechanism's findings exactly once.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "support/plugin_fixture.h"
#include "support/temp_dir.h"
#include "../common/file_text.h"

namespace MBX_UNITY_ID {

using namespace itest;
namespace fs = std::filesystem;

namespace {

using mbx_test::read_file;

// Every regular file below `dir`, relative, sorted.
std::vector<std::string> tree_of(const fs::path& dir) {
    std::vector<std::string> out;
    if (!fs::exists(dir)) return out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) out.push_back(fs::relative(e.path(), dir).generic_string());
    std::sort(out.begin(), out.end());
    return out;
}

// `mesh` is an int, as a C host may store any value in the enum field.
mbx_status export_run(const Run& r, const fs::path& dir, uint32_t formats, int mesh = MBX_MESH_STL,
                      const char* name = "fourbar") {
    mbx_export_options o{};
    o.struct_size = sizeof o;
    o.formats = formats;
    std::memcpy(&o.mesh_format, &mesh, sizeof mesh);
    o.model_name = name;
    return api().mechanism_export(r.context.get(), r.get(), &o, dir.string().c_str());
}

bool any_starts_with(const std::vector<std::string>& files, const std::string& prefix) {
    return std::any_of(files.begin(), files.end(), [&](const std::string& f) { return f.rfind(prefix, 0) == 0; });
}

uint32_t count_code(const mbx_mechanism* m, mbx_finding_code code) {
    uint32_t n = 0;
    for (uint32_t i = 0; i < api().mechanism_finding_count(m); ++i) {
        mbx_finding f{};
        f.struct_size = sizeof f;
        REQUIRE(api().mechanism_get_finding(m, i, &f) == MBX_OK);
        n += f.code == code;
    }
    return n;
}

}  // namespace

TEST_CASE("export api: the plugin table carries mbx_mechanism_export (ABI 4)") {
    REQUIRE(api().abi_version >= 4);
    REQUIRE(api().struct_size >= offsetof(mbx_api, mechanism_export) + sizeof(void*));
    CHECK(bool(api().mechanism_export));
}

TEST_CASE("export api: each format bit writes its own files and only those") {
    const Run r = translate_builtin("fourbar");
    REQUIRE(r.status == MBX_OK);
    struct Case {
        uint32_t bits;
        const char* expected_prefix;
    };
    for (Case c : {Case{MBX_EXPORT_MODELICA, "modelica/"}, Case{MBX_EXPORT_MJCF, "mjcf/"},
                   Case{MBX_EXPORT_URDF, "urdf/"}, Case{MBX_EXPORT_MESHES, "meshes/"}}) {
        CAPTURE(c.expected_prefix);
        TempDir dir;
        REQUIRE(export_run(r, dir.path, c.bits) == MBX_OK);
        const auto files = tree_of(dir.path);
        CHECK(any_starts_with(files, c.expected_prefix));
        for (const char* other : {"modelica/", "mjcf/", "urdf/"})
            if (std::string(other) != c.expected_prefix) CHECK_FALSE(any_starts_with(files, other));
        // MJCF and URDF refer to STL meshes, so those come along; Modelica keeps its own copies.
        if (c.bits == MBX_EXPORT_MODELICA) CHECK_FALSE(any_starts_with(files, "meshes/"));
        if (c.bits == MBX_EXPORT_MJCF || c.bits == MBX_EXPORT_URDF) CHECK(any_starts_with(files, "meshes/"));
        CHECK((std::find(files.begin(), files.end(), "scene.glb") != files.end()) == (c.bits == MBX_EXPORT_MESHES));
        // No temporaries are left behind.
        for (const auto& f : files) CHECK(f.find(".tmp") == std::string::npos);
    }
}

TEST_CASE("export api: formats 0 means all, and a re-export is byte-identical") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    TempDir a, b;
    REQUIRE(export_run(r, a.path, 0, MBX_MESH_STL, "arm") == MBX_OK);
    REQUIRE(export_run(r, b.path, MBX_EXPORT_ALL, MBX_MESH_STL, "arm") == MBX_OK);
    const auto files = tree_of(a.path);
    REQUIRE(files == tree_of(b.path));
    for (const char* prefix : {"modelica/", "mjcf/", "urdf/", "meshes/"}) CHECK(any_starts_with(files, prefix));
    for (const auto& f : files) {
        CAPTURE(f);
        CHECK(read_file(a.path / f) == read_file(b.path / f));
    }
}

TEST_CASE("export api: the user's Modelica model survives a re-export") {
    const Run r = translate_builtin("fourbar");
    REQUIRE(r.status == MBX_OK);
    TempDir dir;
    REQUIRE(export_run(r, dir.path, MBX_EXPORT_MODELICA) == MBX_OK);
    fs::path user;
    for (const auto& f : tree_of(dir.path))
        if (f.size() > 12 && f.compare(f.size() - 12, 12, "UserModel.mo") == 0) user = dir.path / f;
    REQUIRE_FALSE(user.empty());
    const std::string edited = read_file(user) + "// my addition\n";
    { std::ofstream(user, std::ios::binary) << edited; }
    REQUIRE(export_run(r, dir.path, MBX_EXPORT_MODELICA) == MBX_OK);
    CHECK(read_file(user) == edited);
}

TEST_CASE("export api: bad options and paths are refused with a message, and nothing is written") {
    const Run r = translate_builtin("fourbar");
    REQUIRE(r.status == MBX_OK);
    TempDir dir;
    CHECK(export_run(r, dir.path, 1u << 9) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(api().context_last_error(r.context.get())).find("format") != std::string::npos);
    CHECK(export_run(r, dir.path, MBX_EXPORT_MJCF, 7) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(api().context_last_error(r.context.get())).find("mesh_format") != std::string::npos);
    CHECK(tree_of(dir.path).empty());
    CHECK(api().mechanism_export(r.context.get(), r.get(), nullptr, "") == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(api().mechanism_export(nullptr, r.get(), nullptr, dir.path.c_str()) == MBX_ERROR_INVALID_ARGUMENT);

    // The output directory cannot be created (a file is in the way): an I/O
    // error naming the path, and no partial export anywhere.
    const fs::path blocker = dir.path / "blocked";
    { std::ofstream(blocker) << "x"; }
    CHECK(export_run(r, blocker / "out", 0) == MBX_ERROR_IO);
    CHECK(std::string(api().context_last_error(r.context.get())).find("blocked") != std::string::npos);
    CHECK(tree_of(dir.path) == std::vector<std::string>{"blocked"});
}

TEST_CASE("export api: an older host's smaller options struct is read only as far as it goes") {
    const Run r = translate_builtin("fourbar");
    REQUIRE(r.status == MBX_OK);
    TempDir dir;
    mbx_export_options o{};
    o.struct_size = offsetof(mbx_export_options, mesh_format);  // knows only `formats`
    o.formats = MBX_EXPORT_URDF;
    const int beyond = 99;  // beyond its size: must be ignored
    std::memcpy(&o.mesh_format, &beyond, sizeof beyond);
    REQUIRE(api().mechanism_export(r.context.get(), r.get(), &o, dir.path.string().c_str()) == MBX_OK);
    const auto files = tree_of(dir.path);
    CHECK(any_starts_with(files, "urdf/model"));  // default model name
    CHECK(any_starts_with(files, "meshes/"));
}

TEST_CASE("export api: what a format cannot express joins the findings once, however often exported") {
    const Run r = translate_builtin("fourbar");  // a loop: URDF keeps the spanning tree
    REQUIRE(r.status == MBX_OK);
    CHECK(count_code(r.get(), MBX_FINDING_EXPORT_LOOPS_AS_TREE) == 0);
    TempDir dir;
    REQUIRE(export_run(r, dir.path, MBX_EXPORT_URDF) == MBX_OK);
    CHECK(count_code(r.get(), MBX_FINDING_EXPORT_LOOPS_AS_TREE) == 1);
    REQUIRE(export_run(r, dir.path, MBX_EXPORT_URDF) == MBX_OK);
    CHECK(count_code(r.get(), MBX_FINDING_EXPORT_LOOPS_AS_TREE) == 1);
    CHECK(std::string(api().finding_code_name(MBX_FINDING_EXPORT_LOOPS_AS_TREE)) == "export_loops_as_tree");
}

TEST_CASE("export api: mesh_format picks the meshes/ files, MJCF and URDF still get STL beside glTF") {
    const Run r = translate_builtin("fourbar");
    REQUIRE(r.status == MBX_OK);
    for (const auto& [format, ext] : std::vector<std::pair<mbx_mesh_format, std::string>>{
             {MBX_MESH_STL, ".stl"}, {MBX_MESH_OBJ, ".obj"}, {MBX_MESH_GLTF, ".glb"}}) {
        const std::string extension = ext;  // (C++17 lambdas, CAPTURE's among them, cannot capture a binding)
        CAPTURE(extension);
        TempDir only_meshes, with_models;
        REQUIRE(export_run(r, only_meshes.path, MBX_EXPORT_MESHES, format) == MBX_OK);
        std::set<std::string> exts;
        for (const auto& f : tree_of(only_meshes.path / "meshes")) exts.insert(fs::path(f).extension().string());
        CHECK(exts == std::set<std::string>{ext});
        REQUIRE(export_run(r, with_models.path, MBX_EXPORT_MESHES | MBX_EXPORT_MJCF, format) == MBX_OK);
        exts.clear();
        for (const auto& f : tree_of(with_models.path / "meshes")) exts.insert(fs::path(f).extension().string());
        const std::set<std::string> expected =
            format == MBX_MESH_GLTF ? std::set<std::string>{".glb", ".stl"} : std::set<std::string>{ext};
        CHECK(exts == expected);
    }
}
}  // namespace MBX_UNITY_ID
