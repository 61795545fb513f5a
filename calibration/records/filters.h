// Zero-phase low-pass filtering and differentiation of sampled signals, as
// inverse-dynamics identification needs them: positions from an encoder are
// differentiated twice, so noise above the motion's band must go first, and
// every signal that enters one regression is filtered alike (the effort too),
// so the filter's own response cancels out of the fit.
#pragma once
#include <vector>

namespace mbx::calibration {

// Second-order Butterworth low-pass at `cutoff` Hz for sampling period `dt`,
// run forward then backward (no phase lag, fourth-order magnitude); the
// ends are padded by point reflection so that they do not ring.
std::vector<double> low_pass(const std::vector<double>& x, double dt, double cutoff);

// Central differences (one-sided at the ends).
std::vector<double> derivative(const std::vector<double>& x, double dt);

}  // namespace mbx::calibration
