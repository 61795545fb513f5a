#include "core/assembly/host_reader.h"

#include <cmath>
#include <cstring>
#include <unordered_map>

#include "core/text_format.h"

namespace mbx {
namespace {

constexpr size_t kMessageSize = 512;
constexpr uint32_t kMaxChain = 16;  // longer chains are a host bug, not a joint
// A host's count is only a promise: reserve at most this much up front, so a
// wrong (huge) count fails at the first item the host cannot deliver rather
// than exhausting memory before the first call.
constexpr size_t kMaxReserve = size_t(1) << 16;
size_t reservable(size_t n) { return n < kMaxReserve ? n : kMaxReserve; }
// A C host may store any int in an enum field; loading that as the C++ enum
// type is undefined behaviour, so enum fields are read as the int they are.
template <class E>
int enum_int(const E& field) {
    static_assert(sizeof(E) == sizeof(int), "C enums are ints on the supported ABIs");
    int v;
    std::memcpy(&v, &field, sizeof v);
    return v;
}

std::string str(const char* s) { return s ? std::string(s) : std::string(); }

double factor(double f) { return f == 0.0 ? 1.0 : f; }

bool finite(const double* v, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

// A warning finding about `subject` (the fields it leaves empty: no file, no host code).
Finding warning(mbx_finding_code code, Subject subject, std::string message) {
    Finding f;
    f.severity = MBX_SEVERITY_WARNING;
    f.code = code;
    f.subject = std::move(subject);
    f.message = std::move(message);
    return f;
}

}  // namespace

size_t pull_host_diagnostics(const mbx_host& host, size_t from, Findings& findings) {
    if (!host_has(&host, offsetof(mbx_host, get_diagnostic) + sizeof(host.get_diagnostic)) ||
        !host.diagnostic_count || !host.get_diagnostic)
        return from;
    size_t n = 0;
    if (host.diagnostic_count(host.user_data, &n) != 0)
        throw Error(MBX_ERROR_HOST_CALLBACK, {}, "host failed to report its diagnostic count");
    for (size_t i = from; i < n; ++i) {
        mbx_host_diagnostic d;
        std::memset(&d, 0, sizeof d);
        d.struct_size = sizeof d;
        if (host.get_diagnostic(host.user_data, i, &d) != 0)
            throw Error(MBX_ERROR_HOST_CALLBACK, {}, "host failed to deliver diagnostic #" + std::to_string(i));
        Finding f;
        const int severity = enum_int(d.severity), kind = enum_int(d.subject_kind);
        f.severity = severity >= MBX_SEVERITY_INFO && severity <= MBX_SEVERITY_ERROR ? mbx_severity(severity)
                                                                                     : MBX_SEVERITY_WARNING;
        f.code = MBX_FINDING_HOST_DIAGNOSTIC;
        f.code_text = str(d.code);
        f.subject = {kind >= MBX_SUBJECT_NONE && kind <= MBX_SUBJECT_MODEL ? mbx_subject_kind(kind) : MBX_SUBJECT_NONE,
                     str(d.subject_id), str(d.subject_name)};
        f.message = str(d.message);
        f.file = str(d.file);
        f.line = d.line;
        findings.push_back(std::move(f));
    }
    return n > from ? n : from;
}

namespace {

class Reader {
public:
    Reader(const mbx_host* host, const HostReadOptions& options, Progress& progress, Findings& findings)
        : host_(host), options_(options), progress_(progress), findings_(findings) {}

