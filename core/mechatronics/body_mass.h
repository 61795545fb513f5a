// A body's inertia corrected in the description file (`<body id mass_scale
// com_shift inertia_change>`, docs/mechatronics.md): calibration names a
// mass error when a CAD part's material or a missing component makes the body
// lighter or heavier than the CAD model says, its centre of mass lies
// elsewhere, or its inertia differs. The corrections are relative to the CAD
// values (so they survive a re-export of a CAD model that still has the
// error, and mean nothing odd once it is fixed), and they apply to the
// translated mechanism itself, so the simulator and every export see the
// same body.
#pragma once
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"
#include "core/mechatronics/object_library.h"

namespace mbx {

struct Mechanism;

// The entries of a symmetric 3x3 change in the order xx yy zz xy xz yz.
using InertiaEntries = std::array<double, 6>;
Mat3 inertia_from_entries(const InertiaEntries& e);

// Why no rigid body has this inertia about its centre of mass: not positive
// definite, or a principal moment above the sum of the other two ("" if one can).
std::string implausible_inertia(const Mat3& inertia_about_com);

struct BodyMassSpec {
    std::string body;  // the rigid body's id (its principal CAD part id), or any of its parts' ids
    // The whole inertia times mass_scale (the same shape, more or less material) ...
    double mass_scale = 1;
    // ... then the centre of mass moved by com_shift (m, body frame; the
    // inertia about it unchanged) and inertia_change (kg m^2, about the
    // centre of mass, body axes) added to the inertia tensor.
    Vec3 com_shift = Vec3::Zero();
    InertiaEntries inertia_change{};
    std::string file;
    int line = 0;
};

struct ResolvedBodyMass {
    int body = -1;    // Mechanism::bodies index
    int source = -1;  // MechatronicSpec::body_masses index
    double mass_scale = 1;
    Vec3 com_shift = Vec3::Zero();
    InertiaEntries inertia_change{};
};

// The CAD inertia of every body, so that corrections can be applied again
// from it (attaching another description must not compound them).
struct CadInertia {
    struct Body {
        double mass = 0;
        Vec3 com = Vec3::Zero();
        Mat3 inertia = Mat3::Zero();  // about the centre of mass
    };
    std::vector<Body> bodies;
};
CadInertia cad_inertia(const Mechanism& m);

// Refuses an unknown body, a body reached twice, a scale that is not a
// positive finite number, a shift or change that is not finite, and a
// corrected inertia no rigid body can have (not positive definite, or a
// principal moment above the sum of the other two); the rest resolve.
// `cad`: the bodies' CAD inertia (the mechanism's own when null).
std::vector<ResolvedBodyMass> resolve_body_masses(const std::vector<BodyMassSpec>& specs, const Mechanism& m,
                                                  const CadInertia* cad, std::vector<LibraryError>& errors);

// Sets every body to its CAD inertia with its correction (none without one).
void apply_body_masses(Mechanism& m, const CadInertia& cad, const std::vector<ResolvedBodyMass>& masses);

}  // namespace mbx
