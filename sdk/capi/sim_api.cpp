// The simulation entry points: a model built from a mechanism (with its
// drives), data objects holding state, stepping, dynamics queries and runs
// that write their files.
#include <cmath>
#include <cstring>
#include <optional>

#include "sdk/capi/contact_build.h"
#include "sdk/capi/build_options_of.h"
#include "sdk/capi/guard.h"
#include "sdk/capi/sim_handles.h"
#include "sim/build_model.h"
#include "sim/resolved_joint_dynamics.h"

using namespace mbx;
using namespace mbx::sim;

namespace {


const JointT<double>& joint_at(const Model& m, uint32_t index) {
    if (index >= m.joints.size())
        bad_argument("joint index " + std::to_string(index) + " is out of range (" + std::to_string(m.joints.size()) + " joints)");
    return m.joints[index];
}

// Refuses non-finite entries of a state array, naming the joint they belong to.
void check_values(const Model& m, const double* values, bool velocities, const char* what) {
    for (const JointT<double>& j : m.joints) {
        const int first = velocities ? j.v_index : j.q_index, n = velocities ? j.nv() : j.nq();
        for (int k = 0; k < n; ++k)
            if (!std::isfinite(values[first + k]))
                throw Error(MBX_ERROR_INVALID_INPUT, j.subject(),
                            std::string("joint '") + j.name + "': " + what + " is not finite");
    }
}

void normalise_quaternions(const Model& m, Data& d) {
    for (const JointT<double>& j : m.joints) {
        if (j.kind != JointKind::Spherical && j.kind != JointKind::Free) continue;
        Eigen::Map<Eigen::Vector4d> quat(d.q.data() + j.q_index + (j.kind == JointKind::Free ? 3 : 0));
        if (!(quat.norm() > 1e-12))
            throw Error(MBX_ERROR_INVALID_INPUT, j.subject(), "joint '" + j.name + "': quaternion of zero length");
        quat.normalize();
    }
}

}  // namespace

extern "C" {

MBX_API mbx_status mbx_sim_model_create(mbx_context* context, const mbx_mechanism* mechanism,
                                        const mbx_sim_options* options, mbx_sim_model** out) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!out) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "out_model is NULL");
    *out = nullptr;
    if (!mechanism || !mechanism->model) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechanism is NULL");
    return guarded(context, [&] {
        // Options the caller's struct_size covers; defaults for the rest.
        mbx_sim_options o{};
        o.struct_size = sizeof o;
        if (options) {
            if (options->struct_size < 2 * sizeof(uint32_t)) bad_argument("mbx_sim_options.struct_size is too small");
            std::memcpy(&o, options, std::min<size_t>(options->struct_size, sizeof o));
        }
        BuildOptions build = build_options_of(*mechanism, o.flags, o.gravity);
        auto handle = std::make_unique<mbx_sim_model>();
        const int integrator = raw_enum(o.integrator);
        switch (integrator) {
        case MBX_INTEGRATOR_RK4: handle->integrator.kind = IntegratorKind::RK4; break;
        case MBX_INTEGRATOR_EULER: handle->integrator.kind = IntegratorKind::Euler; break;
        case MBX_INTEGRATOR_ACCURATE: handle->integrator.kind = IntegratorKind::Accurate; break;
        default: bad_argument("unknown integrator " + std::to_string(integrator));
        }
        if (o.step != 0) {
            if (!(std::isfinite(o.step) && o.step > 0)) bad_argument("the step must be positive");
            handle->integrator.step = o.step;
        }
        if (o.tolerance != 0) {
            if (!(std::isfinite(o.tolerance) && o.tolerance > 0 && o.tolerance < 1)) bad_argument("the tolerance must be in (0, 1)");
            handle->integrator.tolerance = o.tolerance;
        }
        handle->model = build_model(*mechanism->model, build);
        build_contact(*mechanism, *handle);
        *out = handle.release();
    });
}

MBX_API void mbx_sim_model_destroy(mbx_sim_model* model) { delete model; }

MBX_API mbx_status mbx_sim_model_get_info(const mbx_sim_model* model, mbx_sim_model_info* out) {
    if (!model) return MBX_ERROR_INVALID_ARGUMENT;
    const Model& m = model->model;
    mbx_sim_model_info info{};
    info.struct_size = sizeof info;
    info.nq = uint32_t(m.nq);
    info.nv = uint32_t(m.nv);
    info.joint_count = uint32_t(m.joints.size());
    info.drive_count = uint32_t(m.drives.size());
    info.loop_closure_count = uint32_t(m.closures.size());
    info.closure_rows = uint32_t(m.closure_rows);
    for (int k = 0; k < 3; ++k) info.gravity[k] = m.gravity[k];
    return copy_out(out, info);
}

