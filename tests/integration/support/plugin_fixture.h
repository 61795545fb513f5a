// Integration tests talk to the SDK only the way a CAD host does: through the
// table returned by the dlopen()ed plugin (mbx_stub::Plugin). Nothing here
// links libmbx.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <mbx/mbx.h>

#include "apps/stub_host/assemblies/stub_assembly.h"

namespace itest {

// The plugin at MBX_PLUGIN_PATH, loaded once for the whole test run; fails
// the current test if it cannot be loaded.
const mbx_api& api();
const char* plugin_path();

struct ContextDeleter {
    void operator()(mbx_context* c) const;
};
struct MechanismDeleter {
    void operator()(mbx_mechanism* m) const;
};
using ContextPtr = std::unique_ptr<mbx_context, ContextDeleter>;
using MechanismPtr = std::unique_ptr<mbx_mechanism, MechanismDeleter>;

ContextPtr make_context();

// One translation with everything it needs kept alive in the right order:
// the mechanism dies first, then the context, then the host it may call.
struct Run {
    std::unique_ptr<mbx_stub::Host> host;
    ContextPtr context;
    MechanismPtr mechanism;
    mbx_status status = MBX_ERROR_INTERNAL;
    std::string error;          // context's last error after translate
    std::string subject_id;     // from mbx_context_last_error_info
    mbx_subject_kind subject_kind = MBX_SUBJECT_NONE;

    mbx_mechanism* get() const { return mechanism.get(); }
};

enum class HostVersion { v2, v1 };

Run translate(mbx_stub::Assembly assembly, mbx_stub::Faults faults = {}, HostVersion version = HostVersion::v2,
              const mbx_translate_options* options = nullptr);
mbx_stub::Assembly builtin(const std::string& name);  // REQUIREs that it exists
Run translate_builtin(const std::string& name, mbx_stub::Faults faults = {});

// Query helpers: REQUIRE MBX_OK and return the filled struct.
mbx_mechanism_summary summary(const mbx_mechanism* m);
mbx_rigid_body_info rigid_body(const mbx_mechanism* m, uint32_t index);
mbx_joint_info joint(const mbx_mechanism* m, uint32_t index);
mbx_loop_info loop(const mbx_mechanism* m, uint32_t index);
std::vector<uint32_t> loop_joints(const mbx_mechanism* m, uint32_t index);
uint32_t find_part(const mbx_mechanism* m, const std::string& part_id);
// Index of the joint made from primitive `primitive` of constraint `id`; REQUIREs it exists.
uint32_t find_joint(const mbx_mechanism* m, const std::string& constraint_id, uint32_t primitive = 0);
uint32_t joint_total(const mbx_mechanism* m);   // tree + cut joints
uint32_t body_total(const mbx_mechanism* m);    // ground + dynamic + nodes

}  // namespace itest
