// The in-memory host adapter: an assembly held in plain C++ data and a Host
// that serves it through the mbx_host callback table, the way a careful CAD
// plugin would. The stub CAD host, the file adapters, the CLI and the tests
// all serve their data through it.
//
// Units: every value is in the units its `units` member states (host units);
// rotations are ROW-MAJOR as in mbx.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <mbx/mbx.h>

namespace mbx_memory {

struct Body {
    std::string id, name;
    uint32_t flags = 0;  // mbx_body_flags
    mbx_units units{1, 1, 0};
    double mass = 0;
    double com[3]{};      // body frame
    double inertia[9]{};  // about the CoM, body axes, row-major
    mbx_pose pose{};      // world
    double volume = 0;    // CAD solid volume in the cube of units.length_to_m; 0 = unknown
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
    double velocity_limit = 0, effort_limit = 0;  // SI; 0: not given
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
    double color[4] = {0, 0, 0, 0};   // red, green, blue, alpha in 0..1; alpha 0: none
};

// What the host noticed itself (served through the version-3 callbacks).
struct Diagnostic {
    mbx_severity severity = MBX_SEVERITY_WARNING;
    std::string code;
    mbx_subject_kind subject_kind = MBX_SUBJECT_NONE;
    std::string subject_id, subject_name;
    std::string file;
    int line = 0;
    std::string message;
};

struct Assembly {
    std::string name, source;
    std::vector<Body> bodies;
    std::vector<Frame> frames;
    std::vector<Constraint> constraints;
    std::map<std::string, std::vector<Mesh>> shapes;  // by body id
    std::vector<Diagnostic> diagnostics;
    double mass = 0;  // the whole assembly's mass as the CAD states it, kg; 0 = none stated
};

// Produces the meshes of one body on demand (file adapters load mesh files
// lazily). Returns false and sets `error` when they cannot be had. Meshes
// found in Assembly::shapes are served first.
using ShapeSource = std::function<bool(const Body& body, std::vector<Mesh>& out, std::string& error)>;

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
    explicit Host(const Assembly& assembly, Faults faults = {}, ShapeSource shape_source = {});
    explicit Host(Assembly&& assembly, Faults faults = {}, ShapeSource shape_source = {});
    ~Host();
    Host(const Host&) = delete;
    Host& operator=(const Host&) = delete;

    // The current table (MBX_HOST_ABI_VERSION).
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

    // Appends a diagnostic the SDK will see: at once if it has not pulled
    // them yet, else after the get_shapes call that is running (a version-4
    // host's list only grows). For shape sources that fail late.
    void add_diagnostic(Diagnostic diagnostic);

    struct State;  // what user_data points at

private:
    std::unique_ptr<State> state_;
};

}  // namespace mbx_memory
