// The experiment file (docs/calibration.md): which measured records fit and
// which validate, which column is which quantity of which CAD joint or body,
// how the model is driven along them and which signals are compared. Parsed
// with every problem named by file and line.
#pragma once
#include <array>
#include <string>
#include <vector>

namespace mbx::calibration {

// Orientation and AngularVelocity are body quantities only; Position and
// Velocity are a joint's coordinate or a body point's world coordinates.
enum class Quantity { Position, Velocity, Acceleration, Effort, Voltage, Current, Reference, ControllerInput, Orientation, AngularVelocity };
enum class DriveMode { ClosedLoop, Effort, Free };
enum class Role { Fit, Validation };

const char* quantity_name(Quantity q);
const char* drive_mode_name(DriveMode m);

struct RecordSpec {
    std::string path;  // resolved against the experiment file's folder
    Role role = Role::Fit;
    double start = -1, stop = -1;  // s on the record's time; < 0: open
    // With <trials column=...>: the trial ids of the file this record takes,
    // each one record (empty: every trial in the file).
    std::vector<long long> trials;
    int line = 0;
};

// One column of every record: a quantity of a joint or a body, in SI after
// value = raw * scale * unit factor (the factor depends on the joint's kind,
// so it is applied when the experiment is bound to a model).
struct ColumnSpec {
    std::string name;
    std::string joint, body;  // CAD id or report name; exactly one is set
    Quantity quantity = Quantity::Position;
    // Body quantities (docs/calibration.md, "Body quantities"): the world
    // axis of a position or velocity and the body-frame axis of an angular
    // velocity (0 x, 1 y, 2 z), or the quaternion component of an
    // orientation (0 w, 1 x, 2 y, 3 z); -1 for joint quantities.
    int component = -1;
    std::array<double, 3> point{0, 0, 0};  // m, body frame: the point a position or velocity is of
    std::string unit;
    double scale = 1;  // the user's factor on top of the unit's
    bool optional = false;
    int line = 0;
};

struct CompareSpec {
    std::string joint, body;
    Quantity quantity = Quantity::Effort;
    int component = -1;                    // as ColumnSpec's
    std::array<double, 3> point{0, 0, 0};  // as ColumnSpec's
    double weight = 1;
    double start = -1, stop = -1;
    int line = 0;
};

struct Experiment {
    std::string path;  // the experiment file
    std::vector<RecordSpec> records;
    std::string time_column;
    double time_factor = 1;
    // <trials column=...>: a record file holds several trials (tosses,
    // drops) told apart by this column; each is a record of its own.
    std::string trial_column;
    std::vector<ColumnSpec> columns;
    DriveMode mode = DriveMode::ClosedLoop;
    double horizon = 0.5;  // s, effort mode's forward-simulation windows
    // <filter cutoff>: the low-pass (Hz) on measured positions and efforts
    // before they are differentiated and compared; 0: from the sampling
    // rate (Record::filter_cutoff).
    double cutoff = 0;
    std::vector<CompareSpec> compare;
};

// Throws mbx::Error (MBX_ERROR_INVALID_INPUT) naming "file:line" and the
// problem, all problems of the file in one message.
Experiment load_experiment(const std::string& path);
Experiment parse_experiment(const std::string& text, const std::string& path);

// The SI factor of a unit for a quantity; false if the unit is unknown for
// it. `linear`: the joint is prismatic (lengths) rather than revolute
// (angles); a body's position and velocity are linear, its angular velocity
// is not, its orientation (a unit quaternion) takes "1".
bool unit_factor(Quantity q, const std::string& unit, bool linear, double& factor);

}  // namespace mbx::calibration
