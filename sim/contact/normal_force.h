// Normal contact force laws (thesis section 3.8): a penalty spring through
// the penetration, linear or power-law (Hertz, exponent 3/2 for spheres),
// with or without damping: linear spring-damper (Kelvin-Voigt) or
// Hunt-Crossley, whose damping grows with the penetration so the force starts
// and ends at zero. The force never pulls. Templated on the scalar like the
// dynamics core, so calibration's Jets can run through it.
#pragma once
#include <cmath>

namespace mbx::sim::contact {

enum class NormalModel { Spring, SpringDamper, HuntCrossley };

struct NormalLaw {
    NormalModel model = NormalModel::HuntCrossley;
    double stiffness = 1e5;  // k: N/m^exponent
    double exponent = 1.5;   // n: 1 linear, 1.5 Hertz
    // SpringDamper: c in N s/m (force k d^n + c d'); HuntCrossley: chi in s/m
    // (force k d^n (1 + chi d')). See damping_for_restitution.
    double damping = 0;
};

// Force along the normal for penetration `depth` (> 0 inside) growing at
// `depth_rate`; zero when apart, and never negative.
template <class S> S normal_force(const NormalLaw& law, const S& depth, const S& depth_rate) {
    using std::pow;
    if (!(depth > S(0))) return S(0);
    const S elastic = law.exponent == 1 ? S(law.stiffness) * depth : S(law.stiffness) * pow(depth, S(law.exponent));
    S f = elastic;
    if (law.model == NormalModel::SpringDamper) f = elastic + S(law.damping) * depth_rate;
    if (law.model == NormalModel::HuntCrossley) f = elastic * (S(1) + S(law.damping) * depth_rate);
    return f > S(0) ? f : S(0);
}

// The coefficient of restitution (rebound over impact speed) the law gives a
// mass `mass` hitting at `impact_speed` (> 0), found by integrating the
// one-dimensional impact to separation. For Hunt-Crossley it depends on
// chi * impact_speed only.
double restitution(const NormalLaw& law, double mass, double impact_speed);

// The damping (c or chi) for which the law gives restitution `e` to that
// impact: the models' restitution-based dampings (Hunt-Crossley's
// 3 (1 - e) / (2 v), Lankarani-Nikravesh's, Flores') are first-order
// approximations of this map, exact only near e = 1; mbx solves it. e is
// clamped to [0.01, 1] (no finite damping stops a penalty contact dead).
// Throws mbx::Error for a non-finite or negative e, mass or speed.
double damping_for_restitution(NormalLaw law, double mass, double impact_speed, double e);

}  // namespace mbx::sim::contact
