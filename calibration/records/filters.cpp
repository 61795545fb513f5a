#include "calibration/records/filters.h"

#include <algorithm>
#include <cmath>

namespace mbx::calibration {

namespace {

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
    for (double& v : x) {
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
    std::vector<double> y;
    y.reserve(n + 2 * pad);
    for (size_t k = pad; k >= 1; --k) y.push_back(2 * x[0] - x[k]);
    y.insert(y.end(), x.begin(), x.end());
    for (size_t k = 1; k <= pad; ++k) y.push_back(2 * x[n - 1] - x[n - 1 - k]);
    const Biquad f = butterworth(dt, cutoff);
    pass(f, y);
    std::reverse(y.begin(), y.end());
    pass(f, y);
    std::reverse(y.begin(), y.end());
    return std::vector<double>(y.begin() + long(pad), y.begin() + long(pad + n));
}

std::vector<double> derivative(const std::vector<double>& x, double dt) {
    const size_t n = x.size();
    std::vector<double> d(n, 0.0);
    if (n < 2) return d;
    d[0] = (x[1] - x[0]) / dt;
    d[n - 1] = (x[n - 1] - x[n - 2]) / dt;
    for (size_t k = 1; k + 1 < n; ++k) d[k] = (x[k + 1] - x[k - 1]) / (2 * dt);
    return d;
}

}  // namespace mbx::calibration
