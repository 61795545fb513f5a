#include "core/heartbeat.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "core/finding.h"

namespace mbx {
namespace {

thread_local Heartbeat* current = nullptr;
thread_local const HeartbeatShare* current_share = nullptr;

}  // namespace

Heartbeat::Heartbeat(Callback callback, std::string what, std::chrono::steady_clock::duration interval)
    : callback_(std::move(callback)), what_(std::move(what)), interval_(interval) {
    last_ = std::chrono::steady_clock::now();
    next_ = last_ + interval_;
}

void Heartbeat::stage(const char* name, double fraction) {
    stage_ = name;
    report_now(fraction);
}

void Heartbeat::report_now(double fraction) {
    throw_if_cancelled();
    if (fraction >= 0) fraction_ = fraction;
    report(std::chrono::steady_clock::now());
}

void Heartbeat::report(std::chrono::steady_clock::time_point now) {
    longest_gap_ = std::max(longest_gap_, std::chrono::duration<double>(now - last_).count());
    last_ = now;
    next_ = now + interval_;
    if (!callback_) return;
    const double f = std::clamp(std::isfinite(fraction_) ? fraction_ : 0.0, 0.0, 1.0);
    if (!callback_(stage_, f)) {
        char done[32];
        std::snprintf(done, sizeof done, "%.1f", 100 * f);
        cancel_message_ = what_ + " was cancelled during '" + stage_ + "' at " + done + " %";
        cancelled_.store(true);
        throw_cancelled();
    }
}

void Heartbeat::throw_cancelled() const {
    throw Error(MBX_ERROR_CANCELLED, Subject::model(""), cancel_message_);
}

Heartbeat* current_heartbeat() { return current; }

void heartbeat(const char* stage, double fraction) {
    Heartbeat* h = current;
    if (!h) return;
    if (std::strcmp(h->stage_name(), stage) != 0)
        h->stage(stage, fraction);
    else
        h->beat(fraction);
}

HeartbeatScope::HeartbeatScope(Heartbeat* h) : previous_(current) { current = h; }
HeartbeatScope::~HeartbeatScope() { current = previous_; }

HeartbeatShare::HeartbeatShare(double from, double to) : from_(from), to_(to), outer_(current_share) {
    if (outer_) {
        from_ = outer_->from_ + from * (outer_->to_ - outer_->from_);
        to_ = outer_->from_ + to * (outer_->to_ - outer_->from_);
    }
    current_share = this;
}

HeartbeatShare::~HeartbeatShare() { current_share = outer_; }

void heartbeat(double part_fraction) {
    Heartbeat* h = current;
    if (!h) return;
    // Outside any share the part's fraction says nothing of the stage's (a
    // loop reused by another stage): an item done, no more.
    const HeartbeatShare* share = current_share;
    if (!share) return h->beat();
    const double f = std::clamp(part_fraction, 0.0, 1.0);
    h->beat(share->from_ + f * (share->to_ - share->from_));
}

}  // namespace mbx
