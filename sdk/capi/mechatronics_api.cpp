// The mechatronics entry points: library and drive files, drives and motions
// from the host, resolution against a mechanism, and drive queries.
#include <cmath>
#include <cstring>

#include "sdk/capi/guard.h"
#include "core/mechatronics/drive_file.h"

using namespace mbx;

namespace {

std::string text_or_empty(const char* s) { return s ? s : ""; }

// One problem as a line of the message: "file:line: object: message", or
// "object: message" for a drive the host added (it has no file).
std::string problem_text(const LibraryError& e) {
    if (!e.file.empty()) return e.text();
    return (e.object.empty() ? std::string() : e.object + ": ") + e.message;
}

// All problems in one message (a line each); the structured error names the
// first: `subject`, or else the file it is in (id = path, name = the object).
[[noreturn]] void fail_with(const std::vector<LibraryError>& errors, const std::string& what,
                            const Subject* subject = nullptr) {
    std::string message = what + " (" + std::to_string(errors.size()) + " problem" + (errors.size() > 1 ? "s" : "") + "):";
    for (const LibraryError& e : errors) message += "\n" + problem_text(e);
    const LibraryError& first = errors.front();
    throw Error(MBX_ERROR_INVALID_INPUT, subject ? *subject : Subject{MBX_SUBJECT_FILE, first.file, first.object},
                message, first.file, first.line);
}

// The first drive of `spec` that resolve_drives left out (the others come
// back in order, each with its source index), or null.
const DriveSpec* first_unresolved(const MechatronicSpec& spec, const std::vector<Drive>& resolved) {
    for (size_t i = 0; i < spec.drives.size(); ++i)
        if (i >= resolved.size() || resolved[i].source != int(i)) return &spec.drives[i];
    return nullptr;
}

// Loads into a copy and keeps it only when clean, so a bad file changes nothing.
template <class Load>
void load_all_or_nothing(mbx_mechatronics* m, const std::string& what, Load&& load) {
    MechatronicSpec copy = m->spec;
    const size_t library_errors = copy.library.errors().size();
    std::vector<DriveError> errors;
    load(copy, errors);
    const auto& lib = copy.library.errors();
    std::vector<LibraryError> all(lib.begin() + ptrdiff_t(library_errors), lib.end());
    all.insert(all.end(), errors.begin(), errors.end());
    if (!all.empty()) fail_with(all, what);
    m->spec = std::move(copy);
}

DriveSpec* find_drive(MechatronicSpec& spec, const std::string& constraint_id, int primitive) {
    for (DriveSpec& d : spec.drives)
        if (d.joint.constraint_id == constraint_id && d.joint.primitive == primitive) return &d;
    return nullptr;
}

bool valid_enum(int value, int last) { return value >= 0 && value <= last; }

}  // namespace

extern "C" {

MBX_API mbx_status mbx_mechatronics_create(mbx_context* context, mbx_mechatronics** out) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!out) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "out_mechatronics is NULL");
    *out = nullptr;
    return guarded(context, [&] { *out = new mbx_mechatronics(); });
}

MBX_API void mbx_mechatronics_destroy(mbx_mechatronics* mechatronics) { delete mechatronics; }

MBX_API mbx_status mbx_mechatronics_load_library(mbx_context* context, mbx_mechatronics* m, const char* path) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !path || !path[0]) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics or path is NULL or empty");
    return guarded(context, [&] {
        load_all_or_nothing(m, std::string("object library '") + path + "' has problems",
                            [&](MechatronicSpec& s, std::vector<DriveError>&) { s.library.load_file(path); });
    });
}

MBX_API mbx_status mbx_mechatronics_load_library_text(mbx_context* context, mbx_mechatronics* m, const char* text,
                                                      const char* name) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !text) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics or text is NULL");
    const std::string file = name && name[0] ? name : "<library text>";
    return guarded(context, [&] {
        load_all_or_nothing(m, "object library '" + file + "' has problems",
                            [&](MechatronicSpec& s, std::vector<DriveError>&) { s.library.load_text(text, file); });
    });
}

