// mbx_excite and the excitation handle: calibration/excitation's design on a
// translated mechanism with its attached drives and joint dynamics, the
// limits gathered from the model (description or CAD range, the host's rated
// speed and effort, the drives') and the options, the causes from the
// options and a calibration.json, and the files of excitation_files.h.
#include <chrono>
#include <cmath>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "calibration/outputs/excitation_files.h"
#include "core/input_file.h"
#include "core/report/json_value.h"
#include "sdk/capi/build_options_of.h"
#include "sdk/capi/guard.h"
#include "sim/build_model.h"
#include "sim/resolved_joint_dynamics.h"

using namespace mbx;
using namespace mbx::calibration;

struct mbx_excitation {
    ExcitationDesign design;
    ExcitationReport report;
    std::vector<std::string> ids, names;
    double wall_time = 0;
};

namespace {

// An error in a file the design reads, named with its path (and line).
[[noreturn]] void file_error(mbx_status status, const std::string& path, const std::string& what) {
    throw Error(status, Subject::model("excitation"), path + ": " + what);
}

[[noreturn]] void bad_input(const std::string& what) { throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("excitation"), what); }

// What a calibration.json asks the design to settle: the causes it named and
// the groups its warnings could not tell apart, as "cause on subject"; and
// the standard errors its records gave, by "cause.parameter on subject".
struct CalibrationAsk {
    std::vector<std::string> causes;
    std::vector<std::pair<std::string, double>> std_errors;
};

CalibrationAsk read_calibration_json(const std::string& path) {
    // calibration.json is a few kilobytes: a file far larger is not one.
    constexpr uintmax_t kMaxBytes = 64u << 20;
    std::error_code ec;
    const uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (!ec && bytes > kMaxBytes)
        file_error(MBX_ERROR_INVALID_INPUT, path, "is " + std::to_string(bytes >> 20) + " MB, more than the 64 MB a calibration.json may have");
    std::string text;
    {
        std::string why;
        if (!read_input_file(path, text, why)) file_error(MBX_ERROR_IO, path, "cannot be read (the calibration.json of mbx calibrate): " + why);
    }
    JsonValue root;
    try {
        root = parse_json(text);
    } catch (const JsonError& e) {
        file_error(MBX_ERROR_INVALID_INPUT, path, "line " + std::to_string(e.line()) + ": " + e.what());
    }
    auto fail = [&](int line, const std::string& why) -> void {
        file_error(MBX_ERROR_INVALID_INPUT, path, "line " + std::to_string(line) + ": " + why + " (not a calibration.json of mbx calibrate?)");
    };
    CalibrationAsk ask;
    const JsonValue* causes = root.find("causes");
    if (!causes || causes->kind != JsonValue::Kind::array) fail(root.line, "no \"causes\" array");
    for (const JsonValue& c : causes->array) {
        const JsonValue* name = c.find("cause");
        const JsonValue* subject = c.find("subject");
        if (!name || name->kind != JsonValue::Kind::string || !subject) fail(c.line, "a cause without name or subject");
        const JsonValue* kind = subject->find("kind");
        const JsonValue* who = subject->find("name");
        if (!kind || !who || kind->kind != JsonValue::Kind::string) fail(c.line, "a cause's subject without kind or name");
        const std::string on = kind->string == "mounting" ? "the mounting" : kind->string + " '" + who->string + "'";
        ask.causes.push_back(name->string + " on " + on);
        if (const JsonValue* params = c.find("parameters"))
            for (const JsonValue& p : params->array) {
                const JsonValue* pn = p.find("name");
                const JsonValue* se = p.find("std_error");
                if (pn && se && se->kind == JsonValue::Kind::number)
                    ask.std_errors.emplace_back(name->string + "." + pn->string + " on " + on, se->number);
            }
    }
    if (const JsonValue* groups = root.find("ambiguous"))
        for (const JsonValue& g : groups->array)
            for (const JsonValue& c : g.array) {
                if (c.kind != JsonValue::Kind::string) fail(c.line, "an ambiguous group's cause is not a string");
                if (std::find(ask.causes.begin(), ask.causes.end(), c.string) == ask.causes.end()) ask.causes.push_back(c.string);
            }
    if (ask.causes.empty())
        file_error(MBX_ERROR_INVALID_INPUT, path, "names no cause and warns of no group: there is nothing for a design to settle");
    return ask;
}

