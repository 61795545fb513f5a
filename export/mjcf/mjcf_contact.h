// Collision shapes and contact materials in MJCF (docs/contact.md, MJCF):
// a geom per shape, contype/conaffinity from its group/mask, and per pair of
// materials MuJoCo's friction, solref and solimp converted from mbx's laws
// (sim/contact/parameter_conversion.h).
#pragma once
#include <string>

#include "core/mechatronics/contact_description.h"

namespace mbx {

// What one material pair becomes in MuJoCo.
struct MjcfContactParams {
    double timeconst = 0.02, dampratio = 1;  // solref
    double impedance = 0.9;                  // solimp = d d width
    double friction = 1;                     // sliding
    std::string approximation;               // what the conversion leaves out ("" if nothing)
};

// The impedance the export uses: its (1 - d) share of the load is what the
// solref's rest depth is sized for; 0.9 keeps MuJoCo's friction holding 90 %
// of a tangential load through the constraint itself.
constexpr double kMjcfContactImpedance = 0.9;

// `mass`: the body the contact is sized for (the lightest moving body made of
// either material); `gravity` > 0.
MjcfContactParams mjcf_contact_params(const ContactMaterialSpec& m, double mass, double gravity);

}  // namespace mbx
