// mbx_calibrate and the calibration handle: the loop of
// calibration/calibrate.h on a translated mechanism with its attached
// drives and joint dynamics, plus the three files of calibration_files.h.
#include <cmath>
#include <cstring>
#include <memory>

#include "calibration/outputs/calibration_files.h"
#include "sdk/capi/contact_build.h"
#include "sdk/capi/build_options_of.h"
#include "sdk/capi/guard.h"
#include "sim/build_model.h"
#include "sim/resolved_joint_dynamics.h"

using namespace mbx;
using namespace mbx::calibration;

struct mbx_calibration {
    CalibrationResult result;
    // The C strings a caller reads, kept alive with the handle.
    std::vector<std::string> subject_ids, subject_names;
    std::vector<mbx_subject_kind> subject_kinds;
    std::vector<char> written;
};

namespace {


}  // namespace

extern "C" {

MBX_API mbx_status mbx_calibrate(mbx_context* context, const mbx_mechanism* mechanism,
                                 const mbx_calibrate_options* options, mbx_calibration** out) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!out) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "out_calibration is NULL");
    *out = nullptr;
    if (!mechanism || !mechanism->model) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechanism is NULL");
    if (!options) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "options is NULL (the experiment file is required)");
    return guarded(context, [&] {
        mbx_calibrate_options o{};
        o.struct_size = sizeof o;
        if (options->struct_size < 2 * sizeof(uint32_t)) bad_argument("mbx_calibrate_options.struct_size is too small");
        std::memcpy(&o, options, std::min<size_t>(options->struct_size, sizeof o));
        if (!o.experiment || !*o.experiment) bad_argument("mbx_calibrate_options.experiment is not set");
        sim::BuildOptions build = build_options_of(*mechanism, o.flags, o.gravity);
        const Experiment experiment = load_experiment(o.experiment);
        CalibrateOptions co;
        if (context->progress) {
            mbx_progress_fn fn = context->progress;
            void* user = context->progress_user;
            co.progress = [fn, user](const char* stage, double fraction) { return fn(user, stage, fraction) == 0; };
        }
        // The description's collision shapes and materials, for the contact stage.
        if (!mechanism->contact.empty()) {
            mbx_sim_model contact_model;
            contact_model.model = sim::build_model(*mechanism->model, build);
            build_contact(*mechanism, contact_model);
            co.contact.shapes = contact_model.shapes;
            co.contact.default_settings = contact_model.contact_default;
            co.contact.pairs = contact_model.contact_pairs;
            co.contact.materials = mechanism->contact.materials;
        }
        auto handle = std::make_unique<mbx_calibration>();
        handle->result = calibrate(*mechanism->model, build, experiment, co);
        // The model the causes were named on: their subjects, and the files' names.
        const sim::Model model = sim::build_model(*mechanism->model, build);
        if (o.directory)
            write_calibration_files(o.directory, *mechanism->model, model, experiment, handle->result,
                                    o.description ? o.description : "");
        const CalibrationResult& r = handle->result;
        for (size_t i = 0; i < r.identification.causes.size(); ++i) {
            const Candidate& c = r.identification.causes[i].candidate;
            if (c.body >= 0) {
                handle->subject_kinds.push_back(MBX_SUBJECT_RIGID_BODY);
                handle->subject_ids.push_back(model.bodies[size_t(c.body)].id);
                handle->subject_names.push_back(model.bodies[size_t(c.body)].name);
            } else if (c.joint < 0) {
                // The mounting: a property of the whole model.
                handle->subject_kinds.push_back(MBX_SUBJECT_MODEL);
                handle->subject_ids.push_back("");
                handle->subject_names.push_back(model.name);
            } else {
                const sim::JointT<double>& j = model.joints[size_t(c.joint)];
                handle->subject_kinds.push_back(MBX_SUBJECT_CONSTRAINT);
                handle->subject_ids.push_back(j.constraint_id);
                handle->subject_names.push_back(j.name);
            }
            bool unwritten = false;
            for (const UnwrittenCause& u : r.unwritten) unwritten = unwritten || u.cause == int(i);
            handle->written.push_back(unwritten ? 0 : 1);
        }
        *out = handle.release();
    });
}