    Assembly run() {
        check_table();
        if (host_has(host_, offsetof(mbx_host, describe_assembly) + sizeof(host_->describe_assembly)) &&
            host_->describe_assembly) {
            const char* name = nullptr;
            const char* source = nullptr;
            if (host_->describe_assembly(host_->user_data, &name, &source) == 0) {
                out_.name = str(name);
                out_.source = str(source);
            }
        }
        read_diagnostics();
        read_bodies();
        read_frames();
        read_constraints();
        read_assembly_mass();
        out_.size = assembly_size();
        return std::move(out_);
    }

private:
    void check_table() {
        if (!host_) throw Error(MBX_ERROR_INVALID_ARGUMENT, {}, "host table is NULL");
        if (host_->struct_size < MBX_HOST_V1_SIZE || host_->abi_version < 1)
            throw Error(MBX_ERROR_VERSION, {},
                        "host table declares struct_size " + std::to_string(host_->struct_size) + " and abi_version " +
                            std::to_string(host_->abi_version) + "; at least version 1 (" +
                            std::to_string(MBX_HOST_V1_SIZE) + " bytes) is required");
        const char* missing = !host_->body_count         ? "body_count"
                              : !host_->get_body         ? "get_body"
                              : !host_->frame_count      ? "frame_count"
                              : !host_->get_frame        ? "get_frame"
                              : !host_->constraint_count ? "constraint_count"
                              : !host_->get_constraint   ? "get_constraint"
                              : !host_->get_primitive    ? "get_primitive"
                                                         : nullptr;
        if (missing)
            throw Error(MBX_ERROR_INVALID_ARGUMENT, {}, std::string("host table has no '") + missing + "' callback");
    }

    size_t count(int (*fn)(void*, size_t*), const char* what) {
        size_t n = 0;
        if (fn(host_->user_data, &n) != 0)
            throw Error(MBX_ERROR_HOST_CALLBACK, {}, std::string("host failed to report its ") + what + " count");
        return n;
    }

    [[noreturn]] void callback_failed(Subject subject, const std::string& what, const char* message) {
        std::string m = "host failed to deliver " + what;
        if (message[0]) m += ": " + std::string(message, strnlen(message, kMessageSize));
        throw Error(MBX_ERROR_HOST_CALLBACK, std::move(subject), m);
    }

    // Rotation from the host, repaired if it is merely rounded.
    Mat3 rotation(const double* r, const Subject& subject, const char* what) {
        Mat3 m = from_row_major(r);
        double err = orthonormality_error(m);
        if (err <= 1e-12 && m.determinant() > 0) return m;
        Mat3 fixed;
        if (err > options_.orthonormality_limit || !nearest_rotation(m, fixed))
            throw Error(MBX_ERROR_INVALID_INPUT, subject,
                        std::string("the ") + what + " rotation of " + subject_kind_name(subject.kind) + " '" +
                            subject.id + "' is not a rotation (max |R^T R - I| = " + readable(err) +
                            (m.determinant() <= 0 ? ", determinant <= 0: a reflection" : "") + ")");
        if (err > options_.orthonormality_tolerance)
            findings_.push_back(warning(MBX_FINDING_ROTATION_REORTHONORMALIZED, subject,
                                 std::string("the ") + what + " rotation of '" + subject.id +
                                     "' was re-orthonormalized (max |R^T R - I| = " + readable(err) +
                                     ", above the rounding tolerance " +
                                     readable(options_.orthonormality_tolerance) + ")"));
        return fixed;
    }

    void require_finite(const double* v, size_t n, const Subject& subject, const char* field) {
        if (!finite(v, n))
            throw Error(MBX_ERROR_INVALID_INPUT, subject,
                        std::string("host delivered a non-finite ") + field + " for " +
                            subject_kind_name(subject.kind) + " '" + subject.id + "'");
    }

    static double units_length(const mbx_units& u) { return factor(u.length_to_m); }

    void require_units(const mbx_units& u, const Subject& s) {
        const double f[3] = {u.length_to_m, u.mass_to_kg, u.inertia_to_kg_m2};
        require_finite(f, 3, s, "unit factor");
        if (u.length_to_m < 0 || u.mass_to_kg < 0 || u.inertia_to_kg_m2 < 0)
            throw Error(MBX_ERROR_INVALID_INPUT, s, "negative unit factor for '" + s.id + "'");
    }

    void read_diagnostics() { out_.host_diagnostics_read = pull_host_diagnostics(*host_, 0, findings_); }

