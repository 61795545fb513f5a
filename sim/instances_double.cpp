// The dynamics on double, compiled here once for every user of the
// simulator (their headers declare these instances extern). The constrained
// forward dynamics, the heaviest to compile, has a unit of its own
// (forward_dynamics_double.cpp) so that two cores share the work.
#include "sim/loop_closure.hxx"

namespace mbx::sim {

MBX_SIM_DYNAMICS_INSTANCES(, double)
MBX_SIM_LOOP_CLOSURE_INSTANCES(, double)

}  // namespace mbx::sim