MBX_API mbx_status mbx_mechatronics_load_drives(mbx_context* context, mbx_mechatronics* m, const char* path) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !path || !path[0]) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics or path is NULL or empty");
    return guarded(context, [&] {
        load_all_or_nothing(m, std::string("drive description '") + path + "' has problems",
                            [&](MechatronicSpec& s, std::vector<DriveError>& e) { load_drive_file(path, s, e); });
    });
}

MBX_API mbx_status mbx_mechatronics_load_drives_text(mbx_context* context, mbx_mechatronics* m, const char* text,
                                                     const char* name) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !text) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics or text is NULL");
    const std::string file = name && name[0] ? name : "<description text>";
    return guarded(context, [&] {
        load_all_or_nothing(m, "drive description '" + file + "' has problems",
                            [&](MechatronicSpec& s, std::vector<DriveError>& e) { load_drive_text(text, file, "", s, e); });
    });
}

MBX_API mbx_status mbx_mechatronics_add_drive(mbx_context* context, mbx_mechatronics* m, const mbx_drive_desc* desc) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !desc) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics or drive is NULL");
    if (desc->struct_size < offsetof(mbx_drive_desc, override_count) + sizeof(uint32_t))
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "drive.struct_size is too small for an ABI 5 drive");
    return guarded(context, [&] {
        DriveSpec d;
        d.name = text_or_empty(desc->name);
        d.joint.constraint_id = text_or_empty(desc->constraint_id);
        d.joint.primitive = desc->primitive_index < 0 ? -1 : desc->primitive_index;
        d.motor_id = text_or_empty(desc->motor_id);
        d.transmission_id = text_or_empty(desc->transmission_id);
        const Subject who = Subject::constraint(d.joint.constraint_id, d.name);
        auto bad = [&](const std::string& what) { throw Error(MBX_ERROR_INVALID_INPUT, who, "drive on constraint '" + d.joint.constraint_id + "': " + what); };
        if (d.joint.constraint_id.empty()) bad("constraint_id is required");
        if (d.motor_id.empty()) bad("motor_id is required");
        const int mode = raw_enum(desc->amplifier_mode);
        if (!valid_enum(mode, MBX_AMPLIFIER_CURRENT)) bad("unknown amplifier_mode " + std::to_string(mode));
        d.amplifier.mode = mode == MBX_AMPLIFIER_CURRENT ? AmplifierMode::Current : AmplifierMode::Voltage;
        d.amplifier.gain = desc->amplifier_gain;
        if (d.amplifier.mode == AmplifierMode::Current && !(std::isfinite(d.amplifier.gain) && d.amplifier.gain > 0))
            bad("a current amplifier needs a positive, finite amplifier_gain");
        const mbx_controller_desc* c = desc->controller;
        if (!c) bad("controller is required");
        if (c->struct_size < offsetof(mbx_controller_desc, velocity_estimate) + sizeof(int))
            bad("controller.struct_size is too small");
        d.controller.kp = c->kp;
        d.controller.ki = c->ki;
        d.controller.kd = c->kd;
        d.controller.kv = c->kv;
        d.controller.kvi = c->kvi;
        d.controller.sample_period = c->sample_period;
        d.controller.delay = c->delay;
        d.controller.output_limit = c->output_limit;
        const int ve = raw_enum(c->velocity_estimate);
        if (!valid_enum(ve, MBX_VELOCITY_FILTERED_DIFFERENCE)) bad("unknown velocity_estimate " + std::to_string(ve));
        d.controller.velocity_estimate = VelocityEstimate(ve);
        for (const auto& [name, v] : controller_values(d.controller))
            if (!std::isfinite(v) || v < 0) bad("controller values must be finite and not negative");
        if (desc->override_count && !desc->overrides) bad("overrides is NULL with override_count > 0");
        for (uint32_t i = 0; i < desc->override_count; ++i) {
            const mbx_parameter_override& o = desc->overrides[i];
            if (!o.name || !o.name[0]) bad("override " + std::to_string(i) + " has no name");
            if (!std::isfinite(o.value)) bad(std::string("override '") + o.name + "' is not finite");
            d.overrides[o.name] = o.value;
        }
        if (DriveSpec* old = find_drive(m->spec, d.joint.constraint_id, d.joint.primitive)) {
            d.motion = old->motion;  // a replaced drive keeps its motion
            *old = std::move(d);
        } else {
            m->spec.drives.push_back(std::move(d));
        }
    });
}

