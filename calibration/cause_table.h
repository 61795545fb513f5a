// The table of calibration causes: one entry per physical effect a model may
// lack (docs/calibration.md, "Causes"), holding everything the stages ask of
// it. The catalogue makes candidates from it, the regression takes their
// columns and physical checks, identify() their refinement, the simulation
// fit their parameters and bounds, and the model extension (hence the replays
// and the description file) what each adds to the model. A new cause is one
// entry in cause_table.cpp and its functions there, plus its case in the
// simulation fit's model (simulation/nonlinear_fit.cpp) if that refines it.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace mbx::calibration {

struct Candidate;
struct RegressionRows;
struct SelectedCause;
struct ExtensionStep;

// In catalogue order: of two causes with the same column the earlier is named.
enum class CauseId {
    ViscousFriction,
    CoulombFriction,
    EffortOffset,
    Armature,
    AsymmetricFriction,
    StribeckFriction,
    PositionDependentEffort,
    ActuatorGain,
    Delay,
    SensorOffset,
    MassError,
    Compliance,
    Backlash,
    MountingTilt,
};

// What a cause is a property of, which decides where the catalogue offers it.
enum class CauseSubject {
    ActuatedJoint,  // a coordinate with a recorded effort
    AnyJoint,       // any coordinate (a sensor)
    Body,           // a moving body with mass
    Transmission,   // an actuated joint's drive train: offered by the simulation stage, not the catalogue
    Mounting,       // the whole machine's base (joint and body -1): offered once
};

// What identify() does with a candidate's nonlinear setting before judging it.
enum class Refinement {
    None,
    ExactLag,         // the delay's column at its own coefficient (a fixed point)
    OffsetAnchor,     // a sensor offset's second-order column at the offset found
    ComAnchor,        // a centre-of-mass shift's columns through the shift found
    GridAndSpeeds,    // one grid setting per joint goes on; its speeds are then searched
};

struct CauseKind {
    CauseId id;
    const char* name;  // the vocabulary of calibration.json, the page and the C API
    CauseSubject subject;
    const char* meaning;  // what the model lacks, in a line (docs/calibration.md)
    // Its coefficients (a candidate's unless `candidates` gives variants);
    // a transmission cause has these in the simulation fit whatever the candidate holds.
    std::vector<std::string> parameters;
    // The candidates for one subject: `proto` has the subject filled in
    // (joint, dof, q_index; body and its inertia).
    void (*candidates)(const RegressionRows& fit, const Candidate& proto, std::vector<Candidate>& out);
    // The regression columns, one per parameter, into `c` (zero on entry;
    // rows stacked as RegressionRows::y).
    void (*columns)(const Candidate& c, const RegressionRows& rows, Eigen::MatrixXd& out);
    // Coefficients a physical effect can have; null: any.
    bool (*physical)(const Candidate& c, const Eigen::VectorXd& theta);
    Refinement refinement;
    int settings;  // nonlinear settings the refinement fits (the evidence test counts them)
    // What the cause adds to the model: joint dynamics, a transmission, a
    // drive's delay, a body's inertia, or a replay adjustment with the
    // reason the description file cannot hold it.
    void (*extend)(const SelectedCause& c, ExtensionStep& step);
    // The simulation fit.
    bool simulated;                               // it carries the cause
    bool needs_effort;                            // only on a joint with a recorded effort
    bool elastic;                                 // a motor-side inertia of its own (not in a closed loop)
    bool rigid_motor;                             // a rigid model's view of a motor inertia (compliance may replace it)
    // Bounds of parameter i, from its start value (infinite: none).
    void (*simulation_bounds)(const Candidate& c, size_t i, double start, double& lower, double& upper);
    // The parts of the rows (RowPart) its candidates and columns read
    // beyond the motion and the model's efforts.
    unsigned row_parts;
};

// Every cause, in catalogue order.
const std::vector<CauseKind>& cause_table();
// The entry named `name`; an mbx::Error naming it when there is none.
const CauseKind& cause_kind(const std::string& name);
const char* cause_name(CauseId id);

}  // namespace mbx::calibration
