// Per-body mesh files, read back by assimp's importer and compared with the
// meshes the SDK loaded (triangles, float rounding only) and with the host's
// own box geometry (bounds of a body merged from several parts).
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>

#include "export_fixture.h"
#include "export/mesh/mesh_export.h"
#include "mesh_readback.h"
#include "tests/common/file_text.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using xmesh::Box;
using xmesh::host_world_vertices;

namespace {

size_t triangle_count(const std::vector<Mesh>& meshes) {
    size_t n = 0;
    for (const Mesh& m : meshes) n += m.triangles.size() / 3;
    return n;
}

const char* hint(mbx_mesh_format f) { return f == MBX_MESH_STL ? "stl" : f == MBX_MESH_OBJ ? "obj" : "glb"; }

}  // namespace

TEST_CASE("mesh files: one file per rigid body with geometry, holding its parts' triangles in the body frame") {
    for (const mbx_mesh_format format : {MBX_MESH_STL, MBX_MESH_OBJ, MBX_MESH_GLTF}) {
        CAPTURE(format);
        auto t = xtest::translate_builtin("six_axis_arm");
        const Mechanism& m = *t->mechanism;
        mbx_test::TempDir dir;
        ExportModel model = xtest::export_model(*t);
        OutputFiles files;
        export_body_meshes(model, format, files);
        write_output_files(dir.path.string(), files);

        size_t expected_files = 0;
        for (size_t b = 0; b < m.bodies.size(); ++b) {
            CAPTURE(m.bodies[b].name);
            const std::vector<Mesh>& source = t->body_shapes(int(b));
            if (triangle_count(source) == 0) {
                CHECK_FALSE(model.has_mesh(int(b)));
                continue;
            }
            ++expected_files;
            const std::string path = model.mesh_path(int(b), format);
            REQUIRE(xtest::find_file(files, path) != nullptr);
            const std::string bytes = mbx_test::read_file(dir.file(path));
            REQUIRE(bytes == xtest::find_file(files, path)->contents);
            const xmesh::ReadBack r = xmesh::read_back(bytes, hint(format));
            const auto got = xmesh::triangles(r.scene);
            const auto want = xmesh::source_triangles(source);
            REQUIRE(got.size() == want.size());
            CHECK(got.size() == triangle_count(source));
            // Every format stores float32: binary ones the values themselves,
            // OBJ text with 9 significant digits, which reads back to the same
            // float. So the only change allowed is the rounding to float.
            CHECK(xmesh::max_difference(got, want) == 0);
        }
        CHECK(files.size() == expected_files);
        CHECK(expected_files == 7);  // ground (pedestal), link1, link2 (3 parts), link3..6
    }
}

TEST_CASE("mesh files: binary STL header names the mesh and the triangle count matches the size") {
    auto t = xtest::translate_builtin("six_axis_arm");
    ExportModel model = xtest::export_model(*t);
    OutputFiles files;
    export_body_meshes(model, MBX_MESH_STL, files);
    REQUIRE(!files.empty());
    for (size_t b = 0; b < t->mechanism->bodies.size(); ++b) {
        if (!model.has_mesh(int(b))) continue;
        const std::string& bytes = xtest::find_file(files, model.mesh_path(int(b), MBX_MESH_STL))->contents;
        REQUIRE(bytes.size() >= 84);
        const std::string header(bytes.data(), 80);
        const std::string expected = "mbx " + model.mesh_stem(int(b));
        CHECK(header.substr(0, expected.size()) == expected);
        CHECK(header.find_first_not_of('\0', expected.size()) == std::string::npos);
        uint32_t n = 0;
        std::memcpy(&n, bytes.data() + 80, 4);
        CHECK(n == triangle_count(t->body_shapes(int(b))));
        CHECK(bytes.size() == 84 + 50 * size_t(n));
    }
}

