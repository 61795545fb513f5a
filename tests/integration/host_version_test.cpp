// ABI evolution seen from an old host: a version-1 table (heap block of
// exactly MBX_HOST_V1_SIZE bytes, so an SDK reading describe_assembly from it
// trips AddressSanitizer) must translate exactly like a version-2 one.
#include <doctest/doctest.h>

#include <cstdlib>
#include <cstring>

#include "support/fingerprint.h"
#include "support/plugin_fixture.h"

namespace MBX_UNITY_ID {

using namespace itest;

TEST_CASE("host versions: a version-1 host translates identically to a version-2 host") {
    std::vector<mbx_stub::Assembly> assemblies;
    for (const auto& name : mbx_stub::builtin_names()) assemblies.push_back(builtin(name));
    assemblies.push_back(mbx_stub::generate_assembly(120, 4));
    for (const mbx_stub::Assembly& a : assemblies) {
        INFO("assembly " << a.name);
        const Run v2 = translate(a, {}, HostVersion::v2);
        const Run v1 = translate(a, {}, HostVersion::v1);
        REQUIRE_MESSAGE(v2.status == MBX_OK, v2.error);
        REQUIRE_MESSAGE(v1.status == MBX_OK, v1.error);
        CHECK(v1.host->v1_table()->struct_size == MBX_HOST_V1_SIZE);
        CHECK(fingerprint(v1.get()) == fingerprint(v2.get()));
        // Shapes (a version-1 callback) still work through the old table.
        mbx_shape_stats s1{}, s2{};
        s1.struct_size = s2.struct_size = sizeof s1;
        const uint32_t last = summary(v1.get()).rigid_body_count;
        CHECK(api().mechanism_get_shape_stats(v1.context.get(), v1.get(), last, &s1) == MBX_OK);
        CHECK(api().mechanism_get_shape_stats(v2.context.get(), v2.get(), last, &s2) == MBX_OK);
        CHECK(s1.mesh_count == s2.mesh_count);
        CHECK(s1.vertex_count == s2.vertex_count);
    }
}

TEST_CASE("host versions: unusable host tables and arguments are refused") {
    const mbx_stub::Assembly a = builtin("fourbar");
    const mbx_stub::Host host(a);
    ContextPtr context = make_context();
    mbx_mechanism* m = nullptr;

    // Smaller than the oldest table there ever was.
    const size_t tiny_size = offsetof(mbx_host, get_body);
    void* tiny = std::malloc(tiny_size);
    std::memcpy(tiny, host.table(), tiny_size);
    // Written as bytes: a member access through mbx_host* to a block too
    // small for one is itself undefined (clang's UBSan refuses it).
    const uint32_t tiny_struct_size = uint32_t(tiny_size);
    std::memcpy(tiny, &tiny_struct_size, sizeof tiny_struct_size);
    const mbx_status tiny_status = api().translate(context.get(), static_cast<mbx_host*>(tiny), nullptr, &m);
    std::free(tiny);
    CHECK((tiny_status == MBX_ERROR_VERSION || tiny_status == MBX_ERROR_INVALID_ARGUMENT));
    CHECK(m == nullptr);
    CHECK(std::string(api().context_last_error(context.get())) != "");

    CHECK(api().translate(context.get(), nullptr, nullptr, &m) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(m == nullptr);
    CHECK(api().translate(context.get(), host.table(), nullptr, nullptr) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(api().translate(nullptr, host.table(), nullptr, &m) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(m == nullptr);
}

TEST_CASE("host versions: optional callbacks may be NULL") {
    const mbx_stub::Assembly a = builtin("planar_sixbar");
    const mbx_stub::Host host(a);
    mbx_host table = *host.table();
    table.describe_assembly = nullptr;
    table.get_shapes = nullptr;
    ContextPtr context = make_context();
    mbx_mechanism* m = nullptr;
    REQUIRE(api().translate(context.get(), &table, nullptr, &m) == MBX_OK);
    MechanismPtr owned(m);
    CHECK(summary(m).dof == 1);
    CHECK(host.counts().shapes == 0);
}

TEST_CASE("host versions: the plugin serves a table at least as new as the header") {
    const mbx_api& a = api();
    CHECK(a.struct_size >= sizeof(mbx_api));
    CHECK(a.abi_version >= MBX_ABI_VERSION);
    REQUIRE(MBX_FIELD_FITS(&a, mbx_api, abi_version_fn));
    CHECK(a.abi_version_fn() == a.abi_version);
    CHECK(std::string(a.version()) == MBX_VERSION_STRING);
    CHECK(std::string(a.status_name(MBX_ERROR_IO)) == "MBX_ERROR_IO");
}
}  // namespace MBX_UNITY_ID
