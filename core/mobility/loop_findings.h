// The findings mobility analysis reports about one loop.
#pragma once
#include "core/translator/mechanism.h"

namespace mbx::mobility {

// Adds PLANAR_LOOP, REDUNDANT_CONSTRAINTS and MOBILITY_MISMATCH findings for
// the analysed loop `loop_index` (see the .cpp for when each applies).
void report_loop(Mechanism& mech, int loop_index);

}  // namespace mbx::mobility
