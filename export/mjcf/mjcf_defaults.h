// Simulation settings written into every MJCF model (docs/exporters.md, MJCF
// explains the choice). Tests derive their tolerances from these.
#pragma once

namespace mbx {
namespace mjcf_defaults {

// RK4: the exported mechanisms carry no damping, so the integrator's job is
// accuracy on conservative motion (energy, pendulum periods). The step is set
// by the loops: MuJoCo stabilizes a closure at acceleration level without
// the constraint's curvature term (J'qdot), so a moving loop lags by about
// (d * timeconst)^2 times the relative acceleration of the joined points,
// and the time constant may not go below two steps (refsafe). 0.5 ms with
// a 1 ms time constant keeps a swinging 0.1 m linkage within ~0.1 mm;
// MuJoCo's 2 ms step with its 20 ms default time constant gives ~1 cm.
constexpr double timestep = 0.0005;
constexpr const char* integrator = "RK4";
constexpr double gravity = 9.81;  // along -z, MuJoCo's default

// Loop closures: time constant two steps, critically damped, impedance 0.99
// (regularization 1 % of the constraint-space inertia, so a loop under a
// static load gives way little).
constexpr const char* solref = "0.001 1";
constexpr const char* solimp = "0.99 0.99 0.001";

// MuJoCo 2.2 reserves this many constraint rows unless <size njmax> says more.
constexpr int default_njmax = 500;

}  // namespace mjcf_defaults
}  // namespace mbx
