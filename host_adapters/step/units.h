// The units a STEP representation context gives its numbers: metres per
// length unit, radians per plane-angle unit, and the distance uncertainty the
// exporter declared (in the context's own length unit). SI units with their
// prefixes and conversion-based units (inch, degree, Onshape's 'METRE' over
// the SI metre) are read through their measure-with-unit chains.
#pragma once

#include <cmath>
#include <string>

#include "host_adapters/step/part21.h"

namespace mbx_step {

struct ContextUnits {
    double length = 1e-3;       // metres per unit (millimetres where the context says nothing)
    double plane_angle = 1.0;   // radians per unit
    double uncertainty = NAN;   // distance uncertainty in the context's length unit, NaN when not given
    std::string length_name;    // as written: "MILLI METRE", "INCH", "METRE"
    std::string angle_name;     // "RADIAN", "DEGREE"
};

// The units of the representation context at instance index `context`;
// defects (no length unit, a conversion that does not resolve) are added to
// `problems` and the defaults kept.
ContextUnits context_units(const File& f, uint32_t context, std::vector<Problem>& problems);

}  // namespace mbx_step
