// Body quantities of the experiment file (docs/calibration.md, "Body
// quantities"): where a body is, how it is turned and how fast it moves, in
// the world, as a tracker or a motion-capture system measures it. The
// simulator gives them by forward kinematics from its joint state, so they
// compare in every drive mode; a free body's measured pose is also the state
// a free replay starts from.
#pragma once
#include <string>

#include "calibration/records/pose_records.h"
#include "calibration/records/records.h"
#include "calibration/simulation/replay.h"
#include "sim/data.h"

namespace mbx::calibration {

// The sim body a <column body=...> or <compare body=...> names (rigid body
// id or report name). Throws mbx::Error naming file and line for no such
// body, a name several bodies share, or the world.
int body_of_key(const sim::Model& m, const std::string& key, const std::string& file, int line);

// Binds a <compare body=...>; throws mbx::Error naming file and line for an
// unknown body.
ComparedSignal bind_body_compare(const Experiment& e, const CompareSpec& c, const sim::Model& m);

// The measured values a compared signal is scored against (a joint's or a
// body's), or null when the record lacks them.
const std::vector<double>* measured_values(const Record& r, const ComparedSignal& c);

// Forward kinematics on a scratch copy of the state, so that sampling a
// body never touches what the integrator keeps between steps.
class BodyKinematics {
public:
    explicit BodyKinematics(const sim::Model& m) : m_(m), kin_(m) {}
    // Poses and velocities of every body at d's state.
    void update(const sim::Data& d);
    // A body quantity at the last update, SI. An orientation component is
    // that of the unit quaternion of the body frame into the world (w x y z,
    // Hamilton, as MuJoCo's xquat) with the sign that agrees with the
    // record's measured components of the same body at sample k (q and -q are
    // the same turn; w >= 0 when none is measured).
    double value(Quantity q, int body, int component, const Eigen::Vector3d& point, const Record* r = nullptr,
                 size_t k = 0) const;
    Eigen::Vector3d position(int body, const Eigen::Vector3d& point) const;
    Eigen::Quaterniond orientation(int body) const;

private:
    const sim::Model& m_;
    sim::Data kin_;
};

// The free bodies (on a free joint) whose origin position (x, y, z) and
// orientation (w, x, y, z) the record measures in full.
std::vector<int> measured_free_bodies(const sim::Model& m, const Record& r);

// The measured pose and velocities of a free body at sample k: position and
// orientation as measured (the quaternion normalised), the origin's velocity
// and the angular velocity from their columns when the record has all three
// axes, else from a quadratic fitted to the measured pose over the 10 ms
// around the sample (at least three samples each side).
PoseSample measured_pose(const Record& r, int body, size_t k);

// Sets the free joints of measured_free_bodies to their measured pose and
// velocities at sample k (after the joint coordinates were set).
void set_measured_free_bodies(const sim::Model& m, sim::Data& d, const Record& r, size_t k);

// A free body's samples as a contact trial (contact_fit.h); `trial` names it.
PoseRecord pose_record(const Record& r, int body, int trial);

}  // namespace mbx::calibration
