// Progress for long runs (a simulation, a calibration), reported by wall
// time rather than by item: a run's loops differ by orders of magnitude in
// cost per item (a fixed step of a pendulum, a CVODE step of a robot, a
// rollout inside a Ceres iteration), so a stride in items either floods the
// host or leaves it without word for minutes. The C API promises a call
// well within every 100 ms, and a cancel that takes effect within that.
//
// The run owns a Heartbeat and makes it current for its thread
// (HeartbeatScope); any loop below, however deep, calls mbx::heartbeat()
// once per item. That costs a clock read; the host's callback runs only when
// `interval` has passed since the last one. Loops need not know what run
// they serve, nor pass a callback through every signature: a loop outside
// any run (a test, a benchmark) beats into nothing.
//
// Worker threads of the run may make its heartbeat current too: their beats
// only learn of a cancel (and throw), the callback runs on the run's own
// thread. Code that must not throw (a Ceres cost function) asks cancelled().
#pragma once
#include <atomic>
#include <chrono>
#include <functional>
#include <string>
#include <thread>

namespace mbx {

class Heartbeat {
public:
    // Receives the stage and the fraction of the whole run done; returns
    // false to cancel. Never called more often than every `interval`.
    using Callback = std::function<bool(const char* stage, double fraction)>;

    static constexpr std::chrono::milliseconds kDefaultInterval{25};

    explicit Heartbeat(Callback callback, std::string what = "the run",
                       std::chrono::steady_clock::duration interval = kDefaultInterval);

    // Enters a stage and reports at once (a stage change is news).
    void stage(const char* name, double fraction);
    // An item of work done at `fraction` of the whole run (negative: no new
    // fraction, the last one stands). Throws mbx::Error(MBX_ERROR_CANCELLED)
    // when the callback asks to stop.
    void beat(double fraction = -1) {
        if (cancelled_.load(std::memory_order_acquire)) throw_cancelled();
        if (std::this_thread::get_id() != owner_) return;
        if (fraction >= 0) fraction_ = fraction;
        const auto now = std::chrono::steady_clock::now();
        if (now >= next_) report(now);
    }
    // Whether the callback asked to stop (any thread may ask).
    bool cancelled() const { return cancelled_.load(std::memory_order_acquire); }
    // Throws the cancel's mbx::Error if there was one (after code that could
    // not throw, a solver, returns).
    void throw_if_cancelled() const {
        if (cancelled()) throw_cancelled();
    }
    // Reports now, whatever the time since the last call (the end of a run).
    void report_now(double fraction);

    const char* stage_name() const { return stage_; }
    // The longest wall time between two calls of the callback so far (s).
    double longest_gap() const { return longest_gap_; }

private:
    void report(std::chrono::steady_clock::time_point now);
    [[noreturn]] void throw_cancelled() const;

    Callback callback_;
    std::thread::id owner_ = std::this_thread::get_id();
    std::atomic<bool> cancelled_{false};
    std::string cancel_message_;
    std::string what_;
    std::chrono::steady_clock::duration interval_;
    std::chrono::steady_clock::time_point last_, next_;
    const char* stage_ = "";
    double fraction_ = 0, longest_gap_ = 0;
};

// The heartbeat of the run on this thread, or nullptr.
Heartbeat* current_heartbeat();

// Makes `h` the current heartbeat of this thread for the scope's life (the
// previous one comes back after it). nullptr: none, loops run silent.
class HeartbeatScope {
public:
    explicit HeartbeatScope(Heartbeat* h);
    ~HeartbeatScope();
    HeartbeatScope(const HeartbeatScope&) = delete;
    HeartbeatScope& operator=(const HeartbeatScope&) = delete;

private:
    Heartbeat* previous_;
};

// One item of work done by a loop of the current run (see the top).
inline void heartbeat() {
    if (Heartbeat* h = current_heartbeat()) h->beat();
}

// One item done, the innermost HeartbeatShare's part at `part_fraction`.
// Without a share it is an item done and no more: a loop tells its fraction
// only where its caller gave it a share of the stage (a loop reused by
// another stage must not move that stage's fraction back and forth).
void heartbeat(double part_fraction);

// The current run is at `fraction` of stage `stage`: a new stage reports at
// once, progress within one by wall time.
void heartbeat(const char* stage, double fraction);

// Maps the fractions a part of a run reports ([0, 1] of the part) onto its
// share [from, to] of the enclosing share (of the whole run when none), for
// the life of the scope: the replay of the fourth record of ten reports its
// own samples, the run sees 0.3-0.4. Without a current heartbeat it does
// nothing.
class HeartbeatShare {
public:
    HeartbeatShare(double from, double to);
    ~HeartbeatShare();
    HeartbeatShare(const HeartbeatShare&) = delete;
    HeartbeatShare& operator=(const HeartbeatShare&) = delete;

private:
    friend void heartbeat(double part_fraction);
    double from_, to_;
    const HeartbeatShare* outer_;
};

}  // namespace mbx