MBX_API mbx_status mbx_sim_model_get_joint(const mbx_sim_model* model, uint32_t index, mbx_sim_joint_info* out) {
    if (!model || index >= model->model.joints.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const JointT<double>& j = model->model.joints[index];
    mbx_sim_joint_info info{};
    info.struct_size = sizeof info;
    info.name = j.name.c_str();
    info.constraint_id = j.constraint_id.c_str();
    switch (j.kind) {
    case JointKind::Revolute: info.kind = MBX_SIM_JOINT_REVOLUTE; break;
    case JointKind::Prismatic: info.kind = MBX_SIM_JOINT_PRISMATIC; break;
    case JointKind::Spherical: info.kind = MBX_SIM_JOINT_SPHERICAL; break;
    case JointKind::Fixed: info.kind = MBX_SIM_JOINT_FIXED; break;
    case JointKind::Free: info.kind = MBX_SIM_JOINT_FREE; break;
    }
    info.mechanism_joint = j.source;
    info.q_index = uint32_t(j.q_index);
    info.v_index = uint32_t(j.v_index);
    info.nq = uint32_t(j.nq());
    info.nv = uint32_t(j.nv());
    return copy_out(out, info);
}

MBX_API mbx_status mbx_sim_model_find_joint(const mbx_sim_model* model, const char* key, uint32_t* out_index) {
    if (!model || !key || !out_index) return MBX_ERROR_INVALID_ARGUMENT;
    const int j = find_joint(model->model, key);
    if (j < 0) return MBX_ERROR_INVALID_ARGUMENT;
    *out_index = uint32_t(j);
    return MBX_OK;
}

MBX_API mbx_status mbx_sim_data_create(mbx_context* context, const mbx_sim_model* model, mbx_sim_data** out) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!out) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "out_data is NULL");
    *out = nullptr;
    if (!model) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "model is NULL");
    return guarded(context, [&] { *out = new mbx_sim_data(model); });
}

MBX_API void mbx_sim_data_destroy(mbx_sim_data* data) { delete data; }

MBX_API mbx_status mbx_sim_initialize(mbx_context* context, mbx_sim_data* data, const mbx_sim_fixed_value* values,
                                      uint32_t count) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data is NULL");
    if (count && !values) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "values is NULL");
    return guarded(context, [&] {
        const Model& m = data->owner->model;
        std::vector<FixedValue> fixed;
        for (uint32_t i = 0; i < count; ++i) {
            joint_at(m, values[i].joint);
            fixed.push_back({int(values[i].joint), int(values[i].index), values[i].velocity != 0, values[i].value});
        }
        // Into a copy: a failed initialisation leaves the data as it was.
        Data trial = data->data;
        initial_state(m, trial, fixed, data->owner->integrator.closure_tolerance);
        data->data = std::move(trial);
    });
}

MBX_API mbx_status mbx_sim_get_state(const mbx_sim_data* data, double* time, double* q, double* v) {
    if (!data) return MBX_ERROR_INVALID_ARGUMENT;
    const Data& d = data->data;
    if (time) *time = d.time;
    if (q) std::memcpy(q, d.q.data(), sizeof(double) * size_t(d.q.size()));
    if (v) std::memcpy(v, d.v.data(), sizeof(double) * size_t(d.v.size()));
    return MBX_OK;
}

MBX_API mbx_status mbx_sim_set_state(mbx_context* context, mbx_sim_data* data, double time, const double* q,
                                     const double* v) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data is NULL");
    return guarded(context, [&] {
        const Model& m = data->owner->model;
        if (!std::isfinite(time)) throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name), "time is not finite");
        if (q) check_values(m, q, false, "position");
        if (v) check_values(m, v, true, "velocity");
        Data& d = data->data;
        const Eigen::VectorXd q_old = d.q;
        if (q) d.q = Eigen::Map<const Eigen::VectorXd>(q, m.nq);
        try {
            normalise_quaternions(m, d);
        } catch (...) {
            d.q = q_old;
            throw;
        }
        if (v) d.v = Eigen::Map<const Eigen::VectorXd>(v, m.nv);
        // Elastic transmissions' motors follow the joints the host placed,
        // at rest against the load (sim/transmission.h).
        if (q || v) settle_transmissions(m, d);
        d.time = time;
    });
}

