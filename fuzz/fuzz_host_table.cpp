// The C API's host table with fuzzed descriptors: a host that answers the
// callbacks with whatever the bytes say (table size and version, counts that
// lie, missing or repeated ids, NULL strings, NaN, infinities and huge values
// in poses, units and inertia, enum values outside their range, failing
// callbacks with a message that fills its buffer, meshes whose indices point
// anywhere; host ABI 4's volumes, stated assembly mass and diagnostics
// appended while shapes are served). The SDK must turn each into a status with a message or a
// finding, never a crash, leak or hang. Then the consumers of a translated
// mechanism run on it: queries, shape statistics and the simulator's model.
#include <fuzzer/FuzzedDataProvider.h>
#include <mbx/mbx.h>

#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

// Ids come from a small pool so references hit, miss and repeat often.
const char* const kIds[] = {"a", "b", "c", "g", "", "A", "a ", "\xff\xfe", "very-long-id-0123456789-0123456789-0123456789"};

double fuzz_double(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 11)) {
        case 0: return 0;
        case 1: return 1;
        case 2: return -1;
        case 3: return std::numeric_limits<double>::quiet_NaN();
        case 4: return std::numeric_limits<double>::infinity();
        case 5: return -std::numeric_limits<double>::infinity();
        case 6: return 1e300;
        case 7: return 1e-300;
        case 8: return std::numeric_limits<double>::denorm_min();
        case 9: {
            uint64_t bits = in.ConsumeIntegral<uint64_t>();
            double d;
            std::memcpy(&d, &bits, sizeof d);
            return d;
        }
        default: return in.ConsumeFloatingPointInRange<double>(-10, 10);
    }
}

const char* fuzz_id(FuzzedDataProvider& in) {
    const size_t k = in.ConsumeIntegralInRange<size_t>(0, sizeof kIds / sizeof *kIds);
    return k == sizeof kIds / sizeof *kIds ? nullptr : kIds[k];
}

// Mostly a proper rotation (so the deeper stages run), else anything.
void fuzz_pose(FuzzedDataProvider& in, mbx_pose& pose) {
    for (double& p : pose.position) p = fuzz_double(in);
    switch (in.ConsumeIntegralInRange<int>(0, 3)) {
        case 0: {
            const double r[9]{1, 0, 0, 0, 1, 0, 0, 0, 1};
            std::memcpy(pose.rotation, r, sizeof r);
            break;
        }
        case 1: {
            const double a = in.ConsumeFloatingPointInRange<double>(-4, 4), c = std::cos(a), s = std::sin(a);
            const double r[9]{c, -s, 0, s, c, 0, 0, 0, 1};
            std::memcpy(pose.rotation, r, sizeof r);
            break;
        }
        case 2: {
            const double r[9]{0, 1, 0, 1, 0, 0, 0, 0, 1};  // a reflection
            std::memcpy(pose.rotation, r, sizeof r);
            break;
        }
        default:
            for (double& r : pose.rotation) r = fuzz_double(in);
    }
}

void fuzz_units(FuzzedDataProvider& in, mbx_units& u) {
    if (in.ConsumeBool()) {
        u = {in.ConsumeBool() ? 0.001 : 1.0, 1.0, in.ConsumeBool() ? 1e-6 : 1.0};
        return;
    }
    u = {fuzz_double(in), fuzz_double(in), fuzz_double(in)};
}

// Counts: usually what was generated, sometimes a lie (more, or absurdly many).
size_t fuzz_count(FuzzedDataProvider& in, size_t real) {
    switch (in.ConsumeIntegralInRange<int>(0, 5)) {
        case 0: return real + 1;
        case 1: return std::numeric_limits<size_t>::max();
        case 2: return size_t(1) << 40;
        default: return real;
    }
}

struct Item {
    bool fail = false;  // the callback returns non-zero
    size_t message_length = 0;
};