MBX_API mbx_status mbx_mechatronics_set_motion(mbx_context* context, mbx_mechatronics* m, const char* constraint_id,
                                               int32_t primitive_index, const mbx_motion_point* points, uint32_t count,
                                               mbx_interpolation interpolation) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !constraint_id || (count && !points))
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics, constraint_id or points is NULL");
    return guarded(context, [&] {
        const Subject who = Subject::constraint(constraint_id, {});
        DriveSpec* d = find_drive(m->spec, constraint_id, primitive_index < 0 ? -1 : primitive_index);
        if (!d)
            throw Error(MBX_ERROR_INVALID_INPUT, who,
                        std::string("no drive on constraint '") + constraint_id + "': add the drive first");
        const int raw = raw_enum(interpolation);
        if (!valid_enum(raw, MBX_INTERPOLATION_STEP))
            throw Error(MBX_ERROR_INVALID_ARGUMENT, who, "unknown interpolation " + std::to_string(raw));
        std::vector<MotionPoint> pts(count);
        for (uint32_t i = 0; i < count; ++i) pts[i] = {points[i].time, points[i].value};
        try {
            d->motion = MotionProfile(std::move(pts), raw == MBX_INTERPOLATION_SMOOTH ? Interpolation::Smooth
                                                      : raw == MBX_INTERPOLATION_STEP ? Interpolation::Step
                                                                                      : Interpolation::Linear);
        } catch (const std::invalid_argument& e) {
            throw Error(MBX_ERROR_INVALID_INPUT, who, std::string("motion of constraint '") + constraint_id + "': " + e.what());
        }
    });
}

MBX_API uint32_t mbx_mechatronics_drive_count(const mbx_mechatronics* m) { return m ? uint32_t(m->spec.drives.size()) : 0; }

MBX_API mbx_status mbx_mechatronics_set_joint_dynamics(mbx_context* context, mbx_mechatronics* m,
                                                       const mbx_joint_dynamics_desc* dynamics) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !dynamics) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics or dynamics is NULL");
    return guarded(context, [&] {
        mbx_joint_dynamics_desc d{};
        if (dynamics->struct_size < 2 * sizeof(uint32_t))
            throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject{}, "mbx_joint_dynamics_desc.struct_size is too small");
        std::memcpy(&d, dynamics, std::min<size_t>(dynamics->struct_size, sizeof d));
        const std::string id = text_or_empty(d.constraint_id);
        if (id.empty()) throw Error(MBX_ERROR_INVALID_INPUT, Subject{}, "joint dynamics need a constraint_id");
        JointDynamicsSpec spec;
        spec.joint = {id, d.primitive_index};
        // Fields past a caller's struct_size were left zero by the memcpy above.
#define MBX_COPY_FROM_DESC(field) spec.field = d.field;
        MBX_JOINT_DYNAMICS_SCALARS(MBX_COPY_FROM_DESC)
#undef MBX_COPY_FROM_DESC
        spec.limited = d.limited != 0;
        // A caller built against ABI 6 declares a struct_size that ends
        // before these: the memcpy above left them zero, the old symmetric law.
        if (MBX_FIELD_FITS(&d, mbx_joint_dynamics_desc, asymmetric) && d.asymmetric != 0) {
            spec.coulomb_negative = d.coulomb_negative;
            spec.damping_negative = d.damping_negative;
        }
        const Subject joint = Subject::constraint(id, "");
        for (const auto& [name, value] : joint_dynamics_coefficients(spec))
            if (!std::isfinite(value) || value < 0)
                throw Error(MBX_ERROR_INVALID_INPUT, joint, "joint dynamics of '" + id + "': " + name + " must be finite and not negative");
        if (!std::isfinite(spec.rest)) throw Error(MBX_ERROR_INVALID_INPUT, joint, "joint dynamics of '" + id + "': rest is not finite");
        for (const std::string& problem : joint_dynamics_problems(spec))
            throw Error(MBX_ERROR_INVALID_INPUT, joint, "joint dynamics of '" + id + "': " + problem);
        if (spec.limited && !(std::isfinite(spec.lower) && std::isfinite(spec.upper) && spec.lower <= spec.upper))
            throw Error(MBX_ERROR_INVALID_INPUT, joint, "joint dynamics of '" + id + "': limits need finite lower <= upper");
        for (JointDynamicsSpec& existing : m->spec.joint_dynamics)
            if (existing.joint.constraint_id == id && existing.joint.primitive == d.primitive_index) {
                existing = spec;
                return;
            }
        m->spec.joint_dynamics.push_back(spec);
    });
}