MBX_API mbx_status mbx_sim_get_joint_state(const mbx_sim_data* data, uint32_t joint, double* q, double* v) {
    if (!data || joint >= data->owner->model.joints.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const JointT<double>& j = data->owner->model.joints[joint];
    if (q) for (int k = 0; k < j.nq(); ++k) q[k] = data->data.q[j.q_index + k];
    if (v) for (int k = 0; k < j.nv(); ++k) v[k] = data->data.v[j.v_index + k];
    return MBX_OK;
}

MBX_API mbx_status mbx_sim_set_joint_state(mbx_context* context, mbx_sim_data* data, uint32_t joint, const double* q,
                                           const double* v) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data is NULL");
    return guarded(context, [&] {
        const Model& m = data->owner->model;
        const JointT<double>& j = joint_at(m, joint);
        for (int k = 0; q && k < j.nq(); ++k)
            if (!std::isfinite(q[k])) throw Error(MBX_ERROR_INVALID_INPUT, j.subject(), "joint '" + j.name + "': position is not finite");
        for (int k = 0; v && k < j.nv(); ++k)
            if (!std::isfinite(v[k])) throw Error(MBX_ERROR_INVALID_INPUT, j.subject(), "joint '" + j.name + "': velocity is not finite");
        Data& d = data->data;
        if (q) {
            Eigen::VectorXd seg = Eigen::Map<const Eigen::VectorXd>(q, j.nq());
            if (j.kind == JointKind::Spherical || j.kind == JointKind::Free) {
                auto quat = seg.tail<4>();
                if (!(quat.norm() > 1e-12))
                    throw Error(MBX_ERROR_INVALID_INPUT, j.subject(), "joint '" + j.name + "': quaternion of zero length");
                quat.normalize();
            }
            d.q.segment(j.q_index, j.nq()) = seg;
        }
        if (v) d.v.segment(j.v_index, j.nv()) = Eigen::Map<const Eigen::VectorXd>(v, j.nv());
    });
}

MBX_API mbx_status mbx_sim_set_effort(mbx_context* context, mbx_sim_data* data, const double* effort) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data || !effort) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data or effort is NULL");
    return guarded(context, [&] {
        check_values(data->owner->model, effort, true, "effort");
        data->data.effort = Eigen::Map<const Eigen::VectorXd>(effort, data->owner->model.nv);
    });
}

MBX_API mbx_status mbx_sim_set_drive_target(mbx_context* context, mbx_sim_data* data, uint32_t drive, double target) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data is NULL");
    return guarded(context, [&] {
        const Model& m = data->owner->model;
        if (drive >= m.drives.size()) bad_argument("drive index " + std::to_string(drive) + " is out of range");
        if (std::isinf(target))
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::constraint(m.drives[drive].spec.joint.constraint_id, m.drives[drive].name),
                        "drive '" + m.drives[drive].name + "': target is infinite");
        data->data.drives.target_override[drive] = target;
    });
}

MBX_API mbx_status mbx_sim_step(mbx_context* context, mbx_sim_data* data, uint32_t count) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data is NULL");
    return guarded(context, [&] {
        const IntegratorSettings& s = data->owner->integrator;
        if (s.kind == IntegratorKind::Accurate) {
            advance(data->owner->model, data->data, s, data->data.time + double(count) * s.step);
            return;
        }
        for (uint32_t k = 0; k < count; ++k) fixed_step(data->owner->model, data->data, s);
    });
}

MBX_API mbx_status mbx_sim_integrate(mbx_context* context, mbx_sim_data* data, double time) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data is NULL");
    return guarded(context, [&] {
        if (!std::isfinite(time) || time < data->data.time) bad_argument("the time to integrate to must be finite and not before the current time");
        advance(data->owner->model, data->data, data->owner->integrator, time);
    });
}

MBX_API mbx_status mbx_sim_inverse_dynamics(mbx_context* context, mbx_sim_data* data, const double* qacc, double* effort) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data || !qacc || !effort) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data, qacc or effort is NULL");
    return guarded(context, [&] {
        const Model& m = data->owner->model;
        check_values(m, qacc, true, "acceleration");
        Data& d = data->data;
        update_kinematics(m, d);
        d.tmp_v = Eigen::Map<const Eigen::VectorXd>(qacc, m.nv);
        inverse_dynamics(m, d, d.tmp_v, d.tmp_v2);
        Eigen::Map<Eigen::VectorXd>(effort, m.nv) = d.tmp_v2;
    });
}

