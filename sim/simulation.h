// Running a simulation end to end: a consistent initial state from the
// coordinates a user fixes, integration to a stop time with samples at an
// output step, and the files a run leaves (trajectory.csv, simulation.json).
// The CLI's `mbx simulate` and the C API's run call these.
#pragma once
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/heartbeat.h"
#include "core/report/atomic_file.h"
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

// What a run may hold and do (docs/limits.md): a trajectory held in memory
// (samples x columns x 8 bytes; a run's files stream theirs to disk), and a
// fixed-step run's step count. A run beyond either is refused before it starts.
constexpr unsigned long long kTrajectoryLimitBytes = 4ull << 30;
constexpr long long kStepLimit = 1'000'000'000'000LL;

struct RunSettings {
    IntegratorSettings integrator;
    double stop_time = 1.0;
    double output_step = 0.01;  // fixed-step modes: a whole number of steps
    // The fraction of the run done, reported by wall time (every
    // `progress_interval`, whatever the cost of a step or the output step),
    // and once at the end; return false to stop.
    std::function<bool(double)> progress;
    std::chrono::steady_clock::duration progress_interval = Heartbeat::kDefaultInterval;
};

struct RunSummary {
    unsigned long long samples = 0;
    std::string integrator;
    double stop_time = 0, step = 0, tolerance = 0, output_step = 0;
    RunStats stats;
    double wall_time = 0;          // s
    double steps_per_second = 0;   // integrator steps per second of wall time
    double energy_start = 0, energy_drift = 0, energy_drift_relative = 0;  // J; drift = max |E - E0|
    bool passive = false;          // no drives, efforts, damping or friction: energy should hold
};

// Where a run's samples go, one row at a time (time first, then
// trajectory_columns' order).
class SampleSink {
public:
    virtual ~SampleSink() = default;
    // Before the first sample: the columns and how many rows will come.
    // Throws mbx::Error(MBX_ERROR_INVALID_ARGUMENT) naming the limit when the
    // sink cannot take them, before any work.
    virtual void open(const std::vector<std::string>& columns, double rows) = 0;
    virtual void add(const double* row) = 0;
};

// Samples held in memory: `columns` names (time first), rows of values; at
// most kTrajectoryLimitBytes.
struct Trajectory final : SampleSink {
    std::vector<std::string> columns;
    std::vector<double> values;  // row-major
    size_t rows() const { return columns.empty() ? 0 : values.size() / columns.size(); }

    void open(const std::vector<std::string>& names, double rows) override;
    void add(const double* row) override { values.insert(values.end(), row, row + columns.size()); }
};

// A run's files in `dir`: trajectory.csv streamed to its temporary as the
// samples come (memory bounded whatever the run's length; refused before the
// run when it would not fit the folder's free space), then simulation.json;
// commit() renames both as one unit. Destroyed without commit (an error, a
// cancel), it leaves the folder as it was.
class RunFiles final : public SampleSink {
public:
    explicit RunFiles(std::string dir) : dir_(std::move(dir)) {}
    void open(const std::vector<std::string>& names, double rows) override;
    void add(const double* row) override;
    void commit(const Model& m, const RunSummary& summary);

private:
    std::string dir_;
    std::unique_ptr<StreamedFile> csv_;
    std::string line_;
    size_t columns_ = 0;
};

// The trajectory's column names for a model (joint coordinates, then drives).
std::vector<std::string> trajectory_columns(const Model& m);

// Integrates data from its current state to settings.stop_time, the state
// at the start and at every output step into `out`. Throws mbx::Error
// (MBX_ERROR_CANCELLED when progress said stop) on failure; `out` then holds
// what was computed.
RunSummary run(const Model& m, Data& d, const RunSettings& settings, SampleSink& out);

}  // namespace mbx::sim
