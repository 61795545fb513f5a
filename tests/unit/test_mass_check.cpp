#include <doctest/doctest.h>

#include "core/assembly/shape_loader.h"
#include "assembly_builder.h"
#include "core/translator/translate.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// Closed box mesh (outward normals) with half extents h centred at c, in the body frame.
Mesh box(const std::string& part, const Vec3& c, const Vec3& h) {
    Mesh m;
    m.name = part + "_box";
    m.part_id = part;
    for (int i = 0; i < 8; ++i)
        m.vertices.push_back(c + Vec3((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z()));
    m.triangles = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    return m;
}

struct Run {
    std::unique_ptr<Mechanism> m;
    int fetches = 0;
};

// A grounded 2.7 kg aluminium-like block (0.1 x 0.1 x 0.1 m) on a revolute;
// its CAD centre of mass is `com` in its own frame, its mesh is centred at 0.
Run run(const Vec3& com, bool open_mesh = false) {
    test::AssemblyBuilder b;
    int g = b.part("ground", 1, Vec3::Zero(), MBX_BODY_GROUND);
    int block = b.part("block", 2.7, Vec3(1, 0, 0), 0, test::rot_z(0.7), Vec3(0.0045, 0.0045, 0.0045).asDiagonal(), com);
    b.revolute("hinge", g, block, Vec3(1, 0, 0));
    std::vector<Mesh> none, meshes;
    Run r;
    TranslateOptions o;
    o.check_mass_with_shapes = true;
    Progress progress;
    r.m = translate_assembly(b.a, {}, o, progress, [&](const Mechanism& m, int body) -> const std::vector<Mesh>& {
        ++r.fetches;
        if (m.bodies[size_t(body)].name != "block") return none;
        meshes = {box("block", Vec3::Zero(), Vec3(0.05, 0.05, 0.05))};
        if (open_mesh) meshes[0].triangles.resize(meshes[0].triangles.size() - 3);
        return meshes;
    });
    return r;
}

int count(const Mechanism& m, mbx_finding_code code) {
    int n = 0;
    for (const Finding& f : m.findings) n += f.code == code;
    return n;
}

}  // namespace

TEST_CASE("mass check: a CAD centre of mass on the mesh centroid passes, density follows") {
    Run r = run(Vec3::Zero());
    CHECK(r.fetches == 2);  // ground and the block, each asked once
    const ShapeCheck& c = r.m->shape_checks[1];
    REQUIRE(c.checked);
    CHECK(c.volume == mbx_test::relative(1e-3, 1e-6));
    CHECK(c.density == mbx_test::relative(2700, 1e-6));
    CHECK(c.centroid_mismatch < 1e-12);
    CHECK(count(*r.m, MBX_FINDING_MASS_MISMATCH) == 0);
}

TEST_CASE("mass check: a centre of mass 5 mm off the centroid is named") {
    Run r = run(Vec3(0, 0.005, 0));
    const ShapeCheck& c = r.m->shape_checks[1];
    CHECK(c.centroid_mismatch == mbx_test::relative(0.005, 1e-6));
    // Tolerance: 2 % of the box diagonal (0.1*sqrt(3) m) = 3.46 mm, above 1 mm.
    CHECK(c.tolerance == mbx_test::relative(0.02 * 0.1 * std::sqrt(3.0), 1e-6));
    REQUIRE(count(*r.m, MBX_FINDING_MASS_MISMATCH) == 1);
    for (const Finding& f : r.m->findings)
        if (f.code == MBX_FINDING_MASS_MISMATCH) {
            CHECK(f.subject.id == "block");
            CHECK(f.message.find("5.000 mm") != std::string::npos);
        }
}

TEST_CASE("mass check: an open mesh is reported, not checked") {
    Run r = run(Vec3::Zero(), true);
    CHECK_FALSE(r.m->shape_checks[1].checked);
    CHECK(count(*r.m, MBX_FINDING_SHAPE_NOT_CLOSED) == 1);
}
}  // namespace MBX_UNITY_ID