    // Calls a host getter with a zeroed descriptor of the SDK's size and
    // checks that the item has an id. `kind` names it in messages ("body").
    template <class Desc, class Call>
    Desc fetch(size_t i, mbx_subject_kind subject, const char* kind, Call call) {
        Desc d;
        std::memset(&d, 0, sizeof d);
        d.struct_size = sizeof d;
        char message[kMessageSize];
        message[0] = '\0';
        const std::string where = std::string(kind) + " #" + std::to_string(i);
        if (call(&d, message) != 0)
            callback_failed({subject, d.id ? d.id : "#" + std::to_string(i), str(d.name)},
                            where + (d.id ? " ('" + std::string(d.id) + "')" : ""), message);
        if (!d.id || !d.id[0])
            throw Error(MBX_ERROR_INVALID_INPUT, {subject, "#" + std::to_string(i), str(d.name)}, where + " has no id");
        return d;
    }

    void read_bodies() {
        size_t n = count(host_->body_count, "body");
        out_.parts.reserve(reservable(n));
        body_index_.reserve(reservable(n));
        progress_.stage("pull bodies", n);
        for (size_t i = 0; i < n; ++i) {
            const auto d = fetch<mbx_body_desc>(i, MBX_SUBJECT_BODY, "body", [&](mbx_body_desc* out, char* msg) {
                return host_->get_body(host_->user_data, i, out, msg, kMessageSize);
            });
            Part p;
            p.id = d.id;
            p.name = d.name ? d.name : d.id;
            Subject s = Subject::body(p.id, p.name);
            if (!body_index_.emplace(p.id, int(i)).second)
                throw Error(MBX_ERROR_INVALID_INPUT, s, "body id '" + p.id + "' is used twice");
            p.flags = d.flags;
            require_units(d.units, s);
            require_finite(&d.mass, 1, s, "mass");
            require_finite(d.com, 3, s, "centre of mass");
            require_finite(d.inertia, 9, s, "inertia tensor");
            require_finite(d.pose.position, 3, s, "position");
            require_finite(d.pose.rotation, 9, s, "rotation");
            const double len = units_length(d.units);
            const double mass_f = factor(d.units.mass_to_kg);
            const double inertia_f = d.units.inertia_to_kg_m2 == 0 ? mass_f * len * len : d.units.inertia_to_kg_m2;
            p.mass = d.mass * mass_f;
            p.com = Vec3(d.com[0], d.com[1], d.com[2]) * len;
            Mat3 inertia = from_row_major(d.inertia) * inertia_f;
            p.inertia = 0.5 * (inertia + inertia.transpose());
            p.pose.position = Vec3(d.pose.position[0], d.pose.position[1], d.pose.position[2]) * len;
            p.pose.rotation = rotation(d.pose.rotation, s, "pose");
            // Zero in the SDK's zeroed descriptor when an older host does not know the field.
            require_finite(&d.volume, 1, s, "volume");
            if (d.volume < 0)
                throw Error(MBX_ERROR_INVALID_INPUT, s, "host delivered a negative volume for body '" + p.id + "'");
            if (d.volume > 0) {
                p.volume = d.volume * len * len * len;
                p.host_density = d.mass / d.volume;
            }
            out_.parts.push_back(std::move(p));
            progress_.tick();
        }
        progress_.finish();
    }