MBX_API mbx_status mbx_mechatronics_set_body_correction(mbx_context* context, mbx_mechatronics* m,
                                                        const mbx_body_correction_desc* correction) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !correction) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics or correction is NULL");
    return guarded(context, [&] {
        mbx_body_correction_desc d{};
        if (correction->struct_size < 2 * sizeof(uint32_t))
            throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject{}, "mbx_body_correction_desc.struct_size is too small");
        std::memcpy(&d, correction, std::min<size_t>(correction->struct_size, sizeof d));
        const std::string id = text_or_empty(d.body_id);
        if (id.empty()) throw Error(MBX_ERROR_INVALID_INPUT, Subject{}, "a body correction needs a body_id");
        const Subject body{MBX_SUBJECT_BODY, id, id};
        BodyMassSpec spec;
        spec.body = id;
        spec.mass_scale = d.mass_scale == 0 ? 1 : d.mass_scale;
        if (!(std::isfinite(spec.mass_scale) && spec.mass_scale > 0))
            throw Error(MBX_ERROR_INVALID_INPUT, body, "body correction of '" + id + "': mass_scale must be positive");
        for (int k = 0; k < 3; ++k) spec.com_shift[k] = d.com_shift[k];
        for (int k = 0; k < 6; ++k) spec.inertia_change[size_t(k)] = d.inertia_change[k];
        bool finite = spec.com_shift.allFinite();
        for (double v : spec.inertia_change) finite = finite && std::isfinite(v);
        if (!finite)
            throw Error(MBX_ERROR_INVALID_INPUT, body,
                        "body correction of '" + id + "': com_shift and inertia_change must be finite");
        for (BodyMassSpec& existing : m->spec.body_masses)
            if (existing.body == id) {
                existing = spec;
                return;
            }
        m->spec.body_masses.push_back(spec);
    });
}

