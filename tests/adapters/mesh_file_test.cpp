// Mesh files: case-insensitive lookup, the open-time probe, loading with assimp.
#include <filesystem>
#include <string>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "host_adapters/common/mesh_file.h"
#include "stl_text.h"
#include "tests/common/step_solids.h"

namespace MBX_UNITY_ID {

using mbx_files::load_mesh_file;
using mbx_files::MeshFileFinder;
using mbx_files::probe_mesh_file;

TEST_CASE("mesh files: names match ignoring case, exact names first, in directory order") {
    atest::TempDir a, b;
    atest::write_file(a.file("sim_ecub_root_link_prt.stl"), "x");
    atest::write_file(b.file("Other.STL"), "x");
    atest::write_file(b.file("sim_ecub_root_link_prt.stl"), "x");
    std::filesystem::create_directories(b.path / "sub");
    atest::write_file((b.path / "sub" / "deep.stl").string(), "x");
    atest::write_file(a.file("Twin.stl"), "x");
    atest::write_file(a.file("twin.stl"), "x");

    MeshFileFinder finder({a.path.string(), b.path.string()});
    CHECK(finder.find("SIM_ECUB_ROOT_LINK_prt.stl") == a.file("sim_ecub_root_link_prt.stl"));
    CHECK(finder.find("other.stl") == b.file("Other.STL"));
    CHECK(finder.find("twin.stl") == a.file("twin.stl"));
    CHECK(finder.find("Twin.stl") == a.file("Twin.stl"));
    CHECK(finder.find("TWIN.STL") == a.file("Twin.stl"));  // sorted listing: 'T' < 't'
    CHECK(finder.find("sub\\DEEP.stl") == (b.path / "sub" / "deep.stl").string());
    CHECK(finder.find("missing.stl").empty());
    CHECK(finder.find("").empty());
    CHECK(finder.find(a.file("TWIN.STL")) == a.file("Twin.stl"));  // absolute
    // Cached listings: a file created later in a listed directory is not seen
    // under another case (the exact name still is).
    atest::write_file(a.file("Late.stl"), "x");
    CHECK(finder.find("Late.stl") == a.file("Late.stl"));
}

TEST_CASE("mesh files: the probe tells STL from junk") {
    atest::TempDir d;
    const auto box = atest::box_triangles(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6));
    std::string why;
    atest::write_file(d.file("a.stl"), atest::stl_ascii(box));
    CHECK(probe_mesh_file(d.file("a.stl"), why));
    atest::write_file(d.file("b.stl"), atest::stl_binary(box));
    CHECK(probe_mesh_file(d.file("b.stl"), why));
    // A binary STL whose header starts with "solid", as some exporters write.
    std::string tricky = atest::stl_binary(box);
    tricky.replace(0, 5, "solid");
    atest::write_file(d.file("c.stl"), tricky);
    CHECK(probe_mesh_file(d.file("c.stl"), why));

    atest::write_file(d.file("empty.stl"), "");
    CHECK_FALSE(probe_mesh_file(d.file("empty.stl"), why));
    CHECK(why.find("empty") != std::string::npos);
    atest::write_file(d.file("cut.stl"), atest::stl_ascii(box).substr(0, 400));
    CHECK_FALSE(probe_mesh_file(d.file("cut.stl"), why));
    CHECK(why.find("cut off") != std::string::npos);
    std::string short_binary = atest::stl_binary(box);
    short_binary.pop_back();
    atest::write_file(d.file("short.stl"), short_binary);
    CHECK_FALSE(probe_mesh_file(d.file("short.stl"), why));
    atest::write_file(d.file("other.obj"), "v 1 2 3\n");
    CHECK(probe_mesh_file(d.file("other.obj"), why));  // only STL is looked into
    atest::write_file(d.file("junk.stl"), std::string(300, '\x7f'));
    CHECK_FALSE(probe_mesh_file(d.file("junk.stl"), why));
    CHECK(why.find("neither") != std::string::npos);
    CHECK_FALSE(probe_mesh_file(d.file("none.stl"), why));
    CHECK(why.find("cannot open") != std::string::npos);
}