    void read_frames() {
        size_t n = count(host_->frame_count, "frame");
        out_.frames.reserve(reservable(n));
        frame_index_.reserve(reservable(n));
        progress_.stage("pull frames", n);
        for (size_t i = 0; i < n; ++i) {
            const auto d = fetch<mbx_frame_desc>(i, MBX_SUBJECT_FRAME, "frame", [&](mbx_frame_desc* out, char* msg) {
                return host_->get_frame(host_->user_data, i, out, msg, kMessageSize);
            });
            Frame f;
            f.id = d.id;
            f.name = d.name ? d.name : d.id;
            Subject s = Subject::frame(f.id, f.name);
            if (!frame_index_.emplace(f.id, int(i)).second)
                throw Error(MBX_ERROR_INVALID_INPUT, s, "frame id '" + f.id + "' is used twice");
            auto body = d.body_id ? body_index_.find(d.body_id) : body_index_.end();
            if (body == body_index_.end())
                throw Error(MBX_ERROR_INVALID_INPUT, s,
                            "frame '" + f.id + "' belongs to unknown body '" + str(d.body_id) + "'");
            f.part = body->second;
            require_units(d.units, s);
            require_finite(d.pose.position, 3, s, "position");
            require_finite(d.pose.rotation, 9, s, "rotation");
            Pose local;
            local.position = Vec3(d.pose.position[0], d.pose.position[1], d.pose.position[2]) * units_length(d.units);
            local.rotation = rotation(d.pose.rotation, s, "frame");
            const int reference = enum_int(d.reference);
            if (reference == MBX_FRAME_IN_BODY)
                f.world = out_.parts[size_t(f.part)].pose * local;
            else if (reference == MBX_FRAME_IN_WORLD)
                f.world = local;
            else
                throw Error(MBX_ERROR_INVALID_INPUT, s,
                            "frame '" + f.id + "' has unknown reference " + std::to_string(reference));
            frame_length_unit_.push_back(units_length(d.units));
            out_.frames.push_back(std::move(f));
            progress_.tick();
        }
        progress_.finish();
    }

    void read_assembly_mass() {
        if (!host_has(host_, offsetof(mbx_host, get_assembly_mass) + sizeof(host_->get_assembly_mass)) ||
            !host_->get_assembly_mass)
            return;
        double mass = 0;
        if (host_->get_assembly_mass(host_->user_data, &mass) != 0) return;  // the host states none
        require_finite(&mass, 1, Subject::model(out_.name), "assembly mass");
        if (mass < 0) throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(out_.name), "host delivered a negative assembly mass");
        out_.stated_mass = mass;
    }

    int frame_ref(const char* id, const Subject& s, const char* role) {
        auto it = id ? frame_index_.find(id) : frame_index_.end();
        if (it == frame_index_.end())
            throw Error(MBX_ERROR_INVALID_INPUT, s,
                        "constraint '" + s.id + "' refers to unknown " + role + " frame '" + str(id) + "'");
        return it->second;
    }

    void read_constraints() {
        size_t n = count(host_->constraint_count, "constraint");
        out_.constraints.reserve(reservable(n));
        std::unordered_map<std::string, int> ids;
        ids.reserve(reservable(n));
        progress_.stage("pull constraints", n);
        for (size_t i = 0; i < n; ++i) {
            const auto d = fetch<mbx_constraint_desc>(
                i, MBX_SUBJECT_CONSTRAINT, "constraint", [&](mbx_constraint_desc* out, char* msg) {
                    return host_->get_constraint(host_->user_data, i, out, msg, kMessageSize);
                });
            Constraint c;
            c.id = d.id;
            c.name = d.name ? d.name : d.id;
            Subject s = Subject::constraint(c.id, c.name);
            if (!ids.emplace(c.id, int(i)).second)
                throw Error(MBX_ERROR_INVALID_INPUT, s, "constraint id '" + c.id + "' is used twice");
            c.base_frame = frame_ref(d.base_frame_id, s, "base");
            c.follower_frame = frame_ref(d.follower_frame_id, s, "follower");
            c.host_status = str(d.host_status);
            if (d.primitive_count == 0 || d.primitive_count > kMaxChain)
                throw Error(MBX_ERROR_INVALID_INPUT, s,
                            "constraint '" + c.id + "' has " + std::to_string(d.primitive_count) +
                                " primitives; 1 to " + std::to_string(kMaxChain) + " are allowed");
            const Frame& base = out_.frames[size_t(c.base_frame)];
            c.chain.reserve(d.primitive_count);
            for (uint32_t k = 0; k < d.primitive_count; ++k) c.chain.push_back(read_primitive(i, k, c, s, base));
            if (!c.host_status.empty())
                findings_.push_back(warning(MBX_FINDING_HOST_STATUS, s,
                                     "host reports on constraint '" + c.name + "': " + c.host_status));
            out_.constraints.push_back(std::move(c));
            progress_.tick();
        }
        progress_.finish();
    }

