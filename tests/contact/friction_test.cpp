// Tangential contact laws (sim/contact/friction.h) on a block on a flat
// plane, pushed sideways by a constant force and integrated in one
// dimension: below mu_s N the friction spring holds it with zero creep (only
// the spring's static stretch F/k), while the regularised law lets it creep
// at exactly the speed where mu_k N tanh(v/v_s) = F; above mu_s N it slides
// at (F - mu_k N)/m; a contact that loses its load forgets its anchor.
#include <doctest/doctest.h>

#include <cmath>

#include "sim/contact/friction.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx::sim::contact;

namespace {

struct Run {
    double x = 0, v = 0;
    double x_at_5 = 0;
};

// Semi-implicit Euler, 0.1 ms steps, 10 s; the block's contact point is its position.
Run push(const FrictionLaw& law, double mass, double force, bool spring, double smoothing = 1e-3) {
    const double g = 9.81, n = mass * g, h = 1e-4;
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    FrictionState state;
    Run r;
    for (int k = 0; k < 100000; ++k) {
        const Eigen::Vector3d point(r.x, 0, 0), vt(r.v, 0, 0);
        FrictionState next;
        const Eigen::Vector3d f = spring ? spring_friction(law, state, point, up, vt, n, next)
                                         : regularised_friction(law, n, vt, smoothing);
        r.v += h * (force + f.x()) / mass;
        r.x += h * r.v;
        state = next;
        if (k == 50000) r.x_at_5 = r.x;
    }
    return r;
}

}  // namespace

TEST_CASE("contact friction: the friction spring holds below mu_s N, the regularised law creeps") {
    FrictionLaw law;
    law.mu_static = 0.6, law.mu_kinetic = 0.5, law.stiffness = 2e4;
    const double m = 0.37, n = m * 9.81;
    law.damping = 2 * std::sqrt(law.stiffness * m);  // critically damped while sticking
    // 90 % of the static limit.
    const double f_hold = 0.9 * law.mu_static * n;
    const Run held = push(law, m, f_hold, true);
    CHECK(std::abs(held.x - held.x_at_5) < 1e-12);             // no creep over the last 5 s
    CHECK(held.x == mbx_test::relative(f_hold / law.stiffness, 1e-6));  // the spring's stretch only
    // The regularised law under 90 % of its kinetic level creeps at v_s atanh(0.9).
    const double vs = 1e-3, f_creep = 0.9 * law.mu_kinetic * n;
    const Run crept = push(law, m, f_creep, false, vs);
    const double speed = (crept.x - crept.x_at_5) / 5;
    MESSAGE("regularised Coulomb creep under 90 % of mu_k N: " << speed * 1e3 << " mm/s");
    CHECK(speed == mbx_test::relative(vs * std::atanh(0.9), 1e-3));

    // Above the static limit: slides with kinetic friction.
    const double f_slide = 1.1 * law.mu_static * n;
    const Run slid = push(law, m, f_slide, true);
    const double a = (f_slide - law.mu_kinetic * n) / m;
    CHECK(slid.v == mbx_test::relative(a * 10, 0.01));

    // Losing the load resets the contact; touching again anchors it anew.
    FrictionState s, next;
    spring_friction(law, s, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), n, next);
    CHECK(next.active);
    CHECK(next.sticking);
    FrictionState lifted;
    CHECK(spring_friction(law, next, Eigen::Vector3d(0.1, 0, 0), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), 0, lifted).norm() == 0);
    CHECK(!lifted.active);
    const Eigen::Vector3d f = spring_friction(law, lifted, Eigen::Vector3d(0.2, 0, 0), Eigen::Vector3d::UnitZ(),
                                              Eigen::Vector3d::Zero(), n, next);
    CHECK(f.norm() == 0);  // anchored where it touched again: no stretch
    CHECK((next.anchor - Eigen::Vector3d(0.2, 0, 0)).norm() == 0);
}
}  // namespace MBX_UNITY_ID