TEST_CASE("mesh files: loaded as is, corners welded so the box is closed") {
    atest::TempDir d;
    const auto box = atest::box_triangles(Eigen::Vector3d(10, 20, 30), Eigen::Vector3d(4, 5, 6));
    for (const std::string& name : {std::string("a.stl"), std::string("b.stl")}) {
        CAPTURE(name);
        atest::write_file(d.file(name), name == "a.stl" ? atest::stl_ascii(box) : atest::stl_binary(box));
        mbx_memory::Mesh mesh;
        std::string error;
        REQUIRE(load_mesh_file(d.file(name), mesh, error));
        CHECK(mesh.name == name);
        CHECK(mesh.vertices.size() == 8 * 3);  // 36 corners welded to 8
        CHECK(mesh.triangles.size() == 12 * 3);
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
        for (size_t i = 0; i < mesh.vertices.size(); i += 3) {
            const Eigen::Vector3d v(mesh.vertices[i], mesh.vertices[i + 1], mesh.vertices[i + 2]);
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
        }
        CHECK(lo.isApprox(Eigen::Vector3d(8, 17.5, 27)));  // no scaling, no frame change
        CHECK(hi.isApprox(Eigen::Vector3d(12, 22.5, 33)));
        const Eigen::Matrix3d r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(mesh.pose.rotation);
        CHECK(r.isIdentity());
    }
    mbx_memory::Mesh mesh;
    std::string error;
    // (Not a broken STL: assimp 5.2 leaks when its STL parser throws.)
    atest::write_file(d.file("broken.obj"), "v 1 2\nf 1 2 3 4 zz\n");
    CHECK_FALSE(load_mesh_file(d.file("broken.obj"), mesh, error));
    CHECK_FALSE(error.empty());
    atest::write_file(d.file("flat.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n");
    CHECK_FALSE(load_mesh_file(d.file("flat.ply"), mesh, error));
    CHECK(error.find("no triangles") != std::string::npos);
    CHECK_FALSE(load_mesh_file(d.file("missing.stl"), mesh, error));
}

TEST_CASE("mesh files: a STEP part is meshed in the body's length unit, and a broken one is a clear error") {
    atest::TempDir d;
    mbx_test::StepSolidWriter writer(mbx_test::StepUnit::Inch);  // the file's unit is not the body's
    writer.box(Eigen::Vector3d(0.010, 0.020, 0.030), Eigen::Vector3d(0.014, 0.025, 0.036));
    const std::string text = writer.file();
    atest::write_file(d.file("Part.STEP"), text);
    std::string why;
    CHECK(mbx_files::is_step_file(d.file("Part.STEP")));
    CHECK(probe_mesh_file(d.file("Part.STEP"), why));
    for (const double unit_m : {1e-3, 1.0}) {
        CAPTURE(unit_m);
        mbx_memory::Mesh mesh;
        std::string error;
        REQUIRE(load_mesh_file(d.file("Part.STEP"), mesh, error, unit_m));
        CHECK(mesh.name == "Part.STEP");
        CHECK(mesh.triangles.size() == 12 * 3);  // six planar faces, two triangles each
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
        for (size_t i = 0; i < mesh.vertices.size(); i += 3) {
            const Eigen::Vector3d v(mesh.vertices[i], mesh.vertices[i + 1], mesh.vertices[i + 2]);
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
        }
        // Inches in the file, the body's unit out: the same box.
        CHECK((lo * unit_m - Eigen::Vector3d(0.010, 0.020, 0.030)).norm() == mbx_test::within(0, 1e-15, "rounding"));
        CHECK((hi * unit_m - Eigen::Vector3d(0.014, 0.025, 0.036)).norm() == mbx_test::within(0, 1e-15, "rounding"));
    }
    atest::write_file(d.file("junk.stp"), "solid x\nfacet normal 0 0 1\n");
    CHECK_FALSE(probe_mesh_file(d.file("junk.stp"), why));
    CHECK(why.find("ISO-10303-21") != std::string::npos);
    // Cut off mid-file: refused naming the file and the line where it stops.
    atest::write_file(d.file("cut.step"), text.substr(0, text.size() / 2));
    mbx_memory::Mesh mesh;
    std::string error;
    CHECK_FALSE(load_mesh_file(d.file("cut.step"), mesh, error, 1e-3));
    CHECK(error.find("cut.step") != std::string::npos);
    // Well-formed but without any solid.
    atest::write_file(d.file("empty.step"), mbx_test::StepSolidWriter().file());
    CHECK_FALSE(load_mesh_file(d.file("empty.step"), mesh, error, 1e-3));
    CHECK(error.find("no solid") != std::string::npos);
}

}  // namespace MBX_UNITY_ID
