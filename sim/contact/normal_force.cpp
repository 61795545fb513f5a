#include "sim/contact/normal_force.h"

#include <algorithm>
#include <string>

#include "core/finding.h"
#include "core/text_format.h"

namespace mbx::sim::contact {

double restitution(const NormalLaw& law, double mass, double v) {
    // Scales of the undamped impact: its deepest penetration and the time to cover it at v.
    const double n = law.exponent;
    const double depth_scale = std::pow((n + 1) * mass * v * v / (2 * law.stiffness), 1 / (n + 1));
    const double h = depth_scale / v / 2000;
    double d = 0, r = v;  // penetration and its rate
    auto accel = [&](double dd, double rr) { return -normal_force(law, dd, rr) / mass; };
    for (int step = 0; step < 1000000; ++step) {
        // RK4 on (d, r); the force is continuous across zero depth from inside.
        const double k1d = r, k1r = accel(d, r);
        const double k2d = r + 0.5 * h * k1r, k2r = accel(d + 0.5 * h * k1d, r + 0.5 * h * k1r);
        const double k3d = r + 0.5 * h * k2r, k3r = accel(d + 0.5 * h * k2d, r + 0.5 * h * k2r);
        const double k4d = r + h * k3r, k4r = accel(d + h * k3d, r + h * k3r);
        d += h / 6 * (k1d + 2 * k2d + 2 * k3d + k4d);
        r += h / 6 * (k1r + 2 * k2r + 2 * k3r + k4r);
        // Apart, or on the way out with the force gone (from then on no force acts).
        if (d <= 0 || (r < 0 && normal_force(law, d, r) <= 0)) return std::max(0.0, -r) / v;
    }
    return 0;  // still in contact: as good as no rebound
}

double damping_for_restitution(NormalLaw law, double mass, double v, double e) {
    if (!(std::isfinite(e) && e >= 0) || !(std::isfinite(mass) && mass > 0) || !(std::isfinite(v) && v > 0) ||
        !(law.stiffness > 0) || !(law.exponent >= 1))
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("contact"),
                    "restitution " + std::to_string(e) + " for mass " + std::to_string(mass) + " at " +
                        readable(v) + " m/s: every value must be a non-negative number (mass and speed positive)");
    if (law.model == NormalModel::Spring) return 0;
    e = std::clamp(e, 0.01, 1.0);
    law.damping = 0;
    if (e >= 1) return 0;
    // Restitution falls monotonically with the damping: bracket, then bisect in log.
    double lo = 0, hi = law.model == NormalModel::HuntCrossley ? 1 / v : 2 * std::sqrt(law.stiffness * mass);
    law.damping = hi;
    while (restitution(law, mass, v) > e) {
        lo = hi, hi *= 4;
        law.damping = hi;
    }
    for (int i = 0; i < 60 && hi - lo > 1e-12 * hi; ++i) {
        const double mid = lo > 0 ? std::sqrt(lo * hi) : 0.5 * hi;
        law.damping = mid;
        (restitution(law, mass, v) > e ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace mbx::sim::contact