// The sim joint a name or CAD id means.
int joint_named_in(const sim::Model& m, const std::string& who) {
    for (size_t j = 0; j < m.joints.size(); ++j)
        if (m.joints[j].name == who || (!m.joints[j].constraint_id.empty() && m.joints[j].constraint_id == who)) return int(j);
    return -1;
}

bool one_coordinate(const sim::JointT<double>& j) {
    return j.kind == sim::JointKind::Revolute || j.kind == sim::JointKind::Prismatic;
}

}  // namespace

extern "C" {

MBX_API mbx_status mbx_excite(mbx_context* context, const mbx_mechanism* mechanism, const mbx_excite_options* options,
                              mbx_excitation** out) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!out) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "out_excitation is NULL");
    *out = nullptr;
    if (!mechanism || !mechanism->model) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechanism is NULL");
    return guarded(context, [&] {
        const auto t0 = std::chrono::steady_clock::now();
        mbx_excite_options o{};
        o.struct_size = sizeof o;
        if (options) {
            if (options->struct_size < 2 * sizeof(uint32_t)) bad_argument("mbx_excite_options.struct_size is too small");
            std::memcpy(&o, options, std::min<size_t>(options->struct_size, sizeof o));
        }
        sim::BuildOptions build = build_options_of(*mechanism, o.flags, o.gravity);
        const sim::Model m = sim::build_model(*mechanism->model, build);
        const Mechanism& mech = *mechanism->model;

        ExcitationOptions eo;
        if (o.period != 0) eo.period = o.period;
        if (o.harmonics != 0) eo.harmonics = int(std::min<uint32_t>(o.harmonics, 1000000));
        if (o.periods != 0) eo.periods = int(std::min<uint32_t>(o.periods, 1000000));
        if (o.flags & MBX_EXCITE_SET_MARGIN) eo.margin = o.margin;
        if (o.sample_rate != 0) eo.sample_rate = o.sample_rate;
        if (o.cutoff != 0) eo.cutoff = o.cutoff;
        if (o.noise_share != 0) eo.noise_share = o.noise_share;
        if (o.evaluations != 0) eo.evaluations = int(std::min<uint32_t>(o.evaluations, 2000000));
        if (o.seed != 0) eo.seed = o.seed;
        if (!(o.acceleration_limit >= 0) || std::isinf(o.acceleration_limit))
            bad_argument("acceleration_limit must be finite and not negative");
        if (o.cause_count > 0 && !o.causes) bad_argument("cause_count is set but causes is NULL");
        if (o.joint_count > 0 && !o.joints) bad_argument("joint_count is set but joints is NULL");
        if (o.limit_count > 0 && !o.limits) bad_argument("limit_count is set but limits is NULL");
        for (uint32_t k = 0; k < o.cause_count; ++k) {
            if (!o.causes[k] || !*o.causes[k]) bad_argument("causes[" + std::to_string(k) + "] is empty");
            eo.causes.push_back(o.causes[k]);
        }
        auto handle = std::make_unique<mbx_excitation>();
        if (o.calibration && *o.calibration) {
            CalibrationAsk ask = read_calibration_json(o.calibration);
            for (const std::string& c : ask.causes)
                if (std::find(eo.causes.begin(), eo.causes.end(), c) == eo.causes.end()) eo.causes.push_back(c);
            handle->report.measured_std_error = std::move(ask.std_errors);
        }
        if (context->progress) {
            mbx_progress_fn fn = context->progress;
            void* user = context->progress_user;
            eo.progress = [fn, user](double fraction) { return fn(user, "excite", fraction) == 0; };
        }

        // The joints: named, or driven, or rated, or every tree joint of a loop-free model.
        std::vector<int> joints;
        for (uint32_t k = 0; k < o.joint_count; ++k) {
            if (!o.joints[k]) bad_argument("joints[" + std::to_string(k) + "] is NULL");
            const int j = joint_named_in(m, o.joints[k]);
            if (j < 0) bad_input(std::string("no joint '") + o.joints[k] + "' in the model");
            if (!one_coordinate(m.joints[size_t(j)])) bad_input(std::string("joint '") + o.joints[k] + "' is not a revolute or sliding joint");
            if (std::find(joints.begin(), joints.end(), j) == joints.end()) joints.push_back(j);
        }
        const auto rated = [&](const sim::JointT<double>& j) -> const Primitive* {
            if (j.source < 0) return nullptr;
            const Joint& mj = mech.joints[size_t(j.source)];
            return &mech.assembly.constraints[size_t(mj.constraint)].chain[size_t(mj.primitive_index)];
        };
        const auto drive_of = [&](const sim::JointT<double>& j) -> const Drive* {
            for (const Drive& d : mechanism->drives)
                if (d.joint == j.source) return &d;
            return nullptr;
        };
        if (joints.empty())
            for (size_t j = 0; j < m.joints.size(); ++j)
                if (one_coordinate(m.joints[j]) && drive_of(m.joints[j])) joints.push_back(int(j));
        if (joints.empty())
            for (size_t j = 0; j < m.joints.size(); ++j)
                if (const Primitive* p = one_coordinate(m.joints[j]) ? rated(m.joints[j]) : nullptr;
                    p && (p->velocity_limit > 0 || p->effort_limit > 0))
                    joints.push_back(int(j));
        if (joints.empty() && mech.loops.empty())
            for (size_t j = 0; j < m.joints.size(); ++j)
                if (one_coordinate(m.joints[j])) joints.push_back(int(j));
        if (joints.empty())
            bad_input("no joint to design for: the model has loops and no drive or rated joint (name the actuated joints)");

        // Their limits: the model's, then the options'.
        std::vector<int> dofs;
        std::vector<ExcitationLimits> limits;
        std::vector<std::string> sources;
        std::vector<char> overridden(o.limit_count, 0);
        std::vector<ExcitationServo> servos;
        for (int j : joints) {
            const sim::JointT<double>& joint = m.joints[size_t(j)];
            dofs.push_back(joint.v_index);
            ExcitationLimits L;
            std::vector<std::string> from;
            if (joint.dynamics.limited) {
                L.lower = joint.dynamics.lower, L.upper = joint.dynamics.upper;
                from.push_back("range: model");
            }
            if (const Primitive* p = rated(joint)) {
                if (p->velocity_limit > 0) L.velocity = p->velocity_limit, from.push_back("speed: rated");
                if (p->effort_limit > 0) L.effort = p->effort_limit, from.push_back("effort: rated");
            }
            ExcitationServo servo;
            if (const Drive* d = drive_of(joint)) {
                if (d->velocity_limit > 0 && d->velocity_limit < L.velocity) L.velocity = d->velocity_limit, from.push_back("speed: drive");
                if (d->effort_limit > 0 && d->effort_limit < L.effort) L.effort = d->effort_limit, from.push_back("effort: drive");
                // The drive's controller as the servo that will follow the
                // reference (kd and a velocity loop act on the measured speed,
                // the back-EMF brakes it).
                servo.stiffness = d->servo.stiffness, servo.damping = d->servo.damping + d->servo.emf_damping;
                if (servo.stiffness > 0) from.push_back("servo: drive");
            }
            servos.push_back(servo);
            if (o.acceleration_limit > 0) L.acceleration = o.acceleration_limit, from.push_back("acceleration: option");
            for (uint32_t k = 0; k < o.limit_count; ++k) {
                const mbx_joint_limits& given = o.limits[k];
                if (given.struct_size < sizeof(uint32_t) + sizeof(const char*)) bad_argument("mbx_joint_limits.struct_size is too small");
                mbx_joint_limits g{};
                std::memcpy(&g, &given, std::min<size_t>(given.struct_size, sizeof g));
                if (!g.joint) bad_argument("limits[" + std::to_string(k) + "].joint is NULL");
                if (joint_named_in(m, g.joint) != j) continue;
                overridden[k] = 1;
                double* field[5] = {&L.lower, &L.upper, &L.velocity, &L.acceleration, &L.effort};
                const double value[5] = {g.lower, g.upper, g.velocity, g.acceleration, g.effort};
                for (int f = 0; f < 5; ++f)
                    if (!std::isnan(value[f])) *field[f] = value[f];
                from.push_back("option");
            }
            std::string s;
            for (const std::string& f : from) s += (s.empty() ? "" : ", ") + f;
            sources.push_back(s.empty() ? "none" : s);
            limits.push_back(L);
            handle->ids.push_back(joint.constraint_id);
            handle->names.push_back(joint.name);
        }
        for (uint32_t k = 0; k < o.limit_count; ++k)
            if (!overridden[k]) bad_input(std::string("limits for '") + o.limits[k].joint + "': not a joint designed for");

        if (std::any_of(servos.begin(), servos.end(), [](const ExcitationServo& sv) { return sv.stiffness > 0; }))
            eo.servo = servos;
        handle->design = design_excitation(m, dofs, limits, eo);
        handle->report.limits = limits;
        handle->report.limit_sources = sources;
        handle->report.options = eo;
        handle->report.input = m.name;
        if (o.directory) write_excitation_files(o.directory, m, handle->design, handle->report);
        handle->wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        *out = handle.release();
    });
}

