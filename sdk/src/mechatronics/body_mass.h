// A body's mass corrected in the description file (`<body id mass_scale>`,
// docs/mechatronics.md): calibration names a mass error when a CAD part's
// material or a missing component makes the body lighter or heavier than the
// CAD model says. The whole inertia scales (mass, and the inertia tensor
// about the unchanged centre of mass: the same shape, more or less material),
// and it applies to the translated mechanism itself, so the simulator and
// every export see the same body.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"
#include "mechatronics/object_library.h"

namespace mbx {

struct Mechanism;

struct BodyMassSpec {
    std::string body;  // the rigid body's id (its principal CAD part id), or any of its parts' ids
    double mass_scale = 1;
    std::string file;
    int line = 0;
};

struct ResolvedBodyMass {
    int body = -1;    // Mechanism::bodies index
    int source = -1;  // MechatronicSpec::body_masses index
    double mass_scale = 1;
};

// Refuses an unknown body, a body reached twice and a scale that is not a
// positive finite number; the rest resolve.
std::vector<ResolvedBodyMass> resolve_body_masses(const std::vector<BodyMassSpec>& specs, const Mechanism& m,
                                                  std::vector<LibraryError>& errors);

// The CAD inertia of every body, so that corrections can be applied again
// from it (attaching another description must not compound them).
struct CadInertia {
    std::vector<std::pair<double, Mat3>> bodies;  // mass, inertia about the centre of mass
};
CadInertia cad_inertia(const Mechanism& m);

// Sets every body to its CAD inertia times its correction (1 without one).
void apply_body_masses(Mechanism& m, const CadInertia& cad, const std::vector<ResolvedBodyMass>& masses);

}  // namespace mbx
