// The dynamics on the simulation fit's Jet, compiled once (see fit_scalar.h);
// the forward dynamics in fit_scalar_forward.cpp, so two cores share the work.
#include "calibration/simulation/fit_scalar.h"

#include "sim/loop_closure.hxx"

namespace mbx::sim {

MBX_SIM_DYNAMICS_INSTANCES(, ::mbx::calibration::FitJet)
MBX_SIM_LOOP_CLOSURE_INSTANCES(, ::mbx::calibration::FitJet)

}  // namespace mbx::sim