struct FuzzBody : Item { mbx_body_desc desc{}; };
struct FuzzFrame : Item { mbx_frame_desc desc{}; };
struct FuzzPrimitive : Item { mbx_primitive_desc desc{}; };
struct FuzzConstraint : Item {
    mbx_constraint_desc desc{};
    std::vector<FuzzPrimitive> primitives;
};
struct FuzzMesh {
    mbx_mesh_desc desc{};
    std::vector<double> vertices;
    std::vector<uint32_t> triangles;
};
struct FuzzShapes : Item {
    std::vector<FuzzMesh> meshes;
};

struct FuzzHost {
    size_t body_count = 0, frame_count = 0, constraint_count = 0, diagnostic_count = 0;
    bool fail_counts = false;
    std::vector<FuzzBody> bodies;
    std::vector<FuzzFrame> frames;
    std::vector<FuzzConstraint> constraints;
    std::vector<mbx_host_diagnostic> diagnostics;
    std::vector<FuzzShapes> shapes;  // served in turn, one per get_shapes call
    size_t shape_calls = 0;
    // Host ABI 4: diagnostics appended while serving shapes (a mesh that
    // only fails when loaded), and the assembly mass the CAD states.
    std::vector<mbx_host_diagnostic> late_diagnostics;
    double assembly_mass = 0;
    bool assembly_mass_fails = false;
    const char* name = nullptr;
    const char* source = nullptr;
};

// Fills the caller's buffer with `length` bytes, NUL-terminated only if it fits:
// the SDK must not trust a host to terminate a message that fills the buffer.
int fail_with(const Item& item, char* message, size_t message_size) {
    if (message && message_size) {
        const size_t n = item.message_length < message_size ? item.message_length : message_size;
        std::memset(message, 'x', n);
        if (n < message_size) message[n] = 0;
    }
    return 1;
}

// Copies at most the descriptor's declared size, as a host built against an
// older header would.
template <class Desc>
void copy_desc(Desc* out, const Desc& in) {
    const uint32_t size = out->struct_size;
    std::memcpy(out, &in, size < sizeof in ? size : sizeof in);
    out->struct_size = size;
}

FuzzHost& self(void* user_data) { return *static_cast<FuzzHost*>(user_data); }

int body_count(void* u, size_t* out) {
    *out = self(u).body_count;
    return self(u).fail_counts ? 1 : 0;
}
int frame_count(void* u, size_t* out) {
    *out = self(u).frame_count;
    return 0;
}
int constraint_count(void* u, size_t* out) {
    *out = self(u).constraint_count;
    return 0;
}
int get_body(void* u, size_t index, mbx_body_desc* out, char* message, size_t message_size) {
    FuzzHost& h = self(u);
    if (index >= h.bodies.size()) return fail_with(Item{false, 12}, message, message_size);
    if (h.bodies[index].fail) return fail_with(h.bodies[index], message, message_size);
    copy_desc(out, h.bodies[index].desc);
    return 0;
}
int get_frame(void* u, size_t index, mbx_frame_desc* out, char* message, size_t message_size) {
    FuzzHost& h = self(u);
    if (index >= h.frames.size()) return fail_with(Item{false, 12}, message, message_size);
    if (h.frames[index].fail) return fail_with(h.frames[index], message, message_size);
    copy_desc(out, h.frames[index].desc);
    return 0;
}
int get_constraint(void* u, size_t index, mbx_constraint_desc* out, char* message, size_t message_size) {
    FuzzHost& h = self(u);
    if (index >= h.constraints.size()) return fail_with(Item{false, 12}, message, message_size);
    if (h.constraints[index].fail) return fail_with(h.constraints[index], message, message_size);
    copy_desc(out, h.constraints[index].desc);
    return 0;
}
int get_primitive(void* u, size_t c, size_t k, mbx_primitive_desc* out, char* message, size_t message_size) {
    FuzzHost& h = self(u);
    if (c >= h.constraints.size() || k >= h.constraints[c].primitives.size())
        return fail_with(Item{false, 12}, message, message_size);
    const FuzzPrimitive& p = h.constraints[c].primitives[k];
    if (p.fail) return fail_with(p, message, message_size);
    copy_desc(out, p.desc);
    return 0;
}
int get_shapes(void* u, const char* body_id, const mbx_shape_sink* sink, char* message, size_t message_size) {
    FuzzHost& h = self(u);
    if (!body_id) std::abort();  // the SDK always names the body
    if (h.shape_calls < h.late_diagnostics.size()) {
        // Appended, never changed: the count grows with the list (a lying
        // count stays a lie).
        if (h.diagnostic_count == h.diagnostics.size()) ++h.diagnostic_count;
        h.diagnostics.push_back(h.late_diagnostics[h.shape_calls]);
    }
    if (h.shapes.empty()) {
        ++h.shape_calls;
        return 0;
    }
    const FuzzShapes& s = h.shapes[h.shape_calls++ % h.shapes.size()];
    if (s.fail) return fail_with(s, message, message_size);
    for (const FuzzMesh& m : s.meshes)
        if (sink->add_mesh(sink->sink_data, &m.desc) != 0) return fail_with(Item{false, 5}, message, message_size);
    return 0;
}
int get_assembly_mass(void* u, double* out) {
    if (self(u).assembly_mass_fails) return 1;
    *out = self(u).assembly_mass;
    return 0;
}
int describe_assembly(void* u, const char** name, const char** source) {
    *name = self(u).name;
    *source = self(u).source;
    return 0;
}
int diagnostic_count(void* u, size_t* out) {
    *out = self(u).diagnostic_count;
    return 0;
}
int get_diagnostic(void* u, size_t index, mbx_host_diagnostic* out) {
    FuzzHost& h = self(u);
    if (index >= h.diagnostics.size()) return 1;
    copy_desc(out, h.diagnostics[index]);
    return 0;
}

