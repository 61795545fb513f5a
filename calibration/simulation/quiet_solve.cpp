#include "calibration/simulation/quiet_solve.h"

#include <glog/logging.h>

#include <mutex>

#include "core/finding.h"
#include "core/heartbeat.h"

namespace mbx::calibration {

namespace {

std::mutex hold_mutex;
int holders = 0;
int level_before = 0;

// Messages below FATAL are dropped before glog formats them; FATAL would
// abort the process, which no solve of ours asks for.
class GlogHold {
public:
    GlogHold() {
        std::lock_guard<std::mutex> lock(hold_mutex);
        if (google::IsGoogleLoggingInitialized()) return;
        held_ = true;
        if (holders++ == 0) {
            level_before = FLAGS_minloglevel;
            FLAGS_minloglevel = google::GLOG_FATAL;
        }
    }
    ~GlogHold() {
        if (!held_) return;
        std::lock_guard<std::mutex> lock(hold_mutex);
        if (--holders == 0) FLAGS_minloglevel = level_before;
    }
    GlogHold(const GlogHold&) = delete;
    GlogHold& operator=(const GlogHold&) = delete;

private:
    bool held_ = false;
};


// Between iterations, on the solving thread: the run's progress, and a
// cancel that a cost function saw (and answered with a failed evaluation,
// as an exception must not cross Ceres) ends the solve.
class HeartbeatCallback final : public ceres::IterationCallback {
public:
    explicit HeartbeatCallback(Heartbeat& h) : heartbeat_(h) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
        if (heartbeat_.cancelled()) return ceres::SOLVER_ABORT;
        try {
            heartbeat_.beat();
        } catch (const Error&) {
            return ceres::SOLVER_ABORT;
        }
        return ceres::SOLVER_CONTINUE;
    }

private:
    Heartbeat& heartbeat_;
};

}  // namespace

void solve_quietly(const ceres::Solver::Options& options, ceres::Problem* problem, ceres::Solver::Summary* summary) {
    GlogHold hold;
    Heartbeat* heartbeat = current_heartbeat();
    if (!heartbeat) return ceres::Solve(options, problem, summary);
    HeartbeatCallback callback(*heartbeat);
    ceres::Solver::Options with_callback = options;
    with_callback.callbacks.push_back(&callback);
    ceres::Solve(with_callback, problem, summary);
    heartbeat->throw_if_cancelled();
}

std::string solver_note(const ceres::Solver::Summary& summary, const std::string& what) {
    switch (summary.termination_type) {
        case ceres::CONVERGENCE:
        case ceres::USER_SUCCESS:
            return "";
        case ceres::NO_CONVERGENCE:
            return what + " stopped at its iteration limit (" + std::to_string(summary.iterations.size()) +
                   " steps) before converging; its values are the last step's";
        default:
            return what + " failed: " + (summary.message.empty() ? std::string("the solver gave no reason")
                                                                  : summary.message);
    }
}

}  // namespace mbx::calibration
