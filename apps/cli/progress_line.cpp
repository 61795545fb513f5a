#include "progress_line.h"

#include <cmath>
#include <cstdio>

namespace mbx_cli {
namespace {

constexpr std::chrono::seconds kLineInterval{1};

// A duration for people: 45 s, 12 min, 3.2 h.
std::string duration_text(double s) {
    char buf[32];
    if (!std::isfinite(s)) return "?";
    if (s < 10)
        std::snprintf(buf, sizeof buf, "%.1f s", s);
    else if (s < 90)
        std::snprintf(buf, sizeof buf, "%.0f s", s);
    else if (s < 5400)
        std::snprintf(buf, sizeof buf, "%.0f min", s / 60);
    else
        std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
    return buf;
}

}  // namespace

int ProgressLine::callback(void* user, const char* stage, double fraction) {
    ProgressLine& p = *static_cast<ProgressLine*>(user);
    const auto now = std::chrono::steady_clock::now();
    if (p.stage_ != stage) {
        p.stage_ = stage;
        p.stage_start_ = now;
        p.finished_ = false;
        p.print(stage, fraction, now);
    } else if (fraction >= 1 && !p.finished_) {
        p.print(stage, fraction, now);
    } else if (now - p.last_line_ >= kLineInterval && fraction < 1) {
        p.print(stage, fraction, now);
    }
    p.finished_ = p.finished_ || fraction >= 1;
    return 0;
}

void ProgressLine::print(const char* stage, double fraction, std::chrono::steady_clock::time_point now) {
    last_line_ = now;
    const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
    std::string line = "mbx: " + std::string(stage);
    char buf[96];
    std::snprintf(buf, sizeof buf, " %.1f%%", 100 * fraction);
    line += buf;
    // A rate only once there is something to measure it on.
    if (elapsed >= 0.5 && fraction > 0) {
        if (total_ > 0) {
            std::snprintf(buf, sizeof buf, ", %.4g of %.4g %s, %.3g %s per second", fraction * total_, total_, unit_.c_str(),
                          fraction * total_ / elapsed, unit_.c_str());
            line += buf;
        }
        if (fraction < 1) line += ", " + duration_text(elapsed * (1 - fraction) / fraction) + " left";
        else line += ", took " + duration_text(elapsed);
    } else if (elapsed >= 0.5) {
        line += ", " + duration_text(elapsed) + " so far";  // a stage that cannot yet say how far it is
    }
    std::fprintf(stderr, "%s\n", line.c_str());
}

}  // namespace mbx_cli
