#include "plugin_fixture.h"

#include <doctest/doctest.h>

#include "apps/stub_host/loader/plugin_loader.h"

namespace itest {

const char* plugin_path() { return MBX_PLUGIN_PATH; }

const mbx_api& api() {
    // Never unloaded: sanitizer reports at exit can still symbolize its frames.
    static const mbx_stub::Plugin* plugin = [] {
        auto* p = new mbx_stub::Plugin;
        std::string error;
        if (!p->load(MBX_PLUGIN_PATH, &error)) {
            delete p;
            p = nullptr;
            MESSAGE(error);
        }
        return p;
    }();
    REQUIRE_MESSAGE(plugin != nullptr, "the mbx plugin could not be loaded from " << MBX_PLUGIN_PATH);
    return *plugin->api();
}

void ContextDeleter::operator()(mbx_context* c) const { api().context_destroy(c); }
void MechanismDeleter::operator()(mbx_mechanism* m) const { api().mechanism_destroy(m); }

ContextPtr make_context() {
    mbx_context* c = nullptr;
    REQUIRE(api().context_create(&c) == MBX_OK);
    REQUIRE(c != nullptr);
    return ContextPtr(c);
}

mbx_stub::Assembly builtin(const std::string& name) {
    mbx_stub::Assembly a;
    REQUIRE_MESSAGE(mbx_stub::builtin_assembly(name, a), "no builtin " << name);
    return a;
}

Run translate(mbx_stub::Assembly assembly, mbx_stub::Faults faults, HostVersion version,
              const mbx_translate_options* options) {
    Run r;
    r.host.reset(new mbx_stub::Host(std::move(assembly), faults));
    r.context = make_context();
    mbx_mechanism* m = nullptr;
    const mbx_host* table = version == HostVersion::v1 ? r.host->v1_table() : r.host->table();
    r.status = api().translate(r.context.get(), table, options, &m);
    r.mechanism.reset(m);
    r.error = api().context_last_error(r.context.get());
    mbx_error_info info{};
    info.struct_size = sizeof info;
    if (api().context_last_error_info(r.context.get(), &info) == MBX_OK) {
        r.subject_kind = info.subject_kind;
        r.subject_id = info.subject_id ? info.subject_id : "";
    }
    return r;
}

Run translate_builtin(const std::string& name, mbx_stub::Faults faults) { return translate(builtin(name), faults); }

mbx_mechanism_summary summary(const mbx_mechanism* m) {
    mbx_mechanism_summary s{};
    s.struct_size = sizeof s;
    REQUIRE(api().mechanism_get_summary(m, &s) == MBX_OK);
    return s;
}

mbx_rigid_body_info rigid_body(const mbx_mechanism* m, uint32_t index) {
    mbx_rigid_body_info b{};
    b.struct_size = sizeof b;
    REQUIRE(api().mechanism_get_rigid_body(m, index, &b) == MBX_OK);
    return b;
}

mbx_joint_info joint(const mbx_mechanism* m, uint32_t index) {
    mbx_joint_info j{};
    j.struct_size = sizeof j;
    REQUIRE(api().mechanism_get_joint(m, index, &j) == MBX_OK);
    return j;
}

mbx_loop_info loop(const mbx_mechanism* m, uint32_t index) {
    mbx_loop_info l{};
    l.struct_size = sizeof l;
    REQUIRE(api().mechanism_get_loop(m, index, &l) == MBX_OK);
    return l;
}

std::vector<uint32_t> loop_joints(const mbx_mechanism* m, uint32_t index) {
    uint32_t count = 0;
    REQUIRE(api().mechanism_get_loop_joints(m, index, nullptr, &count) == MBX_OK);
    std::vector<uint32_t> joints(count);
    REQUIRE(api().mechanism_get_loop_joints(m, index, joints.data(), &count) == MBX_OK);
    REQUIRE(count == joints.size());
    return joints;
}

uint32_t find_part(const mbx_mechanism* m, const std::string& part_id) {
    uint32_t index = ~0u;
    REQUIRE_MESSAGE(api().mechanism_find_part(m, part_id.c_str(), &index) == MBX_OK, "part " << part_id);
    return index;
}

uint32_t joint_total(const mbx_mechanism* m) { return summary(m).joint_count; }

uint32_t body_total(const mbx_mechanism* m) {
    const mbx_mechanism_summary s = summary(m);
    return 1 + s.rigid_body_count + s.joint_node_count;
}

uint32_t find_joint(const mbx_mechanism* m, const std::string& constraint_id, uint32_t primitive) {
    const uint32_t n = joint_total(m);
    for (uint32_t i = 0; i < n; ++i) {
        const mbx_joint_info j = joint(m, i);
        if (constraint_id == j.constraint_id && j.primitive_index == primitive) return i;
    }
    FAIL("no joint from primitive " << primitive << " of constraint " << constraint_id);
    return ~0u;
}

}  // namespace itest
