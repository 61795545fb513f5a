// What the contact tests and bench_contact build alike: free bodies over a
// ground (an assembly of free parts, translated by mbx's own pipeline), the
// ground half-space, a box shape, and the per-corner box contact the tests
// use (linear springs on the four corners sized on a quarter of the mass).
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "apps/stub_host/assemblies/builder.h"
#include "sim/contact/contact_step.h"

namespace mbx_test {

struct FreePart {
    double mass;
    mbx::Mat3 inertia;  // about the centre, which is the part's origin
    mbx::Vec3 position;
};

// A ground part and the given free parts (no constraints: each becomes a
// floating body with a free joint).
inline mbx_memory::Assembly free_parts(const std::string& name, const std::vector<FreePart>& parts) {
    using namespace mbx_stub::build;
    mbx_memory::Assembly a;
    a.name = name;
    const mbx_units si{1, 1, 1};
    Builder b(a, name, si, si);
    b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, Mat3::Identity(), Vec3::Zero(), Vec3::Zero(), Mat3::Identity());
    for (size_t k = 0; k < parts.size(); ++k)
        b.body("part" + std::to_string(k), "Part", 0, parts[k].mass, Mat3::Identity(), parts[k].position,
               parts[k].position, parts[k].inertia);
    return a;
}

// The ground: the half-space z <= 0 of a frame turned by `tilt` about y.
inline mbx::sim::contact::Shape ground_plane(double tilt = 0) {
    mbx::sim::contact::Shape s;
    s.kind = mbx::sim::contact::ShapeKind::HalfSpace, s.name = "ground", s.body = 0;
    s.rotation = Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()).toRotationMatrix();
    return s;
}

inline mbx::sim::contact::Shape box_shape(int body, double side) {
    mbx::sim::contact::Shape s;
    s.kind = mbx::sim::contact::ShapeKind::Box, s.name = "box", s.body = body, s.size = Eigen::Vector3d(side, side, side);
    return s;
}

// Linear springs per corner (normal k, friction spring k_t), dampers at
// `damping_ratio` of critical for a quarter of the mass on each corner.
inline mbx::sim::contact::ContactSettings corner_contact(double mass, double k = 1e5, double k_t = 2e4,
                                                          double damping_ratio = 1.0) {
    mbx::sim::contact::ContactSettings cs;
    cs.normal.model = mbx::sim::contact::NormalModel::SpringDamper, cs.normal.stiffness = k, cs.normal.exponent = 1;
    cs.normal.damping = damping_ratio * 2 * std::sqrt(k * mass / 4);
    cs.friction.mu_static = 0.6, cs.friction.mu_kinetic = 0.5, cs.friction.stiffness = k_t;
    cs.friction.damping = damping_ratio * 2 * std::sqrt(k_t * mass / 4);
    return cs;
}

}  // namespace mbx_test
