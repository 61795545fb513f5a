// Contact in the simulator (sim/contact/contact_step.h) against closed
// forms, with a single free body over a ground half-space: a ball dropped
// with restitution e rebounds to e^2 of its height; a box resting on the
// plane sinks m g / (4 k) on its four corners and stays level; on an incline
// below atan(mu_s) the friction spring holds the box with zero creep, above
// it the box slides at g (sin - mu_k cos); a box on a gliding platform rides
// along, its friction anchor carried by the platform.
#include <doctest/doctest.h>

#include <cmath>

#include "contact_scenes.h"
#include "tests/export/export_fixture.h"
#include "sim/build_model.h"
#include "sim/contact/contact_step.h"
#include "sim/dynamics.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::sim::contact;

namespace {

constexpr double g = 9.81;

// A ground and one free part of `mass` with `inertia` at the origin.
struct FreeBody {
    std::unique_ptr<xtest::Translated> t;
    sim::Model model;
    explicit FreeBody(double mass, const Mat3& inertia) {
        t = xtest::translate(mbx_test::free_parts("free", {{mass, inertia, Vec3::Zero()}}));
        model = sim::build_model(*t->mechanism);
        REQUIRE(model.nv == 6);
        REQUIRE(model.joints[0].kind == sim::JointKind::Free);
    }
    int body() const { return 1; }
};

Shape ground(double tilt = 0) { return mbx_test::ground_plane(tilt); }

void set_pose(sim::Data& d, const Eigen::Vector3d& p, const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
    d.q.head<3>() = p;
    d.q[3] = q.w(), d.q[4] = q.x(), d.q[5] = q.y(), d.q[6] = q.z();
    d.v.setZero();
}

}  // namespace

TEST_CASE("contact: a ball dropped with restitution e rebounds to e^2 of its height, and gains no energy") {
    const double m = 1, r = 0.05, h0 = 0.5;
    FreeBody fb(m, (0.4 * m * r * r) * Mat3::Identity());
    Shape ball;
    ball.kind = ShapeKind::Sphere, ball.name = "ball", ball.body = fb.body(), ball.radius = r;
    for (double e : {0.0, 0.3, 0.8, 1.0}) {
        ContactSettings cs;
        cs.normal.model = NormalModel::HuntCrossley, cs.normal.stiffness = 1e9, cs.normal.exponent = 1.5;
        const double v_impact = std::sqrt(2 * g * h0);
        cs.normal.damping = damping_for_restitution(cs.normal, m, v_impact, e);
        cs.friction_spring = false;
        ContactWorld world(fb.model, {ground(), ball}, cs);
        sim::Data d(fb.model);
        set_pose(d, Eigen::Vector3d(0, 0, r + h0));
        sim::IntegratorSettings s;
        s.kind = sim::IntegratorKind::Euler, s.step = 1e-5;
        bool touched = false, left = false;
        double apex = 0, most_energy = 0;
        const double energy0 = m * g * h0;
        for (int k = 0; k < 60000; ++k) {
            world.step(fb.model, d, s);
            const double z = d.q[2] - r;
            // The ball's own energy (the contact spring's aside): never above the start's.
            most_energy = std::max(most_energy, 0.5 * m * d.v.head<3>().squaredNorm() + m * g * z);
            if (!world.forces().empty()) touched = true;
            if (touched && world.forces().empty() && z > 0) left = true;
            if (left) apex = std::max(apex, z);
            if (left && d.v[2] < 0) break;
        }
        MESSAGE("e = " << e << ": rebound to " << apex / h0 << " of the drop height (e^2 = " << e * e << ")");
        REQUIRE(touched);
        // Within 2 % of e^2 h0; e = 0: within 2 % of the drop height.
        CHECK(std::abs(apex / h0 - e * e) <= 0.02 * (e > 0 ? e * e : 1.0));
        CHECK(most_energy <= energy0 * (1 + 1e-3));
    }
}

TEST_CASE("contact: a box resting on the plane sinks m g / 4k and stays level") {
    const double m = 2, a = 0.1;
    FreeBody fb(m, (m * a * a / 6) * Mat3::Identity());
    const Shape box = mbx_test::box_shape(fb.body(), a);
    const ContactSettings cs = mbx_test::corner_contact(m);
    ContactWorld world(fb.model, {ground(), box}, cs);
    sim::Data d(fb.model);
    set_pose(d, Eigen::Vector3d(0, 0, a / 2 + 0.001));
    sim::IntegratorSettings s;
    s.kind = sim::IntegratorKind::Euler, s.step = 1e-4;
    for (int k = 0; k < 20000; ++k) world.step(fb.model, d, s);
    const double sink = a / 2 - d.q[2];
    CHECK(world.forces().size() == 4);
    CHECK(sink == mbx_test::relative(m * g / (4 * cs.normal.stiffness), 0.01));
    // Level and still: no rocking on a single deepest corner.
    CHECK(d.v.norm() < 1e-6);
    CHECK(std::abs(d.q[3]) == mbx_test::relative(1, 1e-9));
}

