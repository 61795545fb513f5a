#include "export/mjcf/mjcf_contact.h"

#include <algorithm>
#include <cmath>

// Header-only closed forms; mbx_export does not link the contact library.
#include "../../sim/contact/parameter_conversion.h"

namespace mbx {

MjcfContactParams mjcf_contact_params(const ContactMaterialSpec& m, double mass, double gravity) {
    namespace sc = sim::contact;
    MjcfContactParams p;
    p.impedance = kMjcfContactImpedance;
    std::string lost;
    // MuJoCo's contact is linear: a power law becomes the secant stiffness at
    // the rest depth under the body's weight (the same rest depth).
    const double load = mass * gravity;
    const double rest = std::pow(load / m.stiffness, 1 / m.exponent);
    const double k = m.exponent == 1 ? m.stiffness : load / rest;
    if (m.exponent != 1) lost += "the power law d^" + std::to_string(m.exponent) + " is linearised at the rest depth; ";
    // The damping ratio keeps the restitution.
    double zeta = 0;
    if (m.use_restitution) {
        zeta = sc::damping_ratio_for_restitution_with_cut(m.restitution);
        if (m.restitution < sc::restitution_with_cut(0.999))
            lost += "a linear contact that cannot pull rebounds at least " + std::to_string(sc::restitution_with_cut(0.999)) +
                    " of its impact speed (restitution " + std::to_string(m.restitution) + " asked); ";
    } else if (m.normal == ContactNormalLaw::SpringDamper) {
        zeta = sc::damping_ratio({k, m.damping}, mass);
    } else if (m.normal == ContactNormalLaw::HuntCrossley) {
        // Hunt-Crossley's restitution to first order at 1 m/s.
        zeta = sc::damping_ratio_for_restitution_with_cut(std::clamp(1 - 2.0 / 3.0 * m.damping, 0.01, 1.0));
        lost += "Hunt-Crossley damping as the restitution it gives at 1 m/s; ";
    }
    if (zeta < 0.01) {
        zeta = 0.01;  // MuJoCo's contact needs some damping
        lost += "undamped contact given 1 % of critical damping; ";
    }
    const sc::MujocoSolref s = sc::mbx_to_mujoco({k, zeta * 2 * std::sqrt(k * mass)}, mass, p.impedance);
    p.timeconst = s.timeconst, p.dampratio = s.dampratio;
    p.friction = m.mu_static == m.mu_kinetic ? m.mu_static : 0.5 * (m.mu_static + m.mu_kinetic);
    if (m.mu_static != m.mu_kinetic) lost += "one friction coefficient, the mean of mu_static and mu_kinetic; ";
    lost += m.friction == ContactFrictionLaw::Spring ? "MuJoCo's own soft friction constraint replaces the friction spring"
                                                      : "MuJoCo's own soft friction constraint replaces the regularised law";
    p.approximation = lost;
    return p;
}

}  // namespace mbx