TEST_CASE("mesh files: a body welded from several parts gets the union of their boxes, in metres, body frame") {
    mbx_memory::Assembly host;
    REQUIRE(mbx_stub::builtin_assembly("six_axis_arm", host));
    auto t = xtest::translate_builtin("six_axis_arm");
    const Mechanism& m = *t->mechanism;
    int merged = -1;
    for (size_t b = 0; b < m.bodies.size(); ++b)
        if (m.bodies[b].parts.size() == 3) merged = int(b);
    REQUIRE(merged >= 0);

    // Expected: every host vertex of the three parts, taken into the rigid
    // body's frame (its world pose at the assembly configuration).
    Box want;
    const Pose to_body = m.bodies[size_t(merged)].pose.inverse();
    size_t host_parts_with_meshes = 0;
    for (int p : m.bodies[size_t(merged)].parts) {
        const std::vector<Vec3> world = host_world_vertices(host, m.assembly.parts[size_t(p)].id);
        host_parts_with_meshes += !world.empty();
        for (const Vec3& v : world) want.add(to_body.apply(v));
    }
    REQUIRE(host_parts_with_meshes == 3);

    for (const mbx_mesh_format format : {MBX_MESH_STL, MBX_MESH_OBJ, MBX_MESH_GLTF}) {
        CAPTURE(format);
        ExportModel model = xtest::export_model(*t);
        OutputFiles files;
        export_body_meshes(model, format, files);
        const OutputFile* f = xtest::find_file(files, model.mesh_path(merged, format));
        REQUIRE(f != nullptr);
        const xmesh::ReadBack r = xmesh::read_back(f->contents, hint(format));
        Box got;
        for (const xmesh::Triangle& tri : xmesh::triangles(r.scene))
            for (int k = 0; k < 3; ++k) got.add(Vec3(tri[size_t(3 * k)], tri[size_t(3 * k + 1)], tri[size_t(3 * k + 2)]));
        // float32 storage of coordinates below 1 m.
        CHECK((got.lo - want.lo).cwiseAbs().maxCoeff() < 1e-6);
        CHECK((got.hi - want.hi).cwiseAbs().maxCoeff() < 1e-6);
        // The union is strictly larger than any single part's box.
        CHECK((want.hi - want.lo).norm() > 0.6);
    }
}

TEST_CASE("mesh files: re-export gives byte-identical STL, OBJ, glTF and scene files") {
    // Two independent translations and exports, so nothing (pointers,
    // caches, allocation order) is shared between the runs.
    OutputFiles runs[2];
    for (OutputFiles& out : runs) {
        auto t = xtest::translate_builtin("six_axis_arm");
        ExportModel model = xtest::export_model(*t);
        for (const mbx_mesh_format f : {MBX_MESH_STL, MBX_MESH_OBJ, MBX_MESH_GLTF}) export_body_meshes(model, f, out);
        export_scene(model, out);
    }
    REQUIRE(runs[0].size() == runs[1].size());
    REQUIRE(runs[0].size() == 3 * 7 + 1);
    for (size_t i = 0; i < runs[0].size(); ++i) {
        CAPTURE(runs[0][i].path);
        CHECK(runs[0][i].path == runs[1][i].path);
        CHECK(runs[0][i].contents == runs[1][i].contents);
    }
}

TEST_CASE("mesh files: bodies without triangles are skipped") {
    auto t = xtest::translate_builtin("six_axis_arm");
    const Mechanism& m = *t->mechanism;
    // The same mechanism, but one body's geometry is an empty mesh and
    // another's has vertices and no triangles.
    std::vector<std::vector<Mesh>> shapes(m.bodies.size());
    for (size_t b = 0; b < m.bodies.size(); ++b) shapes[b] = t->body_shapes(int(b));
    int emptied = -1, hollow = -1;
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        if (shapes[b].empty()) continue;
        if (emptied < 0) {
            emptied = int(b);
            for (Mesh& mesh : shapes[b]) mesh.triangles.clear(), mesh.vertices.clear();
        } else if (hollow < 0) {
            hollow = int(b);
            for (Mesh& mesh : shapes[b]) mesh.triangles.clear();
        }
    }
    REQUIRE(hollow >= 0);
    ExportModel model(m, [&](int b) -> const std::vector<Mesh>& { return shapes[size_t(b)]; }, ExportSettings{});
    OutputFiles files;
    export_body_meshes(model, MBX_MESH_STL, files);
    export_scene(model, files);
    CHECK_FALSE(model.has_mesh(emptied));
    CHECK_FALSE(model.has_mesh(hollow));
    CHECK(files.size() == 5 + 1);
    for (const OutputFile& f : files) CHECK(f.contents.size() > 84);

    // encode_mesh cannot skip: it refuses an empty mesh list.
    CHECK_THROWS_AS(encode_mesh(shapes[size_t(emptied)], "empty", MBX_MESH_STL), Error);
}