TEST_CASE("contact: on an incline the friction spring holds below atan(mu_s), above it the box slides at g (sin - mu_k cos)") {
    const double m = 1, a = 0.1;
    FreeBody fb(m, (m * a * a / 6) * Mat3::Identity());
    const Shape box = mbx_test::box_shape(fb.body(), a);
    const ContactSettings cs = mbx_test::corner_contact(m);
    for (double degrees : {25.0, 35.0}) {
        const double theta = degrees * M_PI / 180;
        ContactWorld world(fb.model, {ground(theta), box}, cs);
        sim::Data d(fb.model);
        // Resting on the incline (the plane's normal is its frame's z), just touching.
        const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()).toRotationMatrix();
        set_pose(d, R * Eigen::Vector3d(0, 0, a / 2 - m * g * std::cos(theta) / (4 * cs.normal.stiffness)),
                 Eigen::Quaterniond(R));
        sim::IntegratorSettings s;
        s.kind = sim::IntegratorKind::Euler, s.step = 1e-4;
        const Eigen::Vector3d down_slope = R * Eigen::Vector3d(1, 0, 0);  // x of the incline, downhill for +theta about y
        double x5 = 0;
        const int steps = degrees < 30 ? 100000 : 5000;
        for (int k = 0; k < steps; ++k) {
            world.step(fb.model, d, s);
            if (k == steps / 2) x5 = down_slope.dot(d.q.head<3>());
        }
        const double x = down_slope.dot(d.q.head<3>());
        if (degrees < 30) {
            MESSAGE("25 deg: moved " << (x - x5) << " m over the last 5 s");
            CHECK(std::abs(x - x5) < 1e-9);
        } else {
            const double v = down_slope.dot(d.v.head<3>());
            const double expected = g * (std::sin(theta) - cs.friction.mu_kinetic * std::cos(theta)) * steps * s.step;
            CHECK(std::abs(v) == mbx_test::relative(expected, 0.01));
        }
    }
}

TEST_CASE("contact: the regularised law lets the box creep down the 25 degree incline the friction spring holds") {
    const double m = 1, a = 0.1, theta = 25 * M_PI / 180;
    FreeBody fb(m, (m * a * a / 6) * Mat3::Identity());
    const Shape box = mbx_test::box_shape(fb.body(), a);
    ContactSettings cs = mbx_test::corner_contact(m);
    cs.friction_spring = false, cs.smoothing_speed = 1e-3;
    ContactWorld world(fb.model, {ground(theta), box}, cs);
    sim::Data d(fb.model);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()).toRotationMatrix();
    set_pose(d, R * Eigen::Vector3d(0, 0, a / 2 - m * g * std::cos(theta) / (4 * cs.normal.stiffness)), Eigen::Quaterniond(R));
    sim::IntegratorSettings s;
    s.kind = sim::IntegratorKind::Euler, s.step = 1e-4;
    const Eigen::Vector3d down_slope = R * Eigen::Vector3d(1, 0, 0);
    double x5 = 0;
    for (int k = 0; k < 100000; ++k) {
        world.step(fb.model, d, s);
        if (k == 50000) x5 = down_slope.dot(d.q.head<3>());
    }
    const double creep = (down_slope.dot(d.q.head<3>()) - x5) / 5;
    // Where mu_k N tanh(v / v_s) balances m g sin: v = v_s atanh(tan / mu_k).
    const double expected = cs.smoothing_speed * std::atanh(std::tan(theta) / cs.friction.mu_kinetic);
    MESSAGE("regularised Coulomb on 25 deg: creeps at " << creep * 1e3 << " mm/s (the friction spring: 0)");
    CHECK(creep == mbx_test::relative(expected, 0.02));
}

