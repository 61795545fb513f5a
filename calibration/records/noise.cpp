#include "calibration/records/noise.h"

#include <algorithm>
#include <cmath>

#include "calibration/records/filters.h"

namespace mbx::calibration {

namespace {

// The zero-phase gain of low_pass at `cutoff` (the biquad of filters.cpp,
// bilinear Butterworth prewarped at the cutoff, squared by the backward
// pass) at angular frequency w (rad per sample).
double zero_phase_gain(double dt, double cutoff, double w) {
    const double k = std::tan(M_PI * cutoff * dt), q = std::sqrt(2.0), norm = 1 / (1 + q * k + k * k);
    const double b0 = k * k * norm, b1 = 2 * b0, b2 = b0;
    const double a1 = 2 * (k * k - 1) * norm, a2 = (1 - q * k + k * k) * norm;
    const double c1 = std::cos(w), s1 = std::sin(w), c2 = std::cos(2 * w), s2 = std::sin(2 * w);
    const double nr = b0 + b1 * c1 + b2 * c2, ni = -(b1 * s1 + b2 * s2);
    const double dr = 1 + a1 * c1 + a2 * c2, di = -(a1 * s1 + a2 * s2);
    return (nr * nr + ni * ni) / (dr * dr + di * di);
}

// The mean over 0..pi of f(gain).
template <class F> double band_mean(double dt, double cutoff, F f) {
    constexpr int kSteps = 20000;
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) sum += f(zero_phase_gain(dt, cutoff, M_PI * (i + 0.5) / kSteps));
    return sum / kSteps;
}

}  // namespace

double white_noise_sigma(const std::vector<double>& x, double dt, double band_edge, NoiseShape shape) {
    if (x.size() < 8 || !(dt > 0)) return 0;
    const bool filtered = band_edge > 0 && band_edge < 0.5 / dt;
    const std::vector<double> smooth = filtered ? low_pass(x, dt, band_edge) : std::vector<double>(x.size(), 0.0);
    std::vector<double> squares(x.size());
    for (size_t k = 0; k < x.size(); ++k) squares[k] = (x[k] - smooth[k]) * (x[k] - smooth[k]);
    const double kept = filtered ? band_mean(dt, band_edge, [](double g) { return (1 - g) * (1 - g); }) : 1.0;
    const auto middle = squares.begin() + std::ptrdiff_t(squares.size() / 2);
    std::nth_element(squares.begin(), middle, squares.end());
    // The median square over the variance: a chi-square of one degree's
    // median for a Gaussian; (1/4)^2 / (1/12) for a uniform noise.
    const double median_over_variance = shape == NoiseShape::Uniform ? 0.75 : 0.454936423119572;
    return std::sqrt(*middle / median_over_variance / kept);
}

double low_pass_noise_share(double dt, double cutoff) {
    if (!(cutoff > 0) || !(dt > 0) || cutoff >= 0.5 / dt) return 1;
    return band_mean(dt, cutoff, [](double g) { return g * g; });
}

double low_pass_acceleration_share(double dt, double cutoff) {
    // Each central difference has the gain sin(w) / dt.
    const double s4 = 3.0 / 8.0;  // the mean of sin^4 over 0..pi: no filter
    if (!(cutoff > 0) || !(dt > 0) || cutoff >= 0.5 / dt) return s4;
    constexpr int kSteps = 20000;
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) {
        const double w = M_PI * (i + 0.5) / kSteps, g = zero_phase_gain(dt, cutoff, w), s = std::sin(w);
        sum += g * g * s * s * s * s;
    }
    return sum / kSteps;
}

std::vector<SignalNoise> effort_noise(const std::vector<const Record*>& records, const std::vector<int>& dofs) {
    std::vector<SignalNoise> out;
    for (size_t r = 0; r < records.size(); ++r) {
        const Record& rec = *records[r];
        const double share = low_pass_noise_share(rec.sample_period(), rec.filter_cutoff());
        for (int dof : dofs) {
            const Signal* s = rec.find(Quantity::Effort, dof);
            if (!s || s->values.empty()) continue;
            SignalNoise n;
            n.record = int(r), n.dof = dof;
            n.sigma = white_noise_sigma(s->values, rec.sample_period(), 2 * rec.filter_cutoff());
            n.filtered = n.sigma * std::sqrt(share);
            double sum = 0;
            for (double v : s->values) sum += v * v;
            n.rms = std::sqrt(sum / double(s->values.size()));
            out.push_back(n);
        }
    }
    return out;
}

}  // namespace mbx::calibration
