// What the three calibration output writers share: units, subjects and
// labels, so the JSON file, the page and the description agree.
#pragma once
#include <string>

#include "calibration/calibrate.h"

namespace mbx::calibration::detail {

// Whether sim joint `j` is prismatic (lengths and forces) rather than
// revolute (angles and torques); false for an index out of range.
bool linear_joint(const sim::Model& model, int j);

// SI unit of a quantity on a joint of that kind ("N", "N m", "m/s", ...).
const char* quantity_unit(Quantity q, bool linear);

const char* role_name(Role r);

// What a cause acts on: a joint (CAD constraint id and name) or a body (CAD
// part id and name).
struct CauseSubject {
    const char* kind = "joint";  // "joint", "body" or "mounting"
    std::string id, name;
};
CauseSubject cause_subject(const sim::Model& model, const Candidate& c);

// The step that added cause `i` (Identification::causes index), or null.
const StepErrors* step_of_cause(const CalibrationResult& r, int i);

// "joint <name> (<constraint id>)" for messages and labels.
std::string joint_label(const sim::Model& model, int j);

// A compared signal's subject for labels: "joint <name> (<id>)", or for a
// body quantity "body <name> (<id>) x" with " at (px, py, pz) m" for a point
// off the body's origin (the quaternion component for an orientation).
std::string signal_label(const sim::Model& model, int joint, int body, Quantity q, int component,
                         const Eigen::Vector3d& point);
// The axis or component's letter of a body quantity ("x", "w").
const char* component_name(Quantity q, int component);
// SI unit of a compared signal (a joint's per its kind; a body's position m,
// velocity m/s, angular velocity rad/s, orientation 1).
const char* signal_unit(const sim::Model& model, int joint, int body, Quantity q);

// Throws mbx::Error (MBX_ERROR_INVALID_INPUT) when the result refers to a
// record, joint, body or cause that does not exist, or has no baseline:
// the writers index with these numbers.
void check_result(const sim::Model& model, const CalibrationResult& r);

}  // namespace mbx::calibration::detail
