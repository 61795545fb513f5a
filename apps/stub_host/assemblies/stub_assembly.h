// The stub CAD system: built-in assemblies and a generator of large ones,
// served through the in-memory host adapter (host_adapters/memory). The
// CLI, the benchmarks and the integration tests drive the SDK through this,
// so the names below are a contract.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "host_adapters/memory/memory_host.h"

namespace mbx_stub {

using mbx_memory::Assembly;
using mbx_memory::Body;
using mbx_memory::CallCounts;
using mbx_memory::Constraint;
using mbx_memory::Diagnostic;
using mbx_memory::Faults;
using mbx_memory::Frame;
using mbx_memory::Host;
using mbx_memory::Mesh;
using mbx_memory::Primitive;

// ---------------------------------------------------------------------------
// Built-in assemblies (hand-checked mechanisms; expected translation results
// are derived in the comment of each builtin_*.cpp).
// ---------------------------------------------------------------------------
std::vector<std::string> builtin_names();  // sorted
bool builtin_assembly(const std::string& name, Assembly& out);  // false if unknown

// ---------------------------------------------------------------------------
// Generated assemblies for benchmarks and scale tests.
// ---------------------------------------------------------------------------
// What translating a generated assembly must give (see generator.cpp).
struct GeneratedCounts {
    size_t parts = 0;              // == Assembly::bodies.size()
    size_t helpers = 0;            // parts flagged MBX_BODY_HELPER (all welded into a body)
    size_t welds = 0;              // weld constraints
    size_t rigid_bodies = 0;       // dynamic rigid bodies after weld merging
    size_t joint_nodes = 0;        // massless nodes of 2-primitive universal-joint chains
    size_t revolutes = 0;
    size_t sphericals = 0;
    size_t joints = 0;             // primitive joints (welds excluded)
    size_t loops = 0;              // == cut joints
    size_t planar_loops = 0;
    size_t spatial_loops = 0;
    int dof = 0;
    size_t redundant = 0;          // rank deficit of all closure equations
    size_t branches = 0;           // serial chains hanging from ground
    size_t max_depth = 0;          // deepest rigid body in the spanning tree (ground = 0)
};

Assembly generate_assembly(size_t body_count, uint32_t seed);
Assembly generate_assembly(size_t body_count, uint32_t seed, GeneratedCounts* counts);

}  // namespace mbx_stub