TEST_CASE("contact: a sliding ball starts rolling at t = 2 v0 / (7 mu g) with v = 5 v0 / 7, and energy never grows") {
    const double m = 1, r = 0.05, v0 = 2.0;
    FreeBody fb(m, (0.4 * m * r * r) * Mat3::Identity());
    Shape ball;
    ball.kind = ShapeKind::Sphere, ball.name = "ball", ball.body = fb.body(), ball.radius = r;
    ContactSettings cs;
    cs.normal.model = NormalModel::HuntCrossley, cs.normal.stiffness = 1e7, cs.normal.exponent = 1.5;
    cs.normal.damping = damping_for_restitution(cs.normal, m, 0.5, 0.3);
    cs.friction.mu_static = 0.3, cs.friction.mu_kinetic = 0.3, cs.friction.stiffness = 1e5;
    cs.friction.damping = 2 * std::sqrt(cs.friction.stiffness * m);
    ContactWorld world(fb.model, {ground(), ball}, cs);
    sim::Data d(fb.model);
    // Resting depth of the Hertz contact under m g, then launched sliding without spin.
    set_pose(d, Eigen::Vector3d(0, 0, r - std::pow(m * g / cs.normal.stiffness, 1 / 1.5)));
    d.v[0] = v0;
    sim::IntegratorSettings s;
    s.kind = sim::IntegratorKind::Euler, s.step = 1e-5;
    const double t_roll = 2 * v0 / (7 * cs.friction.mu_kinetic * g);
    double t_stuck = -1;
    for (int k = 0; k < int(1.5 * t_roll / s.step); ++k) {
        world.step(fb.model, d, s);
        // Slip speed of the contact point: v - w x r (free joint: body-frame angular velocity; the body stays unrotated about z here).
        const Eigen::Vector3d w = Eigen::Quaterniond(d.q[3], d.q[4], d.q[5], d.q[6]).toRotationMatrix() * d.v.tail<3>();
        const double slip = d.v[0] + w.cross(Eigen::Vector3d(0, 0, -r)).x();
        if (t_stuck < 0 && std::abs(slip) < 1e-3) t_stuck = (k + 1) * s.step;
    }
    MESSAGE("rolls from t = " << t_stuck << " s (2 v0 / 7 mu g = " << t_roll << " s) at " << d.v[0] << " m/s (5 v0 / 7 = " << 5 * v0 / 7 << ")");
    CHECK(t_stuck == mbx_test::relative(t_roll, 0.02));
    CHECK(d.v[0] == mbx_test::relative(5 * v0 / 7, 0.02));
}

TEST_CASE("contact: a box pushed just below mu_s m g stays, just above it slides at (F - mu_k m g) / m") {
    const double m = 1, a = 0.1;
    FreeBody fb(m, (m * a * a / 6) * Mat3::Identity());
    const Shape box = mbx_test::box_shape(fb.body(), a);
    const ContactSettings cs = mbx_test::corner_contact(m);
    for (double share : {0.95, 1.05}) {
        ContactWorld world(fb.model, {ground(), box}, cs);
        sim::Data d(fb.model);
        set_pose(d, Eigen::Vector3d(0, 0, a / 2 - m * g / (4 * cs.normal.stiffness)));
        sim::IntegratorSettings s;
        s.kind = sim::IntegratorKind::Euler, s.step = 1e-4;
        for (int k = 0; k < 5000; ++k) world.step(fb.model, d, s);  // settle
        // Push along x through the centre of mass, ramped up over 1 s (a
        // quasi-static load: a sudden one rings the friction springs), then held.
        const double F = share * cs.friction.mu_static * m * g;
        const double x0 = d.q[0];
        double x_held = 0, v_held = 0;
        d.effort.setZero();
        for (int k = 0; k < 20000; ++k) {
            d.effort[0] = F * std::min(1.0, (k + 1) * s.step / 1.0);
            world.step(fb.model, d, s);
            if (k == 15000) x_held = d.q[0], v_held = d.v[0];
        }
        if (share < 1) {
            MESSAGE("held at 95 % of mu_s m g: moved " << d.q[0] - x_held << " m in the last 0.5 s, " << d.q[0] - x0
                                                     << " m in all (the springs' stretch)");
            CHECK(std::abs(d.q[0] - x_held) < 1e-9);
            CHECK(d.q[0] - x0 < 1e-3);
        } else {
            const double accel = (d.v[0] - v_held) / 0.5;
            CHECK(accel == mbx_test::relative((F - cs.friction.mu_kinetic * m * g) / m, 0.02));
        }
    }
}