MBX_API void mbx_calibration_destroy(mbx_calibration* calibration) { delete calibration; }

MBX_API mbx_status mbx_calibration_get_summary(const mbx_calibration* c, mbx_calibration_summary* out) {
    if (!c) return MBX_ERROR_INVALID_ARGUMENT;
    const CalibrationResult& r = c->result;
    mbx_calibration_summary s{};
    s.struct_size = sizeof s;
    s.cause_count = uint32_t(r.identification.causes.size());
    s.warning_count = uint32_t(r.warnings.size());
    s.baseline_fit_error = r.identification.baseline_fit_error;
    s.baseline_validation_error = r.identification.baseline_validation_error;
    s.final_fit_error = r.identification.final_fit_error;
    s.final_validation_error = r.identification.final_validation_error;
    s.baseline_simulated_fit_error = r.baseline().simulated_fit;
    s.baseline_simulated_validation_error = r.baseline().simulated_validation;
    s.final_simulated_fit_error = r.final_step().simulated_fit;
    s.final_simulated_validation_error = r.final_step().simulated_validation;
    s.noise_level = r.identification.noise_level;
    s.wall_time = r.wall_time;
    s.explained_to_noise = std::isfinite(s.noise_level)
                               ? (explained_to_noise(r.identification.final_validation_error, s.noise_level) ? 1 : 0)
                               : -1;
    s.residual_note_count = uint32_t(r.identification.residual_concentration.size());
    return copy_out(out, s);
}

MBX_API mbx_status mbx_calibration_get_cause(const mbx_calibration* c, uint32_t index, mbx_calibration_cause* out) {
    if (!c || index >= c->result.identification.causes.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const SelectedCause& sc = c->result.identification.causes[index];
    const StepErrors& step = c->result.steps[index + 1];
    mbx_calibration_cause o{};
    o.struct_size = sizeof o;
    o.name = sc.candidate.cause.c_str();
    o.subject_kind = c->subject_kinds[index];
    o.subject_id = c->subject_ids[index].c_str();
    o.subject_name = c->subject_names[index].c_str();
    o.evidence = sc.evidence.c_str();
    o.parameter_count = uint32_t(sc.parameters.size());
    o.written = c->written[index];
    o.fit_error = sc.fit_error;
    o.validation_error = sc.validation_error;
    o.simulated_fit_error = step.simulated_fit;
    o.simulated_validation_error = step.simulated_validation;
    return copy_out(out, o);
}

MBX_API mbx_status mbx_calibration_get_parameter(const mbx_calibration* c, uint32_t cause, uint32_t index,
                                                 mbx_calibration_parameter* out) {
    if (!c || cause >= c->result.identification.causes.size()) return MBX_ERROR_INVALID_ARGUMENT;
    const std::vector<Estimate>& p = c->result.identification.causes[cause].parameters;
    if (index >= p.size()) return MBX_ERROR_INVALID_ARGUMENT;
    mbx_calibration_parameter o{};
    o.struct_size = sizeof o;
    o.name = p[index].name.c_str();
    o.value = p[index].value;
    o.std_error = p[index].std_error;
    return copy_out(out, o);
}

MBX_API const char* mbx_calibration_get_warning(const mbx_calibration* c, uint32_t index) {
    if (!c || index >= c->result.warnings.size()) return nullptr;
    return c->result.warnings[index].c_str();
}

MBX_API const char* mbx_calibration_get_residual_note(const mbx_calibration* c, uint32_t index) {
    if (!c || index >= c->result.identification.residual_concentration.size()) return nullptr;
    return c->result.identification.residual_concentration[index].c_str();
}

}  // extern "C"
