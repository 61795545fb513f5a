// The scalar the simulation fit differentiates with: a Ceres Jet of the
// stride its DynamicAutoDiffCostFunction evaluates at once. The dynamics on
// it are compiled once, in fit_scalar.cpp and fit_scalar_forward.cpp, and declared extern
// here for the fit (as sim/dynamics.h does for double).
#pragma once
#include <ceres/jet.h>

#include "sim/forward_dynamics.h"

namespace mbx::calibration {

// Derivatives carried per pass: four parameters of a window at a time.
constexpr int kFitStride = 4;
using FitJet = ceres::Jet<double, kFitStride>;

}  // namespace mbx::calibration

namespace mbx::sim {

MBX_SIM_DYNAMICS_INSTANCES(extern, ::mbx::calibration::FitJet)
MBX_SIM_LOOP_CLOSURE_INSTANCES(extern, ::mbx::calibration::FitJet)
MBX_SIM_FORWARD_DYNAMICS_INSTANCES(extern, ::mbx::calibration::FitJet)

}  // namespace mbx::sim
