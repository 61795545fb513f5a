// mbx_host callbacks over an in-memory Assembly. It behaves like a careful
// real host: it writes only the descriptor fields that lie within
// the struct_size the SDK declared, hands out strings it owns, and reports
// failures through the message buffer.
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <unordered_map>
#include <utility>

#include "memory_host.h"

// Write `field` only if the SDK's descriptor is large enough to hold it.
#define STUB_SET(out, type, field, value)                         \
    do {                                                          \
        if (MBX_FIELD_FITS(out, type, field)) (out)->field = (value); \
    } while (0)
#define STUB_COPY(out, type, field, source)                                               \
    do {                                                                                  \
        if (MBX_FIELD_FITS(out, type, field)) std::memcpy(&(out)->field, &(source), sizeof((out)->field)); \
    } while (0)

namespace mbx_memory {

struct Host::State {
    Assembly assembly;
    Faults faults;
    ShapeSource shape_source;
    CallCounts counts;
    std::vector<std::string> shape_requests;
    std::unordered_map<std::string, size_t> body_index;
    mbx_host table{};
    void* v1_block = nullptr;  // exactly MBX_HOST_V1_SIZE bytes
};

namespace {

using State = Host::State;

State& state(void* user_data) { return *static_cast<State*>(user_data); }

#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
int fail(char* message, size_t message_size, const char* format, ...) {
    if (message && message_size) {
        va_list args;
        va_start(args, format);
        std::vsnprintf(message, message_size, format, args);
        va_end(args);
    }
    return 1;
}

const char* or_null(const std::string& s) { return s.empty() ? nullptr : s.c_str(); }

int body_count(void* user_data, size_t* out_count) {
    if (!out_count) return 1;
    *out_count = state(user_data).assembly.bodies.size();
    return 0;
}

int get_body(void* user_data, size_t index, mbx_body_desc* out, char* message, size_t message_size) {
    State& s = state(user_data);
    ++s.counts.bodies;
    if (!out) return fail(message, message_size, "memory host: get_body without a descriptor");
    if (index >= s.assembly.bodies.size()) return fail(message, message_size, "memory host: no body at index %zu", index);
    const Body& b = s.assembly.bodies[index];
    if (long(index) == s.faults.fail_at_body)
        return fail(message, message_size, "memory host: simulated failure reading body %s", b.id.c_str());
    const double mass = long(index) == s.faults.nan_at_body ? std::numeric_limits<double>::quiet_NaN() : b.mass;
    STUB_SET(out, mbx_body_desc, id, b.id.c_str());
    STUB_SET(out, mbx_body_desc, name, or_null(b.name));
    STUB_SET(out, mbx_body_desc, flags, b.flags);
    STUB_SET(out, mbx_body_desc, units, b.units);
    STUB_SET(out, mbx_body_desc, mass, mass);
    STUB_COPY(out, mbx_body_desc, com, b.com);
    STUB_COPY(out, mbx_body_desc, inertia, b.inertia);
    STUB_SET(out, mbx_body_desc, pose, b.pose);
    STUB_SET(out, mbx_body_desc, volume, b.volume);
    return 0;
}

int frame_count(void* user_data, size_t* out_count) {
    if (!out_count) return 1;
    *out_count = state(user_data).assembly.frames.size();
    return 0;
}

int get_frame(void* user_data, size_t index, mbx_frame_desc* out, char* message, size_t message_size) {
    State& s = state(user_data);
    ++s.counts.frames;
    if (!out) return fail(message, message_size, "memory host: get_frame without a descriptor");
    if (index >= s.assembly.frames.size())
        return fail(message, message_size, "memory host: no frame at index %zu", index);
    const Frame& f = s.assembly.frames[index];
    STUB_SET(out, mbx_frame_desc, id, f.id.c_str());
    STUB_SET(out, mbx_frame_desc, name, or_null(f.name));
    STUB_SET(out, mbx_frame_desc, body_id, f.body_id.c_str());
    STUB_SET(out, mbx_frame_desc, reference, f.reference);
    STUB_SET(out, mbx_frame_desc, units, f.units);
    STUB_SET(out, mbx_frame_desc, pose, f.pose);
    return 0;
}

int constraint_count(void* user_data, size_t* out_count) {
    if (!out_count) return 1;
    *out_count = state(user_data).assembly.constraints.size();
    return 0;
}

int get_constraint(void* user_data, size_t index, mbx_constraint_desc* out, char* message, size_t message_size) {
    State& s = state(user_data);
    ++s.counts.constraints;
    if (!out) return fail(message, message_size, "memory host: get_constraint without a descriptor");
    if (index >= s.assembly.constraints.size())
        return fail(message, message_size, "memory host: no constraint at index %zu", index);
    const Constraint& c = s.assembly.constraints[index];
    if (long(index) == s.faults.fail_at_constraint)
        return fail(message, message_size, "memory host: simulated failure reading constraint %s", c.id.c_str());
    STUB_SET(out, mbx_constraint_desc, id, c.id.c_str());
    STUB_SET(out, mbx_constraint_desc, name, or_null(c.name));
    STUB_SET(out, mbx_constraint_desc, base_frame_id, c.base_frame_id.c_str());
    STUB_SET(out, mbx_constraint_desc, follower_frame_id, c.follower_frame_id.c_str());
    STUB_SET(out, mbx_constraint_desc, primitive_count, uint32_t(c.chain.size()));
    STUB_SET(out, mbx_constraint_desc, host_status, or_null(c.host_status));
    return 0;
}

int get_primitive(void* user_data, size_t constraint_index, size_t primitive_index, mbx_primitive_desc* out,
                  char* message, size_t message_size) {
    State& s = state(user_data);
    ++s.counts.primitives;
    if (!out) return fail(message, message_size, "memory host: get_primitive without a descriptor");
    if (constraint_index >= s.assembly.constraints.size())
        return fail(message, message_size, "memory host: no constraint at index %zu", constraint_index);
    const Constraint& c = s.assembly.constraints[constraint_index];
    if (primitive_index >= c.chain.size())
        return fail(message, message_size, "memory host: constraint %s has no primitive %zu", c.id.c_str(),
                    primitive_index);
    const Primitive& p = c.chain[primitive_index];
    STUB_SET(out, mbx_primitive_desc, type, p.type);
    STUB_SET(out, mbx_primitive_desc, axis_reference, p.axis_reference);
    STUB_COPY(out, mbx_primitive_desc, axis, p.axis);
    STUB_SET(out, mbx_primitive_desc, has_limits, p.has_limits ? 1 : 0);
    STUB_SET(out, mbx_primitive_desc, lower, p.lower);
    STUB_SET(out, mbx_primitive_desc, upper, p.upper);
    STUB_SET(out, mbx_primitive_desc, velocity_limit, p.velocity_limit);
    STUB_SET(out, mbx_primitive_desc, effort_limit, p.effort_limit);
    return 0;
}

int get_shapes(void* user_data, const char* body_id, const mbx_shape_sink* sink, char* message,
               size_t message_size) {
    State& s = state(user_data);
    ++s.counts.shapes;
    s.shape_requests.emplace_back(body_id ? body_id : "");
    if (!body_id || !sink) return fail(message, message_size, "memory host: get_shapes without a body id or sink");
    const auto found = s.body_index.find(body_id);
    if (found == s.body_index.end()) return fail(message, message_size, "memory host: no body with id %s", body_id);
    if (long(found->second) == s.faults.fail_shapes_at_body)
        return fail(message, message_size, "memory host: simulated failure reading shapes of body %s", body_id);
    if (!MBX_FIELD_FITS(sink, mbx_shape_sink, add_mesh) || !sink->add_mesh)
        return fail(message, message_size, "memory host: shape sink without add_mesh");
    const Body& body = s.assembly.bodies[found->second];
    const auto stored = s.assembly.shapes.find(body_id);
    std::vector<Mesh> loaded;
    if (s.shape_source) {
        std::string error;
        if (!s.shape_source(body, loaded, error))
            return fail(message, message_size, "%s", error.c_str());
    }
    const std::vector<Mesh> none;
    const std::vector<Mesh>& first = stored == s.assembly.shapes.end() ? none : stored->second;
    const std::vector<Mesh>* lists[] = {&first, &loaded};
    for (const std::vector<Mesh>* list : lists)
    for (const Mesh& m : *list) {
        mbx_mesh_desc d{};
        d.struct_size = sizeof(d);
        d.name = m.name.c_str();
        d.units = body.units;
        d.pose = m.pose;
        d.vertices = m.vertices.data();
        d.vertex_count = uint32_t(m.vertices.size() / 3);
        d.triangles = m.triangles.data();
        d.triangle_count = uint32_t(m.triangles.size() / 3);
        for (int k = 0; k < 4; ++k) d.color[k] = m.color[k];
        if (sink->add_mesh(sink->sink_data, &d) != 0)
            return fail(message, message_size, "memory host: mesh %s of body %s was rejected", m.name.c_str(), body_id);
    }
    return 0;
}

int diagnostic_count(void* user_data, size_t* out_count) {
    if (!out_count) return 1;
    *out_count = state(user_data).assembly.diagnostics.size();
    return 0;
}

int get_diagnostic(void* user_data, size_t index, mbx_host_diagnostic* out) {
    const State& s = state(user_data);
    if (!out || index >= s.assembly.diagnostics.size()) return 1;
    const Diagnostic& d = s.assembly.diagnostics[index];
    STUB_SET(out, mbx_host_diagnostic, severity, d.severity);
    STUB_SET(out, mbx_host_diagnostic, code, or_null(d.code));
    STUB_SET(out, mbx_host_diagnostic, subject_kind, d.subject_kind);
    STUB_SET(out, mbx_host_diagnostic, subject_id, d.subject_id.c_str());
    STUB_SET(out, mbx_host_diagnostic, subject_name, d.subject_name.c_str());
    STUB_SET(out, mbx_host_diagnostic, file, or_null(d.file));
    STUB_SET(out, mbx_host_diagnostic, line, d.line);
    STUB_SET(out, mbx_host_diagnostic, message, d.message.c_str());
    return 0;
}

int get_assembly_mass(void* user_data, double* out_mass_kg) {
    const State& s = state(user_data);
    if (!out_mass_kg || !(s.assembly.mass > 0)) return 1;  // none stated
    *out_mass_kg = s.assembly.mass;
    return 0;
}

int describe_assembly(void* user_data, const char** out_name, const char** out_source) {
    const State& s = state(user_data);
    if (out_name) *out_name = s.assembly.name.c_str();
    if (out_source) *out_source = s.assembly.source.c_str();
    return 0;
}

void init(State& s) {
    for (size_t i = 0; i < s.assembly.bodies.size(); ++i) s.body_index.emplace(s.assembly.bodies[i].id, i);
    mbx_host& t = s.table;
    t.struct_size = sizeof(mbx_host);
    t.abi_version = MBX_HOST_ABI_VERSION;
    t.user_data = &s;
    t.body_count = body_count;
    t.get_body = get_body;
    t.frame_count = frame_count;
    t.get_frame = get_frame;
    t.constraint_count = constraint_count;
    t.get_constraint = get_constraint;
    t.get_primitive = get_primitive;
    t.get_shapes = get_shapes;
    t.describe_assembly = describe_assembly;
    t.diagnostic_count = diagnostic_count;
    t.get_diagnostic = get_diagnostic;
    t.get_assembly_mass = get_assembly_mass;

    // An old host's table: the version-1 prefix and not one byte more.
    s.v1_block = std::malloc(MBX_HOST_V1_SIZE);
    if (!s.v1_block) throw std::bad_alloc();
    std::memcpy(s.v1_block, &t, MBX_HOST_V1_SIZE);
    const uint32_t v1_size = uint32_t(MBX_HOST_V1_SIZE), v1_abi = 1;
    auto* bytes = static_cast<unsigned char*>(s.v1_block);
    std::memcpy(bytes + offsetof(mbx_host, struct_size), &v1_size, sizeof v1_size);
    std::memcpy(bytes + offsetof(mbx_host, abi_version), &v1_abi, sizeof v1_abi);
}

}  // namespace

Host::Host(const Assembly& assembly, Faults faults, ShapeSource shape_source) : state_(new State) {
    state_->assembly = assembly;
    state_->faults = faults;
    state_->shape_source = std::move(shape_source);
    init(*state_);
}

Host::Host(Assembly&& assembly, Faults faults, ShapeSource shape_source) : state_(new State) {
    state_->assembly = std::move(assembly);
    state_->faults = faults;
    state_->shape_source = std::move(shape_source);
    init(*state_);
}

Host::~Host() {
    if (state_) std::free(state_->v1_block);
}

const mbx_host* Host::table() const { return &state_->table; }
const mbx_host* Host::v1_table() const { return static_cast<const mbx_host*>(state_->v1_block); }
const CallCounts& Host::counts() const { return state_->counts; }
const std::vector<std::string>& Host::shape_requests() const { return state_->shape_requests; }
void Host::reset_counts() {
    state_->counts = CallCounts{};
    state_->shape_requests.clear();
}
const Assembly& Host::assembly() const { return state_->assembly; }
const Faults& Host::faults() const { return state_->faults; }
void Host::add_diagnostic(Diagnostic diagnostic) { state_->assembly.diagnostics.push_back(std::move(diagnostic)); }

}  // namespace mbx_memory
