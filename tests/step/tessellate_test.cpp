// Solids meshed closed, and their volume, centroid and inertia against
// OpenCASCADE's exact integrals (BRepGProp) on the real files.
#include <doctest/doctest.h>

#include <cstdio>
#include <string>

#include "core/geometry/mesh_properties.h"
#include "host_adapters/step/brep.h"
#include "host_adapters/step/part21.h"
#include "host_adapters/step/tessellate.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"
#include "tests/step/step_test_support.h"

namespace MBX_UNITY_ID {

using namespace mbx_step;

namespace {


}  // namespace

TEST_CASE("step tessellation: the DFKI levers meshed closed at the default tolerance, with OpenCASCADE's volume, centroid and inertia") {
    std::vector<std::string> files = {mbx_test::shared_data("step/dfki_double_pendulum/lever_200.STEP"),
                                      mbx_test::shared_data("step/dfki_double_pendulum/lever_300.STEP"),
                                      mbx_test::shared_data("step/dfki_double_pendulum/lever_400.STEP")};
    // Not yet (issue 24's remaining work): screw.step meshes to its volume within 6e-5 but leaves 46 open
    // edges where its helical faces meet themselves; linkrods.step (B-spline faces) closes but is 1e-3 short.
    for (const std::string& path : files) {
        CAPTURE(path);
        const Brep b = read_breps(read_part21_file(path));
        REQUIRE(b.solids.size() == 1);
        const std::vector<step_test::OracleSolid> exact = step_test::occt(path).solids;
        REQUIRE(exact.size() == 1);
        const Tolerance tol;  // the defaults: 1e-6 m, 1 degree
        const std::vector<SolidMesh> meshes = tessellate(b, tol);
        REQUIRE(meshes.size() == 1);
        const SolidMesh& m = meshes[0];
        for (const Problem& p : m.problems) FAIL_CHECK("#" << p.entity << ": " << p.message);
        std::vector<uint32_t> flat;
        for (const auto& t : m.mesh.triangles) flat.insert(flat.end(), t.begin(), t.end());
        const mbx::MeshClosure closure = mbx::check_closure(flat);
        CHECK(closure.closed);
        CHECK(closure.boundary_edges == 0);
        CHECK(closure.nonmanifold_edges == 0);
        mbx::SolidAccumulator acc;
        acc.add(m.mesh.points, flat);
        const mbx::SolidProperties props = acc.result();
        const double size = std::cbrt(exact[0].volume);
        MESSAGE(path << ": " << m.mesh.triangles.size() << " triangles, volume " << props.volume << " (OpenCASCADE "
                     << exact[0].volume << ", " << (props.volume / exact[0].volume - 1) << ")");
        CHECK(props.volume == mbx_test::relative(exact[0].volume, 1e-4));
        CHECK((props.centroid - exact[0].centroid).norm() == mbx_test::within(0, 1e-4 * size, "1e-4 of the solid's size"));
        CHECK((props.inertia_per_density - exact[0].inertia).norm() ==
              mbx_test::within(0, 1e-3 * exact[0].inertia.norm(), "1e-3 of the inertia"));
    }
}

}  // namespace MBX_UNITY_ID
