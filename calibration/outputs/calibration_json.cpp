// calibration.json: every number of the calibration in one file a script can
// read, keyed by CAD ids like the description file.
#include <algorithm>
#include <cmath>

#include "calibration/outputs/calibration_files.h"
#include "calibration/outputs/calibration_files_detail.h"
#include "core/report/json_writer.h"

namespace mbx::calibration {

namespace {

using namespace detail;

void joint_ref(JsonWriter& w, const sim::Model& model, int j) {
    w.key("joint").begin_object(JsonWriter::Layout::Inline);
    w.member("constraint_id", model.joints[size_t(j)].constraint_id).member("name", model.joints[size_t(j)].name);
    w.end_object();
}

// A joint's signal: its joint; a body quantity's: the body, the axis or
// quaternion component and the point (body frame, m).
void signal_subject(JsonWriter& w, const sim::Model& model, int joint, int body, Quantity q, int component,
                    const Eigen::Vector3d& point) {
    if (body < 0) {
        joint_ref(w, model, joint);
        return;
    }
    w.key("body").begin_object(JsonWriter::Layout::Inline);
    w.member("id", model.bodies[size_t(body)].id).member("name", model.bodies[size_t(body)].name);
    w.end_object();
    w.member(q == Quantity::Orientation ? "component" : "axis", component_name(q, component));
    if (q == Quantity::Position || q == Quantity::Velocity) {
        w.key("point").begin_array(JsonWriter::Layout::Inline);
        for (int k = 0; k < 3; ++k) w.value(point[k]);
        w.end_array();
    }
}

void pose_error(JsonWriter& w, const char* key, const PoseError& e) {
    w.key(key).begin_object(JsonWriter::Layout::Inline);
    w.member("position_percent_of_size", e.position).member("rotation_deg", e.rotation).member("score", e.score());
    w.member("samples", e.samples).member("diverged", e.diverged);
    w.end_object();
}

void contact_settings(JsonWriter& w, const char* key, const ContactModel& m) {
    w.key(key).begin_object(JsonWriter::Layout::Inline);
    w.member("stiffness", m.settings.normal.stiffness).member("exponent", m.settings.normal.exponent);
    w.member("damping", m.settings.normal.damping);
    w.member("mu_static", m.settings.friction.mu_static).member("mu_kinetic", m.settings.friction.mu_kinetic);
    w.member("ground_offset", m.ground_offset);
    w.end_object();
}

// The contact stage: the measured body, the material pair, the causes named
// in order with their parameters and pose errors, the model before and after.
void contact_section(JsonWriter& w, const sim::Model& model, const ContactStageResult& c) {
    w.key("contact").begin_object();
    w.key("body").begin_object(JsonWriter::Layout::Inline);
    w.member("id", model.bodies[size_t(c.body)].id).member("name", model.bodies[size_t(c.body)].name);
    w.end_object();
    w.key("materials").begin_array(JsonWriter::Layout::Inline);
    w.value(c.material_a).value(c.material_b);
    w.end_array();
    w.member("integrator_step", c.integrator_step).member("rollouts", c.fit.rollouts);
    w.member("fit_trials", c.fit_trials.size()).member("validation_trials", c.validation_trials.size());
    pose_error(w, "baseline_fit", c.fit.baseline_fit);
    pose_error(w, "baseline_validation", c.fit.baseline_validation);
    w.key("causes").begin_array();
    for (const ContactStep& s : c.fit.steps) {
        w.begin_object();
        w.member("cause", s.cause);
        w.key("parameters").begin_array();
        for (const FittedValue& v : s.parameters) {
            w.begin_object(JsonWriter::Layout::Inline);
            w.member("name", v.name).member("value", v.value).member("std_error", v.standard_error).member("unit", v.unit);
            if (!v.method.empty()) w.member("method", v.method);
            w.end_object();
        }
        w.end_array();
        pose_error(w, "fit", s.fit);
        pose_error(w, "validation", s.validation);
        w.member("evidence", s.evidence);
        w.end_object();
    }
    w.end_array();
    w.key("notes").begin_array();
    for (const std::string& n : c.fit.notes) w.value(n);
    w.end_array();
    contact_settings(w, "before", c.start);
    contact_settings(w, "after", c.fit.model);
    w.end_object();
}

// One step's errors: the inverse-dynamics ones and every simulated signal's.
void errors(JsonWriter& w, const sim::Model& model, const CalibrationResult& r, const StepErrors& s) {
    w.begin_object();
    w.member("label", s.label);
    w.key("identification").begin_object(JsonWriter::Layout::Inline);
    w.member("fit", s.fit_error).member("validation", s.validation_error);
    w.end_object();
    w.key("simulated").begin_object();
    w.member("fit", s.simulated_fit).member("validation", s.simulated_validation);
    w.key("signals").begin_array();
    for (const SignalError& e : s.simulated) {
        w.begin_object(JsonWriter::Layout::Inline);
        w.member("record", e.record).member("path", r.record_paths[size_t(e.record)]);
        w.member("role", role_name(e.role));
        signal_subject(w, model, e.joint, e.body, e.quantity, e.component, e.point);
        w.member("quantity", quantity_name(e.quantity));
        w.member("unit", signal_unit(model, e.joint, e.body, e.quantity));
        w.member("weight", e.weight).member("relative", e.relative).member("rms", e.rms);
        w.end_object();
    }
    w.end_array();
    w.end_object();
    w.end_object();
}

void joint_dynamics(JsonWriter& w, const sim::JointDynamics& d) {
    w.begin_object(JsonWriter::Layout::Inline);
    w.member("damping", d.damping).member("coulomb", d.coulomb).member("coulomb_velocity", d.coulomb_velocity);
    if (d.asymmetric) w.member("damping_negative", d.damping_negative).member("coulomb_negative", d.coulomb_negative);
    w.member("stribeck", d.stribeck).member("stribeck_velocity", d.stribeck_velocity).member("offset", d.offset);
    w.member("stiffness", d.stiffness).member("rest", d.rest).member("armature", d.armature);
    w.end_object();
}

}  // namespace

std::string calibration_json(const sim::Model& model, const Experiment& experiment, const CalibrationResult& r) {
    check_result(model, r);
    const Identification& id = r.identification;
    JsonWriter w(64 * 1024);
    w.begin_object();
    w.member("format", "mbx calibration").member("version", 1);
    w.member("model", model.name).member("experiment", experiment.path);
    w.member("drive_mode", drive_mode_name(r.mode));
    w.key("records").begin_array();
    for (size_t i = 0; i < r.record_paths.size(); ++i) {
        w.begin_object(JsonWriter::Layout::Inline);
        w.member("index", i).member("path", r.record_paths[i]).member("role", role_name(r.record_roles[i]));
        w.end_object();
    }
    w.end_array();

    w.key("baseline");
    errors(w, model, r, r.baseline());

    w.key("causes").begin_array();
    for (size_t i = 0; i < id.causes.size(); ++i) {
        const SelectedCause& c = id.causes[i];
        const CauseSubject subject = cause_subject(model, c.candidate);
        w.begin_object();
        w.member("step", i + 1).member("cause", c.candidate.cause);
        w.key("subject").begin_object(JsonWriter::Layout::Inline);
        w.member("kind", subject.kind).member("id", subject.id).member("name", subject.name);
        w.end_object();
        w.key("parameters").begin_array();
        for (const Estimate& p : c.parameters) {
            w.begin_object(JsonWriter::Layout::Inline);
            w.member("name", p.name).member("value", p.value).member("std_error", p.std_error);
            w.end_object();
        }
        w.end_array();
        w.member("evidence", c.evidence);
        // What the step cut from the validation error, named with its unit:
        // percentage points of effort error for a joint or body cause, the
        // pose score (% of the body's size plus degrees) for a contact cause.
        w.member(r.contact.ran ? "validation_gain_pose_score" : "validation_gain_percentage_points", c.validation_gain);
        w.key("identification").begin_object(JsonWriter::Layout::Inline);
        w.member("fit", c.fit_error).member("validation", c.validation_error);
        w.end_object();
        // The replay with this cause and every earlier one in the model.
        w.key("after");
        if (const StepErrors* s = step_of_cause(r, int(i))) errors(w, model, r, *s);
        else w.null();
        bool written = true;
        for (const UnwrittenCause& u : r.unwritten)
            if (u.cause == int(i)) written = false;
        w.member("in_description", written);
        w.end_object();
    }
    w.end_array();

    w.key("final");
    errors(w, model, r, r.final_step());
    w.member("noise_level", id.noise_level);  // (null when not finite)
    if (!std::isfinite(id.noise_level))
        w.member("noise_level_note", "not measured: no record holds an effort");
    else
        w.member("explained_to_noise", explained_to_noise(id.final_validation_error, id.noise_level));
    w.key("residual_concentration").begin_array();
    for (const std::string& s : id.residual_concentration) w.value(s);
    w.end_array();

    w.key("description").begin_object();
    w.key("joints").begin_array();
    for (const JointUpdate& u : r.joints) {
        w.begin_object();
        w.member("constraint_id", u.constraint_id).member("primitive", u.primitive).member("name", u.name);
        w.member("kind", u.linear ? "prismatic" : "revolute");
        w.key("causes").begin_array(JsonWriter::Layout::Inline);
        for (const std::string& c : u.causes) w.value(c);
        w.end_array();
        w.key("before");
        joint_dynamics(w, u.before);
        w.key("after");
        joint_dynamics(w, u.after);
        if (u.transmission_after) {
            // The elastic transmission (compliance), as the <transmission> child holds it.
            const sim::Transmission& t = *u.transmission_after;
            w.key("transmission").begin_object(JsonWriter::Layout::Inline);
            w.member("stiffness", t.stiffness).member("damping", t.damping).member("motor_inertia", t.motor_inertia);
            w.member("backlash", t.backlash);
            w.end_object();
        }
        w.end_object();
    }
    w.end_array();
    w.key("drives").begin_array();
    for (const DriveUpdate& d : r.drives) {
        w.begin_object(JsonWriter::Layout::Inline);
        w.member("constraint_id", d.constraint_id).member("name", d.name);
        w.member("delay_before", d.delay_before).member("delay_after", d.delay_after);
        w.end_object();
    }
    w.end_array();
    if (r.mounting_tilted) {
        // rad about the world's x then y axis, on top of the description's <mounting>
        w.key("mounting").begin_object(JsonWriter::Layout::Inline);
        w.member("tilt_x", r.mounting_tilt[0]).member("tilt_y", r.mounting_tilt[1]);
        w.end_object();
    }
    w.key("unwritten").begin_array();
    for (const UnwrittenCause& u : r.unwritten) {
        const SelectedCause& c = id.causes[size_t(u.cause)];
        const CauseSubject subject = cause_subject(model, c.candidate);
        w.begin_object(JsonWriter::Layout::Inline);
        w.member("step", u.cause + 1).member("cause", c.candidate.cause).member("subject", subject.id);
        w.member("reason", u.reason);
        w.end_object();
    }
    w.end_array();
    w.end_object();

    if (r.contact.ran) contact_section(w, model, r.contact);

    w.key("warnings").begin_array();
    // The calibration's own warnings, then the identification's it does not
    // already repeat.
    for (const std::string& s : r.warnings) w.value(s);
    for (const std::string& s : id.warnings)
        if (std::find(r.warnings.begin(), r.warnings.end(), s) == r.warnings.end()) w.value(s);
    w.end_array();
    // The warnings' groups, each cause as "cause on subject": what `mbx
    // excite --calibration` designs a record to separate.
    w.key("ambiguous").begin_array();
    for (const std::vector<std::string>& group : id.ambiguous) {
        w.begin_array(JsonWriter::Layout::Inline);
        for (const std::string& c : group) w.value(c);
        w.end_array();
    }
    w.end_array();
    w.key("considered").begin_array();
    for (const std::string& s : id.considered) w.value(s);
    w.end_array();
    w.member("wall_time", r.wall_time);
    w.end_object();
    return w.take() + "\n";
}

}  // namespace mbx::calibration
