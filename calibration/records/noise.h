// The records' own noise: how much of a measured signal is white noise,
// estimated from the record itself, and how much of it the identification's
// low-pass lets into the residual it compares. A cause must not be named for
// explaining noise, and a run may only say it explains the data "to the
// noise" against a measured floor (docs/calibration.md, "Noise floor").
#pragma once
#include <vector>

#include "calibration/records/records.h"

namespace mbx::calibration {

// Standard deviation of the noise on a sampled signal, as a white noise
// of the level the signal shows above `band_edge` Hz (a band the motion
// does not reach): what the zero-phase low-pass at band_edge removes, its
// median square (which a friction step or a spike hardly moves) divided by
// that of a Gaussian, 0.4549, and by the share of a white noise's variance
// the removal keeps. A noise that falls off with frequency (a drive's
// current filter) is taken at its level above band_edge. 0 for fewer than
// 8 samples.
//
// A measured position's noise is an encoder's quantisation, uniform rather
// than Gaussian: its median square is 0.75 of its variance where a
// Gaussian's is 0.4549 (taken as Gaussian, it reads 1.28 times too large).
// Positions are read as NoiseShape::Uniform.
enum class NoiseShape { Gaussian, Uniform };
double white_noise_sigma(const std::vector<double>& x, double dt, double band_edge,
                         NoiseShape shape = NoiseShape::Gaussian);

// The share of a white noise's variance that low_pass (filters.h) at
// `cutoff` Hz and sampling period `dt` lets through: the squared gain of the
// forward and backward pass, averaged over the band up to half the sampling
// rate (about 1.67 cutoff dt for a cutoff well below it).
double low_pass_noise_share(double dt, double cutoff);

// The same for a position noise differentiated twice (central differences,
// as the identification does) after the low-pass: the variance of the
// acceleration noise is sigma_q^2 times this over dt^4.
double low_pass_acceleration_share(double dt, double cutoff);

// The effort noise of one record and joint (its level above twice the
// record's filter cutoff), and what of it reaches the compared (filtered)
// effort.
struct SignalNoise {
    int record = -1;     // index into the records given
    int dof = -1;        // the effort's coordinate
    double sigma = 0;    // N m or N, the raw record's
    double filtered = 0; // N m or N, after the record's low-pass
    double rms = 0;      // the raw effort's RMS, for scale
};

// Every effort signal of `records` for the coordinates `dofs`.
std::vector<SignalNoise> effort_noise(const std::vector<const Record*>& records, const std::vector<int>& dofs);

}  // namespace mbx::calibration
