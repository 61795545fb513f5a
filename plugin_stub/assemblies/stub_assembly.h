// A stand-in CAD system: assemblies held in plain C++ data and a Host that
// serves them through the mbx_host callback table, the way a real CAD
// plugin would. The CLI, the benchmarks and the integration tests all drive
// the SDK through this, so the names below are a contract.
//
// Units: every value is in the units its `units` member states (host units);
// rotations are ROW-MAJOR as in mbx.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <mbx/mbx.h>

namespace mbx_stub {

struct Body {
    std::string id, name;
    uint32_t flags = 0;  // mbx_body_flags
    mbx_units units{1, 1, 0};
    double mass = 0;
    double com[3]{};      // body frame
    double inertia[9]{};  // about the CoM, body axes, row-major
    mbx_pose pose{};      // world
};

struct Frame {
    std::string id, name, body_id;
    mbx_frame_reference reference = MBX_FRAME_IN_WORLD;
    mbx_units units{1, 1, 0};
    mbx_pose pose{};  // world, or relative to the body's pose (IN_BODY)
};

struct Primitive {
    mbx_primitive_type type;
    mbx_axis_reference axis_reference = MBX_AXIS_IN_WORLD;
    double axis[3]{0, 0, 1};
    bool has_limits = false;
    double lower = 0, upper = 0;
};

// chain[0] is J_N (next to the base), chain.back() is J_1.
struct Constraint {
    std::string id, name, base_frame_id, follower_frame_id;
    std::vector<Primitive> chain;
    std::string host_status;
};

// Vertices in the owning body's length unit, in `pose` relative to the body frame.
struct Mesh {
    std::string name;
    mbx_pose pose{};
    std::vector<double> vertices;     // 3 per vertex
    std::vector<uint32_t> triangles;  // 3 per triangle, 0-based
};

struct Assembly {
    std::string name, source;
    std::vector<Body> bodies;
    std::vector<Frame> frames;
    std::vector<Constraint> constraints;
    std::map<std::string, std::vector<Mesh>> shapes;  // by body id
};

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

// ---------------------------------------------------------------------------
// The host.
// ---------------------------------------------------------------------------
// Indices refer to the host order of Assembly::bodies / ::constraints; -1 = off.
struct Faults {
    long fail_at_body = -1;        // get_body(k) fails
    long nan_at_body = -1;         // get_body(k) serves a NaN mass
    long fail_at_constraint = -1;  // get_constraint(k) fails
    long fail_shapes_at_body = -1; // get_shapes for body k fails
};

// Calls of the get_* callbacks (not of the *_count ones).
struct CallCounts {
    size_t bodies = 0, frames = 0, constraints = 0, primitives = 0, shapes = 0;
};

// Serves an Assembly through the mbx_host callback table. The Host keeps its
// own copy of the assembly, so the strings it hands out live as long as the
// Host does, and table() stays valid for the Host's lifetime. Not copyable
// (the table's user_data points at it), not thread-safe (one Host per thread).
class Host {
public:
    explicit Host(const Assembly& assembly, Faults faults = {});
    explicit Host(Assembly&& assembly, Faults faults = {});
    ~Host();
    Host(const Host&) = delete;
    Host& operator=(const Host&) = delete;

    // The current (version 2) table.
    const mbx_host* table() const;
    // The same callbacks as an old host built against version 1 would hand
    // them over: a heap block of exactly MBX_HOST_V1_SIZE bytes, abi_version 1,
    // so a reader that looks past the end trips AddressSanitizer.
    const mbx_host* v1_table() const;

    const CallCounts& counts() const;
    // Body ids passed to get_shapes, in call order.
    const std::vector<std::string>& shape_requests() const;
    void reset_counts();

    const Assembly& assembly() const;
    const Faults& faults() const;

    struct State;  // what user_data points at

private:
    std::unique_ptr<State> state_;
};

}  // namespace mbx_stub
