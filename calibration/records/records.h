// The measured records of an experiment, read from CSV and bound to a
// simulation model: per record its time and, per compared or driving
// quantity, a signal on a joint's velocity coordinate in SI. A record's
// time window (start/stop) is cut here, so later stages see only the
// samples they may use.
#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include "calibration/records/experiment.h"
#include "core/csv_table.h"
#include "sim/model.h"

namespace mbx::calibration {

struct Signal {
    Quantity quantity = Quantity::Position;
    int joint = -1;  // sim joint index (1-dof joints)
    int dof = -1;    // its velocity coordinate
    std::string column;
    std::vector<double> values;  // SI, one per sample
};

// A measured body quantity (calibration/body_quantities.h), in SI: kept
// apart from the joint signals, which every joint-space stage reads by
// velocity coordinate.
struct BodySignal {
    Quantity quantity = Quantity::Position;
    int body = -1;       // sim body index
    int component = -1;  // world axis, quaternion component (w x y z) or body axis, as ColumnSpec's
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  // m, body frame
    std::string column;
    std::vector<double> values;
};

struct Record {
    std::string path;
    Role role = Role::Fit;
    double start = 0, stop = 0;  // the window used, s
    std::vector<double> t;       // s
    std::vector<Signal> signals;
    std::vector<BodySignal> body_signals;
    double cutoff = 0;  // Hz, the experiment's <filter cutoff>; 0: from the sampling rate

    // The signal of this body quantity (the same point, exactly), or null.
    const BodySignal* find_body(Quantity q, int body, int component, const Eigen::Vector3d& point) const {
        for (const BodySignal& s : body_signals)
            if (s.quantity == q && s.body == body && s.component == component && s.point == point) return &s;
        return nullptr;
    }

    const Signal* find(Quantity q, int dof) const {
        for (const Signal& s : signals)
            if (s.quantity == q && s.dof == dof) return &s;
        return nullptr;
    }
    double sample_period() const { return t.size() > 1 ? (t.back() - t.front()) / double(t.size() - 1) : 0; }
    // The low-pass applied to measured positions and efforts before they are
    // differentiated or compared: the experiment's cutoff, else a fortieth of
    // the sampling rate (at most 25 Hz), which keeps a servo's motion band
    // and leaves most of a current sensor's noise out.
    double filter_cutoff() const {
        const double dt = sample_period();
        const double automatic = dt > 0 ? std::min(25.0, 1.0 / (40.0 * dt)) : 25.0;
        return cutoff > 0 ? cutoff : automatic;
    }
};

// Below this a record (after its window) cannot tell the causes apart.
constexpr size_t kMinimumSamples = 50;
// A trial of a record file with <trials> (a toss) is fitted by rollouts of
// the whole trial, which a few samples already constrain.
constexpr size_t kMinimumTrialSamples = 10;

// The 1-dof joint a <column> or <compare> names (CAD constraint id or report
// name); throws mbx::Error naming file and line for no joint, an ambiguous
// name, or a joint without a single coordinate.
int joint_of_key(const sim::Model& m, const std::string& key, const std::string& file, int line);

// Reads every record of `e` and binds its columns to `m`'s joints (CAD
// constraint id or report name) and bodies (rigid body id or report name).
// Throws mbx::Error naming file and line:
// unknown joint or body, a unit of the wrong kind for it, a missing column, a cell
// that is not a finite number, time not increasing, too few samples.
std::vector<Record> load_records(const Experiment& e, const sim::Model& m);

// One CSV of a record read into named columns (core/csv_table.h, errors on
// the experiment), for the stages, tests and tools.
using Table = CsvTable;
inline Table read_csv(const std::string& path) { return read_csv_table(path, Subject::model("experiment")); }
// The same from text in memory; `path` names it in errors.
inline Table read_csv_text(const std::string& text, const std::string& path) {
    return read_csv_table_text(text, path, Subject::model("experiment"));
}

}  // namespace mbx::calibration
