#include "calibration/simulation/quiet_solve.h"

#include <glog/logging.h>

#include <mutex>

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

}  // namespace

void solve_quietly(const ceres::Solver::Options& options, ceres::Problem* problem, ceres::Solver::Summary* summary) {
    GlogHold hold;
    ceres::Solve(options, problem, summary);
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