void generate(FuzzedDataProvider& in, FuzzHost& h) {
    h.bodies.resize(in.ConsumeIntegralInRange<size_t>(0, 8));
    for (FuzzBody& b : h.bodies) {
        b.fail = in.ConsumeIntegralInRange<int>(0, 31) == 0;
        b.message_length = in.ConsumeIntegralInRange<size_t>(0, 4096);
        b.desc.struct_size = sizeof b.desc;
        b.desc.id = fuzz_id(in);
        b.desc.name = fuzz_id(in);
        b.desc.flags = in.ConsumeBool() ? in.ConsumeIntegralInRange<uint32_t>(0, 3) : in.ConsumeIntegral<uint32_t>();
        fuzz_units(in, b.desc.units);
        b.desc.mass = in.ConsumeBool() ? in.ConsumeFloatingPointInRange<double>(0, 10) : fuzz_double(in);
        for (double& c : b.desc.com) c = in.ConsumeBool() ? 0 : fuzz_double(in);
        if (in.ConsumeBool()) {
            const double d = in.ConsumeFloatingPointInRange<double>(1e-4, 1);
            const double i[9]{d, 0, 0, 0, d, 0, 0, 0, d};
            std::memcpy(b.desc.inertia, i, sizeof i);
        } else {
            for (double& i : b.desc.inertia) i = fuzz_double(in);
        }
        fuzz_pose(in, b.desc.pose);
        b.desc.volume = in.ConsumeBool() ? in.ConsumeFloatingPointInRange<double>(0, 10) : fuzz_double(in);
    }
    h.frames.resize(in.ConsumeIntegralInRange<size_t>(0, 12));
    for (FuzzFrame& f : h.frames) {
        f.fail = in.ConsumeIntegralInRange<int>(0, 31) == 0;
        f.message_length = in.ConsumeIntegralInRange<size_t>(0, 4096);
        f.desc.struct_size = sizeof f.desc;
        f.desc.id = fuzz_id(in);
        f.desc.name = fuzz_id(in);
        f.desc.body_id = fuzz_id(in);
        f.desc.reference = static_cast<mbx_frame_reference>(in.ConsumeBool() ? in.ConsumeIntegralInRange<int>(0, 1)
                                                                              : in.ConsumeIntegral<int>());
        fuzz_units(in, f.desc.units);
        fuzz_pose(in, f.desc.pose);
    }
    h.constraints.resize(in.ConsumeIntegralInRange<size_t>(0, 8));
    for (FuzzConstraint& c : h.constraints) {
        c.fail = in.ConsumeIntegralInRange<int>(0, 31) == 0;
        c.message_length = in.ConsumeIntegralInRange<size_t>(0, 4096);
        c.desc.struct_size = sizeof c.desc;
        c.desc.id = fuzz_id(in);
        c.desc.name = fuzz_id(in);
        c.desc.base_frame_id = fuzz_id(in);
        c.desc.follower_frame_id = fuzz_id(in);
        c.desc.host_status = in.ConsumeBool() ? nullptr : fuzz_id(in);
        c.primitives.resize(in.ConsumeIntegralInRange<size_t>(0, 4));
        for (FuzzPrimitive& p : c.primitives) {
            p.fail = in.ConsumeIntegralInRange<int>(0, 31) == 0;
            p.message_length = in.ConsumeIntegralInRange<size_t>(0, 4096);
            p.desc.struct_size = sizeof p.desc;
            p.desc.type = static_cast<mbx_primitive_type>(in.ConsumeBool() ? in.ConsumeIntegralInRange<int>(0, 3)
                                                                           : in.ConsumeIntegral<int>());
            p.desc.axis_reference = static_cast<mbx_axis_reference>(
                in.ConsumeBool() ? in.ConsumeIntegralInRange<int>(0, 1) : in.ConsumeIntegral<int>());
            for (double& a : p.desc.axis) a = in.ConsumeBool() ? double(in.ConsumeIntegralInRange<int>(-1, 1)) : fuzz_double(in);
            p.desc.has_limits = in.ConsumeIntegral<int32_t>();
            p.desc.lower = fuzz_double(in);
            p.desc.upper = fuzz_double(in);
        }
        c.desc.primitive_count = in.ConsumeBool() ? uint32_t(c.primitives.size()) : in.ConsumeIntegral<uint32_t>();
    }
    h.diagnostics.resize(in.ConsumeIntegralInRange<size_t>(0, 4));
    h.late_diagnostics.resize(in.ConsumeIntegralInRange<size_t>(0, 2));
    for (std::vector<mbx_host_diagnostic>* list : {&h.diagnostics, &h.late_diagnostics}) {
        for (mbx_host_diagnostic& d : *list) {
            d.struct_size = sizeof d;
            d.severity = static_cast<mbx_severity>(in.ConsumeIntegral<int>() % 5);
            d.code = fuzz_id(in);
            d.subject_kind = static_cast<mbx_subject_kind>(in.ConsumeIntegral<int>() % 8);
            d.subject_id = fuzz_id(in);
            d.subject_name = fuzz_id(in);
            d.file = fuzz_id(in);
            d.line = in.ConsumeIntegral<int32_t>();
            d.message = fuzz_id(in);
        }
    }
    h.shapes.resize(in.ConsumeIntegralInRange<size_t>(0, 3));
    for (FuzzShapes& s : h.shapes) {
        s.fail = in.ConsumeIntegralInRange<int>(0, 7) == 0;
        s.message_length = in.ConsumeIntegralInRange<size_t>(0, 4096);
        s.meshes.resize(in.ConsumeIntegralInRange<size_t>(0, 2));
        for (FuzzMesh& m : s.meshes) {
            m.desc.struct_size = in.ConsumeBool() ? uint32_t(sizeof m.desc) : in.ConsumeIntegral<uint32_t>() % uint32_t(sizeof m.desc + 1);
            m.desc.name = fuzz_id(in);
            fuzz_units(in, m.desc.units);
            fuzz_pose(in, m.desc.pose);
            m.vertices.resize(3 * in.ConsumeIntegralInRange<size_t>(0, 8));
            for (double& v : m.vertices) v = in.ConsumeBool() ? double(in.ConsumeIntegralInRange<int>(-2, 2)) : fuzz_double(in);
            m.triangles.resize(3 * in.ConsumeIntegralInRange<size_t>(0, 8));
            const uint32_t n = uint32_t(m.vertices.size() / 3);
            for (uint32_t& t : m.triangles)
                t = in.ConsumeBool() && n ? in.ConsumeIntegralInRange<uint32_t>(0, n - 1) : in.ConsumeIntegral<uint32_t>();
            m.desc.vertices = m.vertices.empty() && in.ConsumeBool() ? nullptr : m.vertices.data();
            m.desc.vertex_count = uint32_t(m.vertices.size() / 3);
            m.desc.triangles = m.triangles.empty() && in.ConsumeBool() ? nullptr : m.triangles.data();
            m.desc.triangle_count = uint32_t(m.triangles.size() / 3);
        }
    }
    h.body_count = fuzz_count(in, h.bodies.size());
    h.frame_count = fuzz_count(in, h.frames.size());
    h.constraint_count = fuzz_count(in, h.constraints.size());
    h.diagnostic_count = fuzz_count(in, h.diagnostics.size());
    h.fail_counts = in.ConsumeIntegralInRange<int>(0, 63) == 0;
    h.assembly_mass = in.ConsumeBool() ? in.ConsumeFloatingPointInRange<double>(0, 50) : fuzz_double(in);
    h.assembly_mass_fails = in.ConsumeIntegralInRange<int>(0, 7) == 0;
    h.name = fuzz_id(in);
    h.source = fuzz_id(in);
}

