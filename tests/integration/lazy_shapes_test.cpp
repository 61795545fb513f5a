// Geometry is pulled lazily: translation makes no shape call at all; asking
// for one rigid body's shape stats asks the host for exactly that body's
// parts, once; the totals and bounds (in the body frame, metres) match what
// is computed here from the stub meshes.
#include <doctest/doctest.h>

#include <algorithm>
#include <limits>
#include <set>

#include "support/plugin_fixture.h"
#include "support/stub_geometry.h"

namespace MBX_UNITY_ID {

using namespace itest;

namespace {

struct Expected {
    uint32_t meshes = 0;
    uint64_t vertices = 0, triangles = 0;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
};

// Every vertex of every mesh of `parts`, taken to world and then into the
// rigid body's frame.
Expected expected_stats(const mbx_stub::Assembly& a, const std::vector<std::string>& parts, const WorldPose& body) {
    Expected e;
    for (const std::string& id : parts) {
        const auto found = a.shapes.find(id);
        if (found == a.shapes.end()) continue;
        const mbx_stub::Body& b = body_by_id(a, id);
        const double lf = length_si(b.units);
        const WorldPose part = body_world(b);
        for (const mbx_stub::Mesh& m : found->second) {
            ++e.meshes;
            e.vertices += m.vertices.size() / 3;
            e.triangles += m.triangles.size() / 3;
            const WorldPose mesh = world(m.pose, lf);
            for (size_t v = 0; v + 2 < m.vertices.size(); v += 3) {
                const Vec3 local = Vec3(m.vertices[v], m.vertices[v + 1], m.vertices[v + 2]) * lf;
                const Vec3 w = part.apply(mesh.apply(local));
                const Vec3 in_body = body.R.transpose() * (w - body.p);
                e.lo = e.lo.cwiseMin(in_body);
                e.hi = e.hi.cwiseMax(in_body);
            }
        }
    }
    return e;
}

void check_stats(const mbx_shape_stats& s, const Expected& e) {
    CHECK(s.mesh_count == e.meshes);
    CHECK(s.vertex_count == e.vertices);
    CHECK(s.triangle_count == e.triangles);
    CHECK((vec(s.bounds_min) - e.lo).norm() < 1e-12);
    CHECK((vec(s.bounds_max) - e.hi).norm() < 1e-12);
}

std::vector<std::string> parts_of(const mbx_stub::Assembly& a, const mbx_mechanism* m, uint32_t body) {
    std::vector<std::string> ids;
    for (const auto& b : a.bodies)
        if (find_part(m, b.id) == body) ids.push_back(b.id);
    return ids;
}

}  // namespace

TEST_CASE("lazy shapes: translation makes zero shape calls") {
    for (const auto& name : mbx_stub::builtin_names()) {
        INFO("builtin " << name);
        const Run r = translate_builtin(name);
        REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
        CHECK(r.host->counts().shapes == 0);
        // Every part was read exactly once.
        CHECK(r.host->counts().bodies == r.host->assembly().bodies.size());
        CHECK(r.host->counts().constraints == r.host->assembly().constraints.size());
    }
}

TEST_CASE("lazy shapes: link 2 of the arm asks for exactly its three parts, once") {
    const mbx_stub::Assembly a = builtin("six_axis_arm");
    const Run r = translate(a);
    REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
    mbx_mechanism* m = r.get();
    const uint32_t link2 = find_part(m, "six_axis_arm/link2_tube");
    const std::vector<std::string> parts = parts_of(a, m, link2);
    REQUIRE(parts.size() == 3);
    REQUIRE(r.host->counts().shapes == 0);

    mbx_shape_stats s{};
    s.struct_size = sizeof s;
    REQUIRE_MESSAGE(api().mechanism_get_shape_stats(r.context.get(), m, link2, &s) == MBX_OK,
                    std::string(api().context_last_error(r.context.get())));
    const std::vector<std::string>& asked = r.host->shape_requests();
    CHECK(std::set<std::string>(asked.begin(), asked.end()) == std::set<std::string>(parts.begin(), parts.end()));
    CHECK(asked.size() == 3);

    const Expected e = expected_stats(a, parts, world(rigid_body(m, link2).pose, 1.0));
    CHECK(e.meshes == 4);
    CHECK(e.vertices == 32);
    CHECK(e.triangles == 48);
    check_stats(s, e);

    // Cached: asking again does not call the host.
    mbx_shape_stats again{};
    again.struct_size = sizeof again;
    REQUIRE(api().mechanism_get_shape_stats(r.context.get(), m, link2, &again) == MBX_OK);
    CHECK(r.host->counts().shapes == 3);
    check_stats(again, e);
}

TEST_CASE("lazy shapes: stats of every body match the stub meshes") {
    for (const auto& name : mbx_stub::builtin_names()) {
        INFO("builtin " << name);
        const mbx_stub::Assembly a = builtin(name);
        const Run r = translate(a);
        REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
        mbx_mechanism* m = r.get();
        const uint32_t dynamic = summary(m).rigid_body_count;
        for (uint32_t i = 0; i <= dynamic; ++i) {
            INFO("rigid body " << i);
            mbx_shape_stats s{};
            s.struct_size = sizeof s;
            REQUIRE(api().mechanism_get_shape_stats(r.context.get(), m, i, &s) == MBX_OK);
            check_stats(s, expected_stats(a, parts_of(a, m, i), world(rigid_body(m, i).pose, 1.0)));
        }
    }
}

TEST_CASE("lazy shapes: after release_host shape requests fail and never reach the host") {
    const Run r = translate_builtin("fourbar");
    REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
    mbx_mechanism* m = r.get();
    mbx_shape_stats s{};
    s.struct_size = sizeof s;
    const uint32_t crank = find_part(m, "fourbar/crank");
    REQUIRE(api().mechanism_get_shape_stats(r.context.get(), m, crank, &s) == MBX_OK);
    REQUIRE(api().mechanism_release_host(m) == MBX_OK);
    const size_t calls = r.host->counts().shapes;
    const uint32_t rocker = find_part(m, "fourbar/rocker");
    CHECK(api().mechanism_get_shape_stats(r.context.get(), m, rocker, &s) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(r.host->counts().shapes == calls);
    // Out-of-range index is an argument error, not a crash.
    CHECK(api().mechanism_get_shape_stats(r.context.get(), m, 999, &s) == MBX_ERROR_INVALID_ARGUMENT);
}
}  // namespace MBX_UNITY_ID
