// Normal force laws (sim/contact/normal_force.h): never pulling, the
// restitution of the undamped laws is 1, Hunt-Crossley's small-damping
// restitution is 1 - (2/3) chi v (their 1975 result) and depends on chi v
// only, the linear spring-damper without the no-pull cut is Kelvin-Voigt's
// exp(-zeta pi / sqrt(1 - zeta^2)) (the cut only raises it), and the damping
// solved for a restitution gives that restitution back.
#include <doctest/doctest.h>

#include <cmath>

#include "core/finding.h"
#include "sim/contact/normal_force.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx::sim::contact;

TEST_CASE("contact normal force: laws, restitution and the damping for a restitution") {
    NormalLaw hc;
    hc.model = NormalModel::HuntCrossley, hc.stiffness = 2e5, hc.exponent = 1.5, hc.damping = 0.5;
    CHECK(normal_force(hc, -0.001, 1.0) == 0);
    CHECK(normal_force(hc, 0.001, 0.0) == mbx_test::relative(2e5 * std::pow(0.001, 1.5), 1e-6));
    CHECK(normal_force(hc, 0.001, -10.0) == 0);  // leaving fast: the law would pull, the force does not

    NormalLaw spring = hc;
    spring.model = NormalModel::Spring;
    CHECK(restitution(spring, 0.37, 2.0) == mbx_test::relative(1, 1e-6));

    // Hunt-Crossley: e ~ 1 - (2/3) chi v for small chi v, and a function of chi v alone.
    hc.damping = 0.005;
    CHECK(restitution(hc, 1.0, 2.0) == mbx_test::relative(1 - 2.0 / 3 * 0.01, 2e-4));
    hc.damping = 0.2;
    const double e1 = restitution(hc, 1.0, 2.0);
    NormalLaw other = hc;
    other.damping = 0.4, other.stiffness = 7e6;
    CHECK(restitution(other, 3.0, 1.0) == mbx_test::relative(e1, 1e-4));

    // The linear spring-damper with a light damping: Kelvin-Voigt's restitution,
    // the cut of the pulling force raising it only a little.
    NormalLaw kv;
    kv.model = NormalModel::SpringDamper, kv.stiffness = 1e5, kv.exponent = 1;
    const double mass = 0.5, zeta = 0.05;
    kv.damping = 2 * zeta * std::sqrt(kv.stiffness * mass);
    const double analytic = std::exp(-zeta * M_PI / std::sqrt(1 - zeta * zeta));
    const double e_kv = restitution(kv, mass, 1.5);
    CHECK(e_kv >= analytic - 1e-6);
    CHECK(e_kv == mbx_test::relative(analytic, 0.02));

    // Solved damping gives its restitution back, for both models, over the range.
    for (double e : {0.3, 0.5, 0.8, 0.95}) {
        for (NormalLaw law : {hc, kv}) {
            law.damping = damping_for_restitution(law, 0.37, 1.7, e);
            CHECK(law.damping > 0);
            CHECK(restitution(law, 0.37, 1.7) == mbx_test::relative(e, 1e-4));
        }
    }
    // e = 0: as good as no rebound.
    hc.damping = damping_for_restitution(hc, 0.37, 1.7, 0);
    CHECK(restitution(hc, 0.37, 1.7) <= 0.0101);
    CHECK_THROWS_AS(damping_for_restitution(hc, 0.37, 1.7, NAN), mbx::Error);
    CHECK_THROWS_AS(damping_for_restitution(hc, -1, 1.7, 0.5), mbx::Error);
}
}  // namespace MBX_UNITY_ID