void use(mbx_context* context, mbx_mechanism* mechanism, FuzzedDataProvider& in) {
    mbx_mechanism_summary summary{};
    summary.struct_size = sizeof summary;
    if (mbx_mechanism_get_summary(mechanism, &summary) != MBX_OK) std::abort();
    const uint32_t bodies = summary.rigid_body_count + summary.joint_node_count + 1;
    for (uint32_t k = 0; k < bodies + 1; ++k) {
        mbx_rigid_body_info info{};
        info.struct_size = sizeof info;
        mbx_mechanism_get_rigid_body(mechanism, k, &info);
        mbx_shape_stats stats{};
        stats.struct_size = sizeof stats;
        mbx_mechanism_get_shape_stats(context, mechanism, k, &stats);
    }
    for (uint32_t k = 0; k < summary.joint_count + 1; ++k) {
        mbx_joint_info info{};
        info.struct_size = sizeof info;
        mbx_mechanism_get_joint(mechanism, k, &info);
    }
    for (uint32_t k = 0; k < summary.loop_count + 1; ++k) {
        mbx_loop_info info{};
        info.struct_size = sizeof info;
        mbx_mechanism_get_loop(mechanism, k, &info);
        uint32_t joints[64];
        uint32_t count = 64;
        mbx_mechanism_get_loop_joints(mechanism, k, joints, &count);
    }
    const uint32_t findings = mbx_mechanism_finding_count(mechanism);
    for (uint32_t k = 0; k < findings + 1; ++k) {
        mbx_finding f{};
        f.struct_size = sizeof f;
        if (mbx_mechanism_get_finding(mechanism, k, &f) == MBX_OK && (!f.message || !f.code_name)) std::abort();
    }
    if (!in.ConsumeBool()) return;
    mbx_sim_model* model = nullptr;
    if (mbx_sim_model_create(context, mechanism, nullptr, &model) != MBX_OK) return;
    mbx_sim_data* data = nullptr;
    if (mbx_sim_data_create(context, model, &data) == MBX_OK) {
        mbx_sim_model_info info{};
        info.struct_size = sizeof info;
        mbx_sim_model_get_info(model, &info);
        std::vector<double> qacc(info.nv + 1);
        mbx_sim_forward_dynamics(context, data, qacc.data());
        mbx_sim_data_destroy(data);
    }
    mbx_sim_model_destroy(model);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* bytes, size_t size) {
    FuzzedDataProvider in(bytes, size);
    FuzzHost h;
    // Table size and version as hosts built against each header would send them,
    // or nonsense; the table is a heap block of exactly that size so reading past
    // what the host declared trips AddressSanitizer.
    static const uint32_t kSizes[] = {uint32_t(MBX_HOST_V1_SIZE), uint32_t(offsetof(mbx_host, diagnostic_count)),
                                      uint32_t(offsetof(mbx_host, get_assembly_mass)), uint32_t(sizeof(mbx_host)), 0, 8};
    const uint32_t table_size = kSizes[in.ConsumeIntegralInRange<size_t>(0, 5)];
    const uint32_t abi = in.ConsumeBool() ? in.ConsumeIntegralInRange<uint32_t>(1, 4) : in.ConsumeIntegral<uint32_t>();
    const uint32_t dropped = in.ConsumeIntegral<uint32_t>();  // callbacks left NULL, one bit each
    generate(in, h);

    mbx_host full{};
    full.struct_size = table_size;
    full.abi_version = abi;
    full.user_data = &h;
    full.body_count = dropped & 1u << 0 ? nullptr : body_count;
    full.get_body = dropped & 1u << 1 ? nullptr : get_body;
    full.frame_count = dropped & 1u << 2 ? nullptr : frame_count;
    full.get_frame = dropped & 1u << 3 ? nullptr : get_frame;
    full.constraint_count = dropped & 1u << 4 ? nullptr : constraint_count;
    full.get_constraint = dropped & 1u << 5 ? nullptr : get_constraint;
    full.get_primitive = dropped & 1u << 6 ? nullptr : get_primitive;
    full.get_shapes = dropped & 1u << 7 ? nullptr : get_shapes;
    full.describe_assembly = dropped & 1u << 8 ? nullptr : describe_assembly;
    full.diagnostic_count = dropped & 1u << 9 ? nullptr : diagnostic_count;
    full.get_diagnostic = dropped & 1u << 10 ? nullptr : get_diagnostic;
    full.get_assembly_mass = dropped & 1u << 11 ? nullptr : get_assembly_mass;
    // Most runs keep every callback, so the data itself gets fuzzed.
    if (!(dropped & 1u << 31)) {
        full.body_count = body_count; full.get_body = get_body; full.frame_count = frame_count;
        full.get_frame = get_frame; full.constraint_count = constraint_count; full.get_constraint = get_constraint;
        full.get_primitive = get_primitive;
    }
    void* block = std::malloc(table_size ? table_size : 1);
    std::memcpy(block, &full, table_size < sizeof full ? table_size : sizeof full);
    const mbx_host* table = static_cast<const mbx_host*>(block);

    mbx_context* context = nullptr;
    if (mbx_context_create(&context) != MBX_OK) std::abort();
    mbx_translate_options options{};
    options.struct_size = sizeof options;
    options.length_tolerance = in.ConsumeBool() ? 0 : fuzz_double(in);
    options.orthonormality_tolerance = in.ConsumeBool() ? 0 : fuzz_double(in);
    options.rank_tolerance = in.ConsumeBool() ? 0 : fuzz_double(in);
    options.flags = in.ConsumeBool() ? MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES : 0;
    options.centroid_tolerance = in.ConsumeBool() ? 0 : fuzz_double(in);
    mbx_mechanism* mechanism = nullptr;
    const mbx_status status = mbx_translate(context, table_size < 8 ? nullptr : table, &options, &mechanism);
    if (status == MBX_OK) {
        if (!mechanism) std::abort();
        use(context, mechanism, in);
        if (in.ConsumeBool()) mbx_mechanism_release_host(mechanism);
        mbx_mechanism_destroy(mechanism);
    } else {
        const char* message = mbx_context_last_error(context);
        if (!message || !*message) std::abort();  // a failure must say why
    }
    mbx_context_destroy(context);
    std::free(block);
    return 0;
}
