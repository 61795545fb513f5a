#include "calibration/records/filters.h"

#include <algorithm>
#include <cmath>

#include "core/heartbeat.h"

namespace mbx::calibration {

namespace {

// Samples between beats of the current run's heartbeat (a power of two): a
// record of millions of samples is filtered in one call.
constexpr size_t kBeatSamples = 4096;

struct Biquad {
    double b0, b1, b2, a1, a2;
};

// Bilinear transform of the analogue Butterworth prototype, prewarped at the cutoff.
Biquad butterworth(double dt, double cutoff) {
    const double k = std::tan(M_PI * cutoff * dt);
    const double q = std::sqrt(2.0);
    const double norm = 1 / (1 + q * k + k * k);
    Biquad f;
    f.b0 = k * k * norm;
    f.b1 = 2 * f.b0;
    f.b2 = f.b0;
    f.a1 = 2 * (k * k - 1) * norm;
    f.a2 = (1 - q * k + k * k) * norm;
    return f;
}

// One pass, starting from the steady state of the first value (a step from
// rest would otherwise be filtered in).
void pass(const Biquad& f, std::vector<double>& x) {
    if (x.empty()) return;
    const double x0 = x[0];
    double x1 = x0, x2 = x0, y1 = x0, y2 = x0;
    for (size_t k = 0; k < x.size(); ++k) {
        if ((k & (kBeatSamples - 1)) == 0) heartbeat();
        double& v = x[k];
        const double y = f.b0 * v + f.b1 * x1 + f.b2 * x2 - f.a1 * y1 - f.a2 * y2;
        x2 = x1, x1 = v, y2 = y1, y1 = y;
        v = y;
    }
}

}  // namespace

std::vector<double> low_pass(const std::vector<double>& x, double dt, double cutoff) {
    const size_t n = x.size();
    if (n < 3 || !(cutoff > 0) || cutoff >= 0.5 / dt) return x;
    // Pad by point reflection (2 x0 - x[k]) over a few time constants of the filter.
    const size_t pad = std::min(n - 1, size_t(std::ceil(3.0 / (cutoff * dt))));
    // (Filled as it goes, with beats: on a record of millions of samples a
    // fresh vector's page faults alone take tens of milliseconds.)
    std::vector<double> y;
    y.reserve(n + 2 * pad);
    for (size_t k = pad; k >= 1; --k) y.push_back(2 * x[0] - x[k]);
    for (size_t k = 0; k < n; k += kBeatSamples) {
        heartbeat();
        y.insert(y.end(), x.begin() + long(k), x.begin() + long(std::min(n, k + kBeatSamples)));
    }
    for (size_t k = 1; k <= pad; ++k) y.push_back(2 * x[n - 1] - x[n - 1 - k]);
    const Biquad f = butterworth(dt, cutoff);
    pass(f, y);
    std::reverse(y.begin(), y.end());
    pass(f, y);
    std::reverse(y.begin(), y.end());
    y.erase(y.begin(), y.begin() + long(pad));
    y.resize(n);
    return y;
}

std::vector<double> derivative(const std::vector<double>& x, double dt) {
    const size_t n = x.size();
    if (n < 2) return std::vector<double>(n, 0.0);
    std::vector<double> d;
    d.reserve(n);
    d.push_back((x[1] - x[0]) / dt);
    for (size_t k = 1; k + 1 < n; ++k) {
        if ((k & (kBeatSamples - 1)) == 0) heartbeat();
        d.push_back((x[k + 1] - x[k - 1]) / (2 * dt));
    }
    d.push_back((x[n - 1] - x[n - 2]) / dt);
    return d;
}

}  // namespace mbx::calibration