MBX_API mbx_status mbx_sim_forward_dynamics(mbx_context* context, mbx_sim_data* data, double* qacc) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data || !qacc) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data or qacc is NULL");
    return guarded(context, [&] {
        const Model& m = data->owner->model;
        Data& d = data->data;
        check_finite_state(m, d, "in the current state");
        update_controllers(m, d, d.time);
        evaluate(m, d, data->owner->integrator.kind == IntegratorKind::Accurate ? FrictionLaw::Slipping : FrictionLaw::Regularised);
        Eigen::Map<Eigen::VectorXd>(qacc, m.nv) = d.qacc;
    });
}

MBX_API mbx_status mbx_sim_mass_matrix(mbx_context* context, mbx_sim_data* data, double* matrix) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data || !matrix) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data or matrix is NULL");
    return guarded(context, [&] {
        const Model& m = data->owner->model;
        update_positions(m, data->data);
        mass_matrix(m, data->data);
        // Symmetric, so row-major and column-major agree.
        Eigen::Map<Eigen::MatrixXd>(matrix, m.nv, m.nv) = data->data.M;
    });
}

MBX_API mbx_status mbx_sim_get_energy(mbx_context* context, mbx_sim_data* data, mbx_sim_energy* out) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data || !out) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data or out is NULL");
    return guarded(context, [&] {
        const Model& m = data->owner->model;
        update_kinematics(m, data->data);
        mbx_sim_energy e{};
        e.struct_size = sizeof e;
        energy(m, data->data, e.kinetic, e.gravity, e.spring);
        e.total = e.kinetic + e.gravity + e.spring;
        if (copy_out(out, e) != MBX_OK) bad_argument("mbx_sim_energy.struct_size is too small");
    });
}

MBX_API mbx_status mbx_sim_get_drive_signals(const mbx_sim_data* data, uint32_t drive, mbx_sim_drive_signals* out) {
    if (!data || drive >= data->data.drives.signals.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const DriveSignals& s = data->data.drives.signals[drive];
    mbx_sim_drive_signals o{};
    o.struct_size = sizeof o;
    o.target = s.target;
    o.output = s.output;
    o.current = s.current;
    o.effort = s.effort;
    return copy_out(out, o);
}

MBX_API mbx_status mbx_sim_get_stats(const mbx_sim_data* data, mbx_sim_stats* out) {
    if (!data) return MBX_ERROR_INVALID_ARGUMENT;
    const RunStats& r = data->data.stats;
    mbx_sim_stats s{};
    s.struct_size = sizeof s;
    s.steps = uint64_t(r.steps);
    s.evaluations = uint64_t(r.evaluations);
    s.mode_switches = uint64_t(r.mode_switches);
    s.max_closure_residual = r.max_closure_residual;
    return copy_out(out, s);
}

MBX_API mbx_status mbx_sim_run(mbx_context* context, mbx_sim_data* data, const mbx_sim_run_options* options,
                               const char* directory) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!data || !options || !directory) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "data, options or directory is NULL");
    return guarded(context, [&] {
        mbx_sim_run_options o{};
        o.struct_size = sizeof o;
        if (options->struct_size < 2 * sizeof(uint32_t)) bad_argument("mbx_sim_run_options.struct_size is too small");
        std::memcpy(&o, options, std::min<size_t>(options->struct_size, sizeof o));
        RunSettings settings;
        settings.integrator = data->owner->integrator;
        settings.stop_time = o.stop_time;
        settings.output_step = o.output_step != 0 ? o.output_step : 0.01;
        if (context->progress) {
            mbx_progress_fn fn = context->progress;
            void* user = context->progress_user;
            settings.progress = [fn, user](double fraction) { return fn(user, "simulating", fraction) == 0; };
        }
        // On a copy of the data: a failed run leaves the data as it was, and
        // the contact's friction anchors with it.
        Data trial = data->data;
        RunFiles files(directory);
        std::optional<sim::contact::ContactWorld::Memory> contact;
        if (data->contact) contact = data->contact->memory();
        try {
            const RunSummary summary = run(data->owner->model, trial, settings, files);
            files.commit(data->owner->model, summary);
        } catch (...) {
            if (contact) data->contact->restore(*contact);
            throw;
        }
        data->data = std::move(trial);
    });
}

}  // extern "C"
