// The stub host obeys the ABI rules a real CAD host must: it writes only the
// descriptor fields that fit in the struct_size the SDK declared, fails with
// a message naming what it could not read, and its version-1 table is
// exactly the version-1 prefix. Exercised here without the SDK.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "apps/stub_host/assemblies/stub_assembly.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

namespace {

constexpr unsigned char kCanary = 0xA5;

// A descriptor buffer that declares only `declared` bytes: everything past
// them must still hold the canary after the callback.
template <class Desc>
struct Truncated {
    explicit Truncated(size_t size) : bytes(sizeof(Desc) + 16, kCanary), declared(size) {
        std::memset(bytes.data(), 0, size);
        const uint32_t struct_size = uint32_t(size);
        std::memcpy(bytes.data(), &struct_size, sizeof struct_size);
    }
    Desc* desc() { return reinterpret_cast<Desc*>(bytes.data()); }
    bool untouched_tail() const {
        for (size_t i = declared; i < bytes.size(); ++i)
            if (bytes[i] != kCanary) return false;
        return true;
    }
    std::vector<unsigned char> bytes;
    size_t declared;
};

mbx_stub::Assembly fourbar() {
    mbx_stub::Assembly a;
    REQUIRE(mbx_stub::builtin_assembly("fourbar", a));
    return a;
}

}  // namespace

TEST_CASE("stub host: descriptors are filled only within struct_size") {
    const mbx_stub::Host host(fourbar());
    const mbx_host* t = host.table();
    char message[256] = "";

    for (size_t cut : {offsetof(mbx_body_desc, id), offsetof(mbx_body_desc, flags), offsetof(mbx_body_desc, mass),
                       offsetof(mbx_body_desc, inertia), offsetof(mbx_body_desc, pose), sizeof(mbx_body_desc)}) {
        Truncated<mbx_body_desc> d(cut);
        REQUIRE(t->get_body(t->user_data, 3, d.desc(), message, sizeof message) == 0);
        CHECK_MESSAGE(d.untouched_tail(), "body descriptor cut at " << cut);
    }
    for (size_t cut : {offsetof(mbx_frame_desc, body_id), offsetof(mbx_frame_desc, units), sizeof(mbx_frame_desc)}) {
        Truncated<mbx_frame_desc> d(cut);
        REQUIRE(t->get_frame(t->user_data, 0, d.desc(), message, sizeof message) == 0);
        CHECK_MESSAGE(d.untouched_tail(), "frame descriptor cut at " << cut);
    }
    for (size_t cut : {offsetof(mbx_constraint_desc, primitive_count), offsetof(mbx_constraint_desc, host_status),
                       sizeof(mbx_constraint_desc)}) {
        Truncated<mbx_constraint_desc> d(cut);
        REQUIRE(t->get_constraint(t->user_data, 2, d.desc(), message, sizeof message) == 0);
        CHECK_MESSAGE(d.untouched_tail(), "constraint descriptor cut at " << cut);
    }
    for (size_t cut : {offsetof(mbx_primitive_desc, has_limits), offsetof(mbx_primitive_desc, upper),
                       sizeof(mbx_primitive_desc)}) {
        Truncated<mbx_primitive_desc> d(cut);
        REQUIRE(t->get_primitive(t->user_data, 2, 0, d.desc(), message, sizeof message) == 0);
        CHECK_MESSAGE(d.untouched_tail(), "primitive descriptor cut at " << cut);
    }

    // A full descriptor gets everything, strings pointing into the host's copy.
    mbx_body_desc body{};
    body.struct_size = sizeof body;
    REQUIRE(t->get_body(t->user_data, 3, &body, message, sizeof message) == 0);
    CHECK(std::string(body.id) == "fourbar/crank");
    CHECK(body.id == host.assembly().bodies[3].id.c_str());
    CHECK(body.mass == mbx_test::relative(20.0, 1e-6));  // grams
    CHECK(body.units.length_to_m == 1e-3);
}

