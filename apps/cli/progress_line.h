// `--progress` on stderr for the long commands (simulate, calibrate, excite):
// a line when a stage begins, then one at most every second of wall time
// with the fraction, the rate and the time left, and one at the end. The C
// API calls the callback every few tens of milliseconds; a terminal wants
// far fewer lines than that.
#pragma once
#include <chrono>
#include <string>

namespace mbx_cli {

class ProgressLine {
public:
    // `total` and `unit`: what a fraction of 1 stands for (the stop time, in
    // "s"), shown with the rate in those units; 0: fractions only.
    explicit ProgressLine(double total = 0, std::string unit = {}) : total_(total), unit_(std::move(unit)) {}

    // An mbx_progress_fn; `user` is the ProgressLine.
    static int callback(void* user, const char* stage, double fraction);

private:
    void print(const char* stage, double fraction, std::chrono::steady_clock::time_point now);

    double total_;
    std::string unit_, stage_;
    bool finished_ = false;
    std::chrono::steady_clock::time_point stage_start_{}, last_line_{};
};

}  // namespace mbx_cli