TEST_CASE("mesh files: a non-finite vertex or a bad index never reaches a file, the error names the body") {
    auto t = xtest::translate_builtin("six_axis_arm");
    const Mechanism& m = *t->mechanism;
    int victim = -1;
    for (size_t b = 0; b < m.bodies.size(); ++b)
        if (victim < 0 && !t->body_shapes(int(b)).empty()) victim = int(b);
    REQUIRE(victim >= 0);
    const std::string name = m.bodies[size_t(victim)].name;

    const double bad_values[] = {std::nan(""), std::numeric_limits<double>::infinity(), 1e300 /* overflows float */};
    for (const double bad : bad_values) {
        CAPTURE(bad);
        std::vector<Mesh> broken = t->body_shapes(victim);
        broken.back().vertices.back().y() = bad;
        ExportModel model(m, [&](int b) -> const std::vector<Mesh>& {
            return b == victim ? broken : t->body_shapes(b);
        }, ExportSettings{});
        for (const mbx_mesh_format f : {MBX_MESH_STL, MBX_MESH_OBJ, MBX_MESH_GLTF}) {
            OutputFiles files;
            try {
                export_body_meshes(model, f, files);
                FAIL("export accepted a non-finite vertex");
            } catch (const Error& e) {
                CHECK(e.status() == MBX_ERROR_INVALID_INPUT);
                CHECK(std::string(e.what()).find("'" + name + "'") != std::string::npos);
                CHECK(e.subject().kind == MBX_SUBJECT_RIGID_BODY);
                CHECK(e.subject().name == name);
            }
            OutputFiles scene;
            CHECK_THROWS_AS(export_scene(model, scene), Error);
            CHECK(scene.empty());
        }
        CHECK_THROWS_AS(encode_mesh(broken, "x", MBX_MESH_STL), Error);
    }

    std::vector<Mesh> bad_index = t->body_shapes(victim);
    bad_index.front().triangles.back() = uint32_t(bad_index.front().vertices.size());
    try {
        encode_mesh(bad_index, "bad_index", MBX_MESH_GLTF);
        FAIL("encode_mesh accepted an index past the vertices");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("bad_index") != std::string::npos);
    }
}

TEST_CASE("mesh files: encode_mesh writes a plain triangle exactly") {
    Mesh tri;
    tri.name = "tri";
    tri.vertices = {Vec3(0, 0, 0), Vec3(0.25, 0, 0), Vec3(0, 0.5, 0.125)};
    tri.triangles = {0, 1, 2};
    for (const mbx_mesh_format format : {MBX_MESH_STL, MBX_MESH_OBJ, MBX_MESH_GLTF}) {
        CAPTURE(format);
        const std::string bytes = encode_mesh({tri}, "tri", format);
        const xmesh::ReadBack r = xmesh::read_back(bytes, hint(format));
        const auto got = xmesh::triangles(r.scene);
        REQUIRE(got.size() == 1);
        CHECK(xmesh::max_difference(got, xmesh::source_triangles({tri})) == 0);
    }
    const std::string glb = encode_mesh({tri}, "tri", MBX_MESH_GLTF);
    CHECK(glb.compare(0, 4, "glTF") == 0);  // one self-contained binary glTF
}

TEST_CASE("mesh files: concurrent encodes (one assimp Exporter each) give the single-threaded bytes") {
    auto t = xtest::translate_builtin("six_axis_arm");
    const std::vector<Mesh>& source = t->body_shapes(2);  // link 2: three parts
    REQUIRE(!source.empty());
    const mbx_mesh_format formats[] = {MBX_MESH_STL, MBX_MESH_OBJ, MBX_MESH_GLTF};
    std::string reference[3];
    for (int f = 0; f < 3; ++f) reference[f] = encode_mesh(source, "link2", formats[f]);
    std::vector<std::string> results(4 * 3);
    std::vector<std::thread> threads;
    for (int k = 0; k < 4; ++k)
        threads.emplace_back([&, k] {
            for (int round = 0; round < 5; ++round)
                for (int f = 0; f < 3; ++f) results[size_t(3 * k + f)] = encode_mesh(source, "link2", formats[f]);
        });
    for (std::thread& th : threads) th.join();
    for (size_t i = 0; i < results.size(); ++i) CHECK(results[i] == reference[i % 3]);
}
}  // namespace MBX_UNITY_ID
