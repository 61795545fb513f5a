// Running a simulation end to end: a consistent initial state from the
// coordinates a user fixes, integration to a stop time with samples at an
// output step, and the files a run leaves (trajectory.csv, simulation.json).
// The CLI's `mbx simulate` and the C API's run call these.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "sim/integrator.h"

namespace mbx::sim {

// One coordinate the user fixes: q or qd of joint `joint` (sim joint index),
// coordinate `index` within it (0 for revolute and prismatic joints).
struct FixedValue {
    int joint = -1;
    int index = 0;
    bool velocity = false;
    double value = 0;
};

// Sets data to the CAD assembly pose at rest, applies `fixed` and solves the
// loop closures for the other coordinates, positions from the CAD pose as
// the start guess, then velocities. Throws mbx::Error naming the joint for
// a non-finite value and the loop for values no closure can satisfy.
void initial_state(const Model& m, Data& d, const std::vector<FixedValue>& fixed, double closure_tolerance = 1e-11);

// Finds a joint by its report name or CAD constraint id; -1 if none (or if
// the name is ambiguous, `ambiguous` is set).
int find_joint(const Model& m, const std::string& key, bool* ambiguous = nullptr);

// What a run may hold and do (docs/limits.md): its trajectory is kept until
// written (samples x columns x 8 bytes), and a fixed-step run's step count
// bounds its time. A run beyond either is refused before it starts.
constexpr unsigned long long kTrajectoryLimitBytes = 4ull << 30;
constexpr long long kStepLimit = 1'000'000'000'000LL;

struct RunSettings {
    IntegratorSettings integrator;
    double stop_time = 1.0;
    double output_step = 0.01;  // fixed-step modes: a whole number of steps
    // Called at every output sample with the fraction done; return false to stop.
    std::function<bool(double)> progress;
};

// Samples of a run: `columns` names (time first), rows of values.
struct Trajectory {
    std::vector<std::string> columns;
    std::vector<double> values;  // row-major
    size_t rows() const { return columns.empty() ? 0 : values.size() / columns.size(); }
};

struct RunSummary {
    std::string integrator;
    double stop_time = 0, step = 0, tolerance = 0, output_step = 0;
    RunStats stats;
    double wall_time = 0;          // s
    double steps_per_second = 0;   // integrator steps per second of wall time
    double energy_start = 0, energy_drift = 0, energy_drift_relative = 0;  // J; drift = max |E - E0|
    bool passive = false;          // no drives, efforts, damping or friction: energy should hold
};

// The trajectory's column names for a model (joint coordinates, then drives).
std::vector<std::string> trajectory_columns(const Model& m);

// Integrates data from its current state to settings.stop_time. Throws
// mbx::Error (MBX_ERROR_CANCELLED when progress said stop) on failure; the
// trajectory then holds what was computed.
RunSummary run(const Model& m, Data& d, const RunSettings& settings, Trajectory& out);

// trajectory.csv and simulation.json as one unit (temporaries, then renames).
void write_run_files(const std::string& dir, const Model& m, const Trajectory& t, const RunSummary& s);

}  // namespace mbx::sim
