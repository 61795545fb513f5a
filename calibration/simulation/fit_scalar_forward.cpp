// forward_dynamics on the simulation fit's Jet, compiled once (see fit_scalar.h).
#include "calibration/simulation/fit_scalar.h"

#include "sim/forward_dynamics.hxx"

namespace mbx::sim {

MBX_SIM_FORWARD_DYNAMICS_INSTANCES(, ::mbx::calibration::FitJet)

}  // namespace mbx::sim
