// forward_dynamics on double, compiled once (see instances_double.cpp).
#include "sim/forward_dynamics.hxx"

namespace mbx::sim {

MBX_SIM_FORWARD_DYNAMICS_INSTANCES(, double)

}  // namespace mbx::sim