TEST_CASE("contact: a box on a moving platform rides along, its friction spring anchored on the platform") {
    // A 50 kg platform gliding at 0.5 m/s on four frictionless feet, its top
    // a half-space on the platform's body; a 1 kg box resting on that top
    // at the same speed. Nothing pulls the box sideways, so it must stay
    // where it sits on the platform. An anchor left at a world point would
    // stretch at 0.5 m/s, break loose within a millisecond and drag the box
    // back off the platform.
    const double m_platform = 50, m_box = 1, a = 0.1, half = 0.5, thick = 0.1, foot = 0.02;
    const double z_platform = foot + thick / 2, z_box = z_platform + thick / 2 + a / 2;
    const Mat3 platform_inertia =
        (m_platform / 12) * Eigen::Vector3d(4 * half * half + thick * thick, 4 * half * half + thick * thick,
                                            8 * half * half).asDiagonal();
    auto t = xtest::translate(mbx_test::free_parts(
        "platform", {{m_platform, platform_inertia, Vec3(0, 0, z_platform)},
                     {m_box, (m_box * a * a / 6) * Mat3::Identity(), Vec3(0, 0, z_box)}}));
    const sim::Model model = sim::build_model(*t->mechanism);
    REQUIRE(model.nv == 12);
    std::vector<Shape> shapes = {ground()};
    for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0}) {
            Shape f;
            f.kind = ShapeKind::Sphere, f.name = "foot", f.body = 1, f.radius = foot, f.material = 1;
            f.position = Eigen::Vector3d(sx * 0.8 * half, sy * 0.8 * half, -thick / 2);
            shapes.push_back(f);
        }
    Shape top;
    top.kind = ShapeKind::HalfSpace, top.name = "top", top.body = 1, top.material = 1;
    top.position = Eigen::Vector3d(0, 0, thick / 2);
    shapes.push_back(top);
    Shape box = mbx_test::box_shape(2, a);
    box.material = 2;
    shapes.push_back(box);
    ContactSettings feet = mbx_test::corner_contact(m_platform, 1e6);
    feet.friction_spring = false, feet.friction.mu_static = feet.friction.mu_kinetic = 0;
    const ContactSettings grip = mbx_test::corner_contact(m_box);
    ContactWorld world(model, shapes, grip, {{0, 1, feet}, {1, 2, grip}});
    sim::Data d(model);
    // Free joints: position, quaternion (w x y z); velocities linear then angular.
    d.q.setZero();
    d.q.segment<3>(0) = Eigen::Vector3d(0, 0, z_platform - m_platform * g / (4 * 1e6));
    d.q[3] = 1;
    d.q.segment<3>(7) = Eigen::Vector3d(0, 0, z_box - m_platform * g / (4 * 1e6) - m_box * g / (4 * 1e5));
    d.q[10] = 1;
    d.v.setZero();
    d.v[0] = d.v[6] = 0.5;
    sim::IntegratorSettings s;
    s.kind = sim::IntegratorKind::Euler, s.step = 1e-4;
    const double offset0 = d.q[7] - d.q[0];
    double largest_offset_change = 0;
    bool sticking = true;
    for (int k = 0; k < 20000; ++k) {
        world.step(model, d, s);
        largest_offset_change = std::max(largest_offset_change, std::abs(d.q[7] - d.q[0] - offset0));
        if (k > 1000)
            for (const ContactForce& f : world.forces())
                if (f.contact.shape_b == int(shapes.size()) - 1) sticking = sticking && f.sticking;
    }
    MESSAGE("the platform travelled " << d.q[0] << " m; the box moved " << largest_offset_change
                                      << " m at most on it");
    CHECK(d.q[0] > 0.95);  // the platform glided on (frictionless feet)
    CHECK(largest_offset_change < 1e-4);
    CHECK(sticking);
}

TEST_CASE("contact: the same drop under RK4 and the accurate mode, whose steps see the contact force at every stage") {
    const double m = 1, r = 0.05, h0 = 0.5, e = 0.3;
    FreeBody fb(m, (0.4 * m * r * r) * Mat3::Identity());
    Shape ball;
    ball.kind = ShapeKind::Sphere, ball.name = "ball", ball.body = fb.body(), ball.radius = r;
    ContactSettings cs;
    cs.normal.model = NormalModel::HuntCrossley, cs.normal.stiffness = 1e9, cs.normal.exponent = 1.5;
    cs.normal.damping = damping_for_restitution(cs.normal, m, std::sqrt(2 * g * h0), e);
    for (sim::IntegratorKind kind : {sim::IntegratorKind::RK4, sim::IntegratorKind::Accurate}) {
        ContactWorld world(fb.model, {ground(), ball}, cs);
        sim::Data d(fb.model);
        set_pose(d, Eigen::Vector3d(0, 0, r + h0));
        d.applied_forces = &world;
        sim::IntegratorSettings s;
        s.kind = kind;
        s.step = kind == sim::IntegratorKind::RK4 ? 2e-5 : 1e-3;
        s.tolerance = 1e-9;
        // Sampled every 0.1 ms: the apex after the bounce.
        double apex = 0;
        bool bounced = false;
        for (int k = 1; k <= 6000; ++k) {
            sim::advance(fb.model, d, s, k * 1e-4);
            if (d.v[2] > 0) bounced = true;
            if (bounced) apex = std::max(apex, d.q[2] - r);
            if (bounced && d.v[2] < 0) break;
        }
        MESSAGE(std::string(sim::integrator_name(kind)) << ": rebound to " << apex / h0 << " of the drop height (e^2 = " << e * e << "), "
                                           << d.stats.steps << " steps");
        CHECK(apex / h0 == mbx_test::relative(e * e, 0.02));
    }
}
}  // namespace MBX_UNITY_ID