TEST_CASE("stub host: simulated faults name what failed") {
    const mbx_stub::Assembly a = fourbar();
    mbx_stub::Faults f;
    f.fail_at_body = 2;
    f.nan_at_body = 4;
    f.fail_at_constraint = 3;
    f.fail_shapes_at_body = 5;
    const mbx_stub::Host host(a, f);
    const mbx_host* t = host.table();
    char message[256] = "";

    mbx_body_desc body{};
    body.struct_size = sizeof body;
    CHECK(t->get_body(t->user_data, 2, &body, message, sizeof message) != 0);
    CHECK(std::string(message) == "memory host: simulated failure reading body " + a.bodies[2].id);
    CHECK(t->get_body(t->user_data, 4, &body, message, sizeof message) == 0);
    CHECK(std::isnan(body.mass));

    mbx_constraint_desc constraint{};
    constraint.struct_size = sizeof constraint;
    CHECK(t->get_constraint(t->user_data, 3, &constraint, message, sizeof message) != 0);
    CHECK(std::string(message) == "memory host: simulated failure reading constraint " + a.constraints[3].id);

    mbx_shape_sink sink{};
    sink.struct_size = sizeof sink;
    sink.add_mesh = [](void*, const mbx_mesh_desc*) { return 0; };
    CHECK(t->get_shapes(t->user_data, a.bodies[5].id.c_str(), &sink, message, sizeof message) != 0);
    CHECK(std::string(message) == "memory host: simulated failure reading shapes of body " + a.bodies[5].id);

    // A tiny message buffer is respected (and still terminated).
    char tiny[8];
    std::memset(tiny, 'x', sizeof tiny);
    CHECK(t->get_body(t->user_data, 2, &body, tiny, sizeof tiny) != 0);
    CHECK(std::strlen(tiny) == sizeof tiny - 1);

    CHECK(host.counts().bodies == 3);
    CHECK(host.counts().constraints == 1);
    CHECK(host.counts().shapes == 1);
    CHECK(host.shape_requests() == std::vector<std::string>{a.bodies[5].id});
}

TEST_CASE("stub host: shapes are delivered through the sink") {
    const mbx_stub::Assembly a = fourbar();
    const mbx_stub::Host host(a);
    const mbx_host* t = host.table();
    struct Seen {
        size_t meshes = 0, vertices = 0, triangles = 0;
    } seen;
    mbx_shape_sink sink{};
    sink.struct_size = sizeof sink;
    sink.sink_data = &seen;
    sink.add_mesh = [](void* data, const mbx_mesh_desc* m) {
        auto* s = static_cast<Seen*>(data);
        ++s->meshes;
        s->vertices += m->vertex_count;
        s->triangles += m->triangle_count;
        return m->struct_size == sizeof(mbx_mesh_desc) ? 0 : 1;
    };
    char message[128] = "";
    REQUIRE(t->get_shapes(t->user_data, "fourbar/coupler", &sink, message, sizeof message) == 0);
    CHECK(seen.meshes == 2);
    CHECK(seen.vertices == 16);
    CHECK(seen.triangles == 24);
    // The helper has no geometry: success, nothing delivered.
    REQUIRE(t->get_shapes(t->user_data, "fourbar/RootPart", &sink, message, sizeof message) == 0);
    CHECK(seen.meshes == 2);
    // A rejected mesh stops the delivery with a failure.
    sink.add_mesh = [](void*, const mbx_mesh_desc*) { return 1; };
    CHECK(t->get_shapes(t->user_data, "fourbar/crank", &sink, message, sizeof message) != 0);
    CHECK(std::string(message).find("fourbar/crank") != std::string::npos);
}

TEST_CASE("stub host: the version-1 table is exactly the version-1 prefix") {
    const mbx_stub::Host host(fourbar());
    const mbx_host* v2 = host.table();
    const mbx_host* v1 = host.v1_table();
    CHECK(v2->struct_size == sizeof(mbx_host));
    CHECK(v2->abi_version == MBX_HOST_ABI_VERSION);
    CHECK(bool(v2->describe_assembly != nullptr));
    CHECK(v1 != v2);
    CHECK(v1->struct_size == MBX_HOST_V1_SIZE);
    CHECK(v1->abi_version == 1);
    CHECK(v1->user_data == v2->user_data);
    CHECK(bool(v1->get_body == v2->get_body));
    CHECK(bool(v1->get_shapes == v2->get_shapes));
    CHECK_FALSE(MBX_FIELD_FITS(v1, mbx_host, describe_assembly));
}
}  // namespace MBX_UNITY_ID