    Primitive read_primitive(size_t ci, uint32_t k, const Constraint& c, const Subject& s, const Frame& base) {
        mbx_primitive_desc d;
        std::memset(&d, 0, sizeof d);
        d.struct_size = sizeof d;
        char message[kMessageSize];
        message[0] = '\0';
        const std::string where = "primitive " + std::to_string(k) + " of constraint '" + c.id + "'";
        if (host_->get_primitive(host_->user_data, ci, k, &d, message, sizeof message) != 0)
            callback_failed(s, where, message);
        Primitive p;
        const int type = enum_int(d.type), axis_reference = enum_int(d.axis_reference);
        if (type < MBX_PRIMITIVE_WELD || type > MBX_PRIMITIVE_SPHERICAL)
            throw Error(MBX_ERROR_INVALID_INPUT, s, where + " has unknown type " + std::to_string(type));
        p.type = mbx_primitive_type(type);
        require_finite(d.axis, 3, s, "joint axis");
        if (p.type == MBX_PRIMITIVE_REVOLUTE || p.type == MBX_PRIMITIVE_PRISMATIC) {
            Vec3 axis(d.axis[0], d.axis[1], d.axis[2]);
            if (axis_reference == MBX_AXIS_IN_BASE_FRAME)
                axis = base.world.rotation * axis;
            else if (axis_reference != MBX_AXIS_IN_WORLD)
                throw Error(MBX_ERROR_INVALID_INPUT, s,
                            where + " has unknown axis reference " + std::to_string(axis_reference));
            const double norm = axis.norm();
            if (!(norm > 1e-9))
                throw Error(MBX_ERROR_INVALID_INPUT, s, where + " has a zero-length axis");
            p.axis = axis / norm;
        }
        if (d.has_limits && p.type != MBX_PRIMITIVE_WELD && p.type != MBX_PRIMITIVE_SPHERICAL) {
            const double lim[2] = {d.lower, d.upper};
            require_finite(lim, 2, s, "joint limit");
            const double scale = p.type == MBX_PRIMITIVE_PRISMATIC ? frame_length_unit_[size_t(c.base_frame)] : 1.0;
            if (d.lower > d.upper) {
                findings_.push_back(warning(MBX_FINDING_LIMITS_INVERTED, s,
                                     where + " has lower limit " + readable(d.lower) + " above upper limit " +
                                         readable(d.upper) + "; the limits are ignored"));
            } else {
                p.has_limits = true;
                p.lower = d.lower * scale;
                p.upper = d.upper * scale;
            }
        }
        if (MBX_FIELD_FITS(&d, mbx_primitive_desc, effort_limit) && p.type != MBX_PRIMITIVE_WELD) {
            const double rated[2] = {d.velocity_limit, d.effort_limit};
            require_finite(rated, 2, s, "joint velocity and effort limit");
            if (d.velocity_limit < 0 || d.effort_limit < 0)
                throw Error(MBX_ERROR_INVALID_INPUT, s, where + " has a negative velocity or effort limit");
            p.velocity_limit = d.velocity_limit, p.effort_limit = d.effort_limit;
        }
        return p;
    }

    double assembly_size() const {
        if (out_.parts.empty() && out_.frames.empty()) return 1.0;
        Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
        for (const Part& p : out_.parts) {
            lo = lo.cwiseMin(p.pose.position);
            hi = hi.cwiseMax(p.pose.position);
        }
        for (const Frame& f : out_.frames) {
            lo = lo.cwiseMin(f.world.position);
            hi = hi.cwiseMax(f.world.position);
        }
        const double d = (hi - lo).norm();
        return d > 1e-6 ? d : 1.0;
    }

    const mbx_host* host_;
    HostReadOptions options_;
    Progress& progress_;
    Findings& findings_;
    Assembly out_;
    std::unordered_map<std::string, int> body_index_;
    std::unordered_map<std::string, int> frame_index_;
    std::vector<double> frame_length_unit_;
};

}  // namespace

Assembly read_host(const mbx_host* host, const HostReadOptions& options, Progress& progress, Findings& findings) {
    return Reader(host, options, progress, findings).run();
}

}  // namespace mbx