MBX_API mbx_status mbx_mechanism_set_mechatronics(mbx_context* context, mbx_mechanism* mechanism,
                                                  const mbx_mechatronics* m) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!mechanism || !mechanism->model) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechanism is NULL");
    return guarded(context, [&] {
        if (!m) {
            mechanism->drives.clear();
            mechanism->joint_dynamics.clear();
            mechanism->body_masses.clear();
            mechanism->contact = {};
            mechanism->mounting = {};
            if (mechanism->cad_inertia) apply_body_masses(*mechanism->model, *mechanism->cad_inertia, {});
            return;
        }
        std::vector<DriveError> errors;
        std::vector<Drive> drives = resolve_drives(m->spec, *mechanism->model, errors);
        if (!errors.empty()) {
            // A drive is about a CAD joint: name it by its constraint id.
            const DriveSpec* culprit = first_unresolved(m->spec, drives);
            const Subject joint = culprit ? Subject::constraint(culprit->joint.constraint_id, errors.front().object)
                                          : Subject{MBX_SUBJECT_FILE, errors.front().file, errors.front().object};
            fail_with(errors, "drives do not fit the mechanism", &joint);
        }
        std::vector<ResolvedJointDynamics> dynamics = resolve_joint_dynamics(m->spec, *mechanism->model, errors);
        if (!errors.empty()) {
            const LibraryError& first = errors.front();
            const JointDynamicsSpec* culprit = nullptr;
            for (size_t i = 0; i < m->spec.joint_dynamics.size() && !culprit; ++i)
                if (i >= dynamics.size() || dynamics[i].source != int(i)) culprit = &m->spec.joint_dynamics[i];
            const Subject joint = culprit ? Subject::constraint(culprit->joint.constraint_id, first.object)
                                          : Subject{MBX_SUBJECT_FILE, first.file, first.object};
            fail_with(errors, "joint dynamics do not fit the mechanism", &joint);
        }
        std::vector<ResolvedBodyMass> masses = resolve_body_masses(m->spec.body_masses, *mechanism->model, mechanism->cad_inertia.get(), errors);
        if (!errors.empty()) {
            const LibraryError& first = errors.front();
            const Subject body{MBX_SUBJECT_BODY, first.object, first.object};
            fail_with(errors, "body corrections do not fit the mechanism", &body);
        }
        ResolvedContact contact = resolve_contact(m->spec.contact, *mechanism->model, errors);
        if (!errors.empty()) {
            const LibraryError& first = errors.front();
            const Subject body{MBX_SUBJECT_BODY, first.object, first.object};
            fail_with(errors, "collision shapes or contact materials do not fit the mechanism", &body);
        }
        mechanism->drives = std::move(drives);
        mechanism->joint_dynamics = std::move(dynamics);
        mechanism->contact = std::move(contact);
        mechanism->mounting = m->spec.mounting;
        if (!masses.empty() && !mechanism->cad_inertia)
            mechanism->cad_inertia = std::make_unique<CadInertia>(cad_inertia(*mechanism->model));
        if (mechanism->cad_inertia) apply_body_masses(*mechanism->model, *mechanism->cad_inertia, masses);
        mechanism->body_masses = std::move(masses);
    });
}

MBX_API mbx_status mbx_mechatronics_add_collision_shape(mbx_context* context, mbx_mechatronics* m,
                                                        const mbx_collision_shape_desc* desc) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !desc) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics or shape is NULL");
    if (desc->struct_size < sizeof(mbx_collision_shape_desc))
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mbx_collision_shape_desc.struct_size is too small");
    return guarded(context, [&] {
        CollisionSpec s;
        s.body = text_or_empty(desc->body_id);
        s.name = text_or_empty(desc->name);
        const std::string who = s.name.empty() ? s.body : s.name;
        auto bad = [&](const std::string& what) {
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::body(s.body, s.name), "collision shape '" + who + "': " + what);
        };
        if (s.body.empty()) bad("body_id is required (a rigid body's or CAD part's id, \"world\" or \"*\")");
        const int kind = raw_enum(desc->kind);
        if (!valid_enum(kind, MBX_COLLISION_HULL)) bad("unknown kind " + std::to_string(kind));
        s.kind = CollisionKind(kind);
        s.radius = desc->radius, s.length = desc->length;
        for (int k = 0; k < 3; ++k) s.size[k] = desc->size[k], s.position[k] = desc->position[k], s.rpy[k] = desc->rpy[k];
        if (desc->material && desc->material[0]) s.material = desc->material;
        if (desc->group != 0 || desc->mask != 0) s.group = desc->group, s.mask = desc->mask;
        s.file = "";
        for (const std::string& problem : collision_problems(s)) bad(problem);
        m->spec.contact.shapes.push_back(std::move(s));
    });
}