MBX_API void mbx_excitation_destroy(mbx_excitation* e) { delete e; }

MBX_API mbx_status mbx_excitation_get_summary(const mbx_excitation* e, mbx_excitation_summary* out) {
    if (!e) return MBX_ERROR_INVALID_ARGUMENT;
    mbx_excitation_summary s{};
    s.struct_size = sizeof s;
    s.joint_count = uint32_t(e->design.dofs.size());
    s.parameter_count = uint32_t(e->design.predicted.names.size());
    s.periods = uint32_t(e->design.periods);
    s.evaluations = uint32_t(e->design.evaluations);
    s.period = e->design.period;
    s.criterion = e->design.predicted.criterion;
    s.wall_time = e->wall_time;
    s.dropped_count = uint32_t(e->design.dropped.size());
    return copy_out(out, s);
}

MBX_API mbx_status mbx_excitation_get_joint(const mbx_excitation* e, uint32_t index, mbx_excitation_joint* out) {
    if (!e || index >= e->design.dofs.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const ExcitationDesign& d = e->design;
    const ExcitationLimits& L = e->report.limits[index];
    mbx_excitation_joint j{};
    j.struct_size = sizeof j;
    j.id = e->ids[index].c_str();
    j.name = e->names[index].c_str();
    j.start = d.references[index].q0;
    j.lower = L.lower, j.upper = L.upper, j.velocity = L.velocity, j.acceleration = L.acceleration, j.effort = L.effort;
    j.limit_source = e->report.limit_sources[index].c_str();
    j.lowest = d.lowest[index], j.highest = d.highest[index];
    j.peak_velocity = d.peak_velocity[index], j.peak_acceleration = d.peak_acceleration[index];
    j.peak_effort = d.peak_effort[index];
    return copy_out(out, j);
}

MBX_API mbx_status mbx_excitation_get_parameter(const mbx_excitation* e, uint32_t index, mbx_excitation_parameter* out) {
    if (!e || index >= e->design.predicted.names.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const ExcitationDesign& d = e->design;
    mbx_excitation_parameter p{};
    p.struct_size = sizeof p;
    p.name = d.predicted.names[index].c_str();
    p.std_error = d.predicted.std_error[Eigen::Index(index)];
    p.random_multisine_std_error =
        index < size_t(d.reference.std_error.size()) ? d.reference.std_error[Eigen::Index(index)] : NAN;
    p.measured_std_error = measured_std_error(e->report, d.predicted.names[index]);
    return copy_out(out, p);
}

MBX_API const char* mbx_excitation_get_dropped(const mbx_excitation* e, uint32_t index) {
    if (!e || index >= e->design.dropped.size()) return nullptr;
    return e->design.dropped[index].c_str();
}

MBX_API mbx_status mbx_excitation_sample(const mbx_excitation* e, double t, double* q, double* qd, double* qdd) {
    if (!e || !std::isfinite(t)) return MBX_ERROR_INVALID_ARGUMENT;
    const ExcitationDesign& d = e->design;
    const double at = std::clamp(t, 0.0, d.period * d.periods);
    for (size_t i = 0; i < d.references.size(); ++i) {
        double a, b, c;
        d.references[i].at(at, d.period, a, b, c);
        if (q) q[i] = a;
        if (qd) qd[i] = b;
        if (qdd) qdd[i] = c;
    }
    return MBX_OK;
}

}  // extern "C"
