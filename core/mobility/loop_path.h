// The fundamental cycle of a cut joint in the spanning tree.
#pragma once
#include "core/translator/mechanism.h"

namespace mbx::mobility {

// Fills mech.loops[loop_index].joints and .signs in the order and with the
// signs documented in mobility.h. Walks up from both ends of the cut joint
// by depth, so the cost is proportional to the loop's length. Throws
// Error(MBX_ERROR_INTERNAL) naming the loop if the tree is inconsistent.
void trace_loop(Mechanism& mech, int loop_index);

}  // namespace mbx::mobility