MBX_API mbx_status mbx_mechatronics_set_contact_material(mbx_context* context, mbx_mechatronics* m,
                                                         const mbx_contact_material_desc* desc) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!m || !desc) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechatronics or material is NULL");
    if (desc->struct_size < sizeof(mbx_contact_material_desc))
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mbx_contact_material_desc.struct_size is too small");
    return guarded(context, [&] {
        ContactMaterialSpec c;
        c.a = text_or_empty(desc->material_a);
        c.b = text_or_empty(desc->material_b);
        const std::string who = c.a.empty() && c.b.empty() ? "default contact" : "contact " + c.a + "/" + c.b;
        auto bad = [&](const std::string& what) {
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(who), who + ": " + what);
        };
        if (c.a.empty() != c.b.empty()) bad("give both materials, or neither for the default");
        const int law = raw_enum(desc->normal_law), friction = raw_enum(desc->friction_law);
        if (!valid_enum(law, MBX_CONTACT_SPRING)) bad("unknown normal_law " + std::to_string(law));
        if (!valid_enum(friction, MBX_CONTACT_FRICTION_REGULARISED)) bad("unknown friction_law " + std::to_string(friction));
        c.normal = ContactNormalLaw(law);
        c.stiffness = desc->stiffness;
        c.exponent = desc->exponent != 0 ? desc->exponent : c.normal == ContactNormalLaw::HuntCrossley ? 1.5 : 1;
        c.damping = desc->damping;
        c.use_restitution = desc->use_restitution != 0;
        c.restitution = desc->restitution;
        c.impact_speed = desc->impact_speed != 0 ? desc->impact_speed : 1;
        if (c.normal == ContactNormalLaw::Spring && (c.damping != 0 || c.use_restitution)) bad("the spring law has no damping");
        c.mu_static = desc->mu_static, c.mu_kinetic = desc->mu_kinetic;
        c.friction = ContactFrictionLaw(friction);
        c.friction_stiffness = desc->friction_stiffness, c.friction_damping = desc->friction_damping;
        c.stick_speed = desc->stick_speed != 0 ? desc->stick_speed : 1e-3;
        c.smoothing_speed = desc->smoothing_speed != 0 ? desc->smoothing_speed : 1e-3;
        for (const std::string& problem : contact_material_problems(c)) bad(problem);
        for (ContactMaterialSpec& existing : m->spec.contact.materials)
            if ((existing.a == c.a && existing.b == c.b) || (existing.a == c.b && existing.b == c.a)) {
                existing = c;
                return;
            }
        m->spec.contact.materials.push_back(std::move(c));
    });
}

MBX_API uint32_t mbx_mechanism_collision_shape_count(const mbx_mechanism* mechanism) {
    return mechanism ? uint32_t(mechanism->contact.shapes.size()) : 0;
}

MBX_API uint32_t mbx_mechanism_drive_count(const mbx_mechanism* mechanism) {
    return mechanism ? uint32_t(mechanism->drives.size()) : 0;
}

MBX_API mbx_status mbx_mechanism_get_drive(const mbx_mechanism* mechanism, uint32_t index, mbx_drive_info* out) {
    if (!mechanism || !out || index >= mechanism->drives.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const Drive& d = mechanism->drives[index];
    mbx_drive_info info{};
    info.struct_size = sizeof info;
    info.name = d.name.c_str();
    info.joint = uint32_t(d.joint);
    info.linear = d.linear;
    info.motor_name = d.motor_name.c_str();
    info.transmission_name = d.transmission_name.c_str();
    info.ratio = d.ratio;
    info.efficiency = d.efficiency;
    info.armature = d.armature;
    info.effort_limit = d.effort_limit;
    info.velocity_limit = d.velocity_limit;
    info.output_limit = d.output_limit;
    info.torque_constant = d.motor.torque_constant;
    info.stall_torque = d.motor.stall_torque;
    info.no_load_speed = d.motor.no_load_speed;
    info.rotor_inertia = d.motor.rotor_inertia;
    info.servo_stiffness = d.servo.stiffness;
    info.servo_damping = d.servo.damping;
    info.emf_damping = d.servo.emf_damping;
    info.motion_point_count = uint32_t(d.spec.motion.points().size());
    return copy_out(out, info);
}

MBX_API mbx_status mbx_mechanism_drive_target(const mbx_mechanism* mechanism, uint32_t index, double time,
                                              double out[3]) {
    if (!mechanism || !out || index >= mechanism->drives.size() || !std::isfinite(time))
        return MBX_ERROR_INVALID_ARGUMENT;
    const MotionSample s = mechanism->drives[index].spec.motion.at(time);
    out[0] = s.position;
    out[1] = s.velocity;
    out[2] = s.acceleration;
    return MBX_OK;
}

}  // extern "C"
