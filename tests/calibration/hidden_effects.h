// Data sets for the calibration tests with a known physical effect hidden in
// them. MuJoCo simulates mbx's own MJCF export of a mechanism (so the data
// does not come from mbx's simulator), driven by a PD controller tracking a
// smooth multi-sine on each actuated joint; the effect is put in MuJoCo's
// model where MuJoCo can express it (damping, frictionloss, armature, body
// mass) and around MuJoCo in the control loop otherwise (offsets, gains,
// delay, asymmetric and Stribeck friction, springs). Records carry white
// effort noise and encoder quantisation, and come with an experiment file in
// the docs/calibration.md format plus truth.json for people.
#pragma once
#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "calibration/identification/identify.h"
#include "tests/export/export_fixture.h"

namespace mbx_test {

// One hidden effect as the calibration should name it: the cause from the
// calibration vocabulary, its subject (a joint's CAD constraint id and report
// name, or a body's CAD part id and name) and the true parameter values.
struct HiddenEffect {
    std::string cause;
    std::string joint_id, joint_name;
    std::string body_id, body_name;
    std::vector<std::pair<std::string, double>> parameters;
    double parameter(const std::string& name) const;  // throws if absent
};

// What to hide: a cause on a subject (a joint's constraint id or report name,
// a body's id or name), its main magnitude drawn uniformly from [low, high]
// (units per cause: see hidden_effects.cpp's table).
struct EffectSpec {
    std::string cause;
    std::string subject;
    double low = 0, high = 0;
    // com_shift and inertia_error (both named mass_error): the shift's
    // direction, or the one the material spreads along, in mbx's body frame.
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();
};

struct CaseSpec {
    std::string name;       // also the case's folder name
    std::string mechanism;  // "emps_axis", "two_link_arm", "yaw_arm", "fourbar" or "dfki_acrobot"
    std::vector<EffectSpec> effects;  // none: a clean case
    unsigned seed = 1;      // magnitudes, excitation phases and noise
    double fit_seconds = 8, validation_seconds = 4;
    double noise_fraction = 0.015;  // effort noise sigma over the record's effort RMS
    // Per actuated joint, the effort noise sigma itself (N m, N) in place of
    // noise_fraction: a sensor's noise that does not follow the motion.
    std::vector<double> noise_sigma;
    // Rests in the excitation: every 2.7 s the reference fades out and holds
    // still for 0.4 s (standstill data separates an effort offset from
    // asymmetric Coulomb friction).
    bool holds = false;
    // The fit record's reference per actuated joint (position and speed at
    // t) in place of the random multi-sine: a designed excitation.
    std::function<void(size_t joint, double t, double& r, double& rd)> fit_reference;
    // The same for the validation record (a second run along a designed
    // excitation, as the experiment file `mbx excite` writes asks for).
    std::function<void(size_t joint, double t, double& r, double& rd)> validation_reference;
};

struct GeneratedCase {
    std::string name;
    std::string mechanism;
    std::string input_kind;  // "builtin", "file" (PMXML), "urdf" or "test_assembly" (two_link_arm_assembly(), in-process only)
    std::string input;       // built-in name, PMXML path or test assembly name
    std::string shapes;      // VRML shapes file for a "file" input ("" otherwise)
    std::vector<HiddenEffect> hidden;
    std::string experiment_path;
    std::string fit_csv, validation_csv;
    std::vector<std::string> joint_ids, joint_names;  // the actuated joints, in column order
    std::vector<std::string> column_stems;  // per actuated joint: columns "<stem>.q" and "<stem>.effort"
    // Per actuated joint the PD that follows the references: effort
    // kp (r - q) + kd (r' - q') (before a hidden actuator gain).
    std::vector<double> controller_kp, controller_kd;
};

// MuJoCo's motion along one record, in mbx's coordinates (sim::build_model of
// the same translation; hinge and slide coordinates are equal in both), at the
// output samples, before noise, quantisation and sensor offsets.
struct TrueMotion {
    std::vector<double> t;
    Eigen::MatrixXd q, v, a;          // samples x model nv
    Eigen::MatrixXd commanded;        // samples x actuated: the controller's effort (what is recorded, noise-free)
    // samples x actuated: what the actuator put on the joint over the step
    // starting at the sample (the command extrapolated to mid-step, after the effects)
    Eigen::MatrixXd applied;
    Eigen::MatrixXd generator_force;  // samples x actuated: forces the generator added (friction, springs)
    std::vector<int> actuated_dof;    // model velocity coordinate of each actuated joint
    double effort_noise_sigma_first = 0;  // sigma of the first actuated joint's recorded effort noise
};

// The mechanisms, translated by mbx's own pipeline as the calibration would
// read them: the emps_axis sample (prismatic 40:-:41), the two-link arm
// below, the fourbar built-in, and dfki_acrobot: the DFKI double pendulum's
// own URDF (../shared/data/measured/dfki_double_pendulum_c0, joints "Joint1"
// and "Joint2", links "Link1" and "Link2") as a user's URDF.
std::unique_ptr<xtest::Translated> open_mechanism(const std::string& mechanism);

// Two revolute joints about y hanging under gravity from a shoulder 1 m up:
// upper link 0.30 m, 2 kg; forearm 0.25 m, 1 kg. Joints
// "two_link_arm/shoulder" and "two_link_arm/elbow"; bodies
// "two_link_arm/upper" and "two_link_arm/forearm".
mbx_memory::Assembly two_link_arm_assembly();

// A yaw-pitch-pitch arm: a turntable about z 1.1 m up, the two-link arm's
// links (pitch about y) hung from a shoulder 0.1 m off the yaw axis. Joints
// "yaw_arm/yaw", "yaw_arm/shoulder", "yaw_arm/elbow". A tilted mounting
// loads its yaw joint with a torque that turns with the yaw angle, which no
// joint cause has (on a planar arm a tilt in its plane is a sensor offset
// of the first joint, and out of it nothing).
mbx_memory::Assembly yaw_arm_assembly();

// Writes fit.csv, validation.csv, experiment.xml, truth.json and the MJCF
// export (mjcf/) into out_dir (created). Throws std::runtime_error on a bad
// spec (unknown mechanism, cause or subject) or a MuJoCo failure.
GeneratedCase generate_case(const CaseSpec& spec, const std::string& out_dir,
                            std::vector<TrueMotion>* motion = nullptr);

// A fixed list: >= 30 single-effect cases over the three mechanisms and the
// causes, 6 clean cases and 3 with two effects; `seed` varies magnitudes,
// excitation and noise, not the list.
std::vector<CaseSpec> hidden_effect_suite(unsigned seed);

// Every case into out_dir/<name>/ and all truths into out_dir/truth.json.
std::vector<GeneratedCase> generate_suite(const std::vector<CaseSpec>& specs, const std::string& out_dir);

// The linear identification of a generated case's records on model `m`
// with `options`, the selection stopped at the validation records' noise
// floor as calibrate() stops it.
mbx::calibration::Identification identify_case(const mbx::sim::Model& m, const std::string& experiment_path,
                                               mbx::calibration::IdentifyOptions options = {});

// The causes the suite draws (backlash on the two-link arm only: the slide's
// dead band is not named yet, docs/calibration.md), with com_shift and
// inertia_error, the generator's names for the mass_error of a body's centre
// of mass and of its inertia.
std::vector<std::string> generated_causes();

}  // namespace mbx_test
