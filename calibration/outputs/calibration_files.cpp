#include "calibration/outputs/calibration_files.h"

#include "calibration/outputs/calibration_files_detail.h"
#include "calibration/cause_table.h"
#include <cstdio>

#include "core/finding.h"
#include "core/report/atomic_file.h"

namespace mbx::calibration {

namespace detail {

bool linear_joint(const sim::Model& model, int j) {
    return j >= 0 && size_t(j) < model.joints.size() && model.joints[size_t(j)].kind == sim::JointKind::Prismatic;
}

const char* quantity_unit(Quantity q, bool linear) {
    switch (q) {
    case Quantity::Position:
    case Quantity::Reference: return linear ? "m" : "rad";
    case Quantity::Velocity: return linear ? "m/s" : "rad/s";
    case Quantity::Acceleration: return linear ? "m/s^2" : "rad/s^2";
    case Quantity::Effort: return linear ? "N" : "N m";
    case Quantity::Voltage:
    case Quantity::ControllerInput: return "V";
    case Quantity::Current: return "A";
    case Quantity::Orientation: return "1";
    case Quantity::AngularVelocity: return "rad/s";
    }
    return "";
}

const char* role_name(Role r) { return r == Role::Fit ? "fit" : "validation"; }

CauseSubject cause_subject(const sim::Model& model, const Candidate& c) {
    CauseSubject s;
    if (c.body >= 0 && size_t(c.body) < model.bodies.size()) {
        s.kind = "body";
        s.id = model.bodies[size_t(c.body)].id;
        s.name = model.bodies[size_t(c.body)].name;
    } else if (c.joint >= 0 && size_t(c.joint) < model.joints.size()) {
        s.id = model.joints[size_t(c.joint)].constraint_id;
        s.name = model.joints[size_t(c.joint)].name;
    } else {
        s.kind = "mounting";
        s.name = "mounting";
    }
    return s;
}

const StepErrors* step_of_cause(const CalibrationResult& r, int i) {
    for (const StepErrors& s : r.steps)
        if (s.cause == i) return &s;
    return nullptr;
}

std::string joint_label(const sim::Model& model, int j) {
    if (j < 0 || size_t(j) >= model.joints.size()) return "joint " + std::to_string(j);
    const auto& joint = model.joints[size_t(j)];
    return joint.constraint_id.empty() ? joint.name : joint.name + " (" + joint.constraint_id + ")";
}

const char* component_name(Quantity q, int component) {
    static const char* axes[] = {"x", "y", "z"};
    static const char* quaternion[] = {"w", "x", "y", "z"};
    if (q == Quantity::Orientation) return component >= 0 && component < 4 ? quaternion[component] : "?";
    return component >= 0 && component < 3 ? axes[component] : "?";
}

std::string signal_label(const sim::Model& model, int joint, int body, Quantity q, int component,
                         const Eigen::Vector3d& point) {
    if (body < 0) return joint_label(model, joint);
    if (size_t(body) >= model.bodies.size()) return "body " + std::to_string(body);
    const auto& b = model.bodies[size_t(body)];
    std::string s = "body " + b.name + (b.id.empty() || b.id == b.name ? "" : " (" + b.id + ")") + " " + component_name(q, component);
    if (!point.isZero()) {
        char at[96];
        std::snprintf(at, sizeof at, " at (%g, %g, %g) m", point[0], point[1], point[2]);
        s += at;
    }
    return s;
}

const char* signal_unit(const sim::Model& model, int joint, int body, Quantity q) {
    if (body < 0) return quantity_unit(q, linear_joint(model, joint));
    switch (q) {
    case Quantity::Position: return "m";
    case Quantity::Velocity: return "m/s";
    case Quantity::AngularVelocity: return "rad/s";
    case Quantity::Orientation: return "1";
    default: return "";
    }
}

namespace {

[[noreturn]] void bad(const std::string& what) {
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(""), "calibration result cannot be written: " + what);
}

}  // namespace

void check_result(const sim::Model& model, const CalibrationResult& r) {
    if (r.steps.empty()) bad("it has no baseline step");
    if (r.record_roles.size() != r.record_paths.size()) bad("record paths and roles differ in number");
    const size_t records = r.record_paths.size(), joints = model.joints.size();
    const size_t causes = r.identification.causes.size();
    auto joint_ok = [&](int j) { return j >= 0 && size_t(j) < joints; };
    auto record_ok = [&](int i) { return i >= 0 && size_t(i) < records; };
    auto subject_ok = [&](int j, int b) { return b >= 0 ? size_t(b) < model.bodies.size() : joint_ok(j); };
    for (const StepErrors& s : r.steps) {
        if (s.cause >= int(causes)) bad("step '" + s.label + "' names cause " + std::to_string(s.cause));
        for (const SignalError& e : s.simulated)
            if (!record_ok(e.record) || !subject_ok(e.joint, e.body))
                bad("a signal error of step '" + s.label + "' names record " + std::to_string(e.record) + ", joint " +
                    std::to_string(e.joint));
    }
    for (const SelectedCause& c : r.identification.causes) {
        const bool body = c.candidate.body >= 0, mounting = c.candidate.cause == cause_name(CauseId::MountingTilt);
        if (mounting ? false : body ? size_t(c.candidate.body) >= model.bodies.size() : !joint_ok(c.candidate.joint))
            bad("cause " + c.candidate.cause + " has no subject in the model");
    }
    for (const Trace& t : r.traces) {
        if (!record_ok(t.record) || !subject_ok(t.joint, t.body)) bad("a trace names a record or joint that does not exist");
        const size_t n = t.t.size();
        if (t.measured.size() != n || t.baseline.size() != n || t.calibrated.size() != n)
            bad("a trace's series differ in length");
    }
    for (const ResidualCloud& c : r.residuals) {
        if (!joint_ok(c.joint)) bad("a residual cloud names joint " + std::to_string(c.joint));
        const size_t n = c.velocity.size();
        if (c.position.size() != n || c.before.size() != n || c.after.size() != n)
            bad("a residual cloud's series differ in length");
    }
    for (const JointUpdate& u : r.joints)
        if (u.constraint_id.empty()) bad("a joint update has no CAD constraint id");
    for (const DriveUpdate& d : r.drives)
        if (d.drive < 0 || size_t(d.drive) >= model.drives.size()) bad("a drive update names drive " + std::to_string(d.drive));
    for (const UnwrittenCause& u : r.unwritten)
        if (u.cause < 0 || size_t(u.cause) >= causes) bad("an unwritten cause names cause " + std::to_string(u.cause));
}

}  // namespace detail

void write_calibration_files(const std::string& dir, const Mechanism& mechanism, const sim::Model& model,
                             const Experiment& experiment, const CalibrationResult& result,
                             const std::string& input_description) {
    if (dir.empty()) throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::model(""), "calibration output folder is empty");
    // Every file is complete in memory before anything touches the disk, so
    // an error in any of them leaves the folder as it was.
    std::vector<std::pair<std::string, std::string>> files;
    files.emplace_back(dir + "/calibration.json", calibration_json(model, experiment, result));
    files.emplace_back(dir + "/calibration.html", calibration_html(model, experiment, result));
    files.emplace_back(dir + "/description.xml",
                       calibrated_description(mechanism, model, result, input_description));
    write_files_atomically(files);
}

}  // namespace mbx::calibration
