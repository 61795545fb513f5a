#include "stub_geometry.h"

#include <doctest/doctest.h>

namespace itest {

double length_si(const mbx_units& u) { return u.length_to_m != 0 ? u.length_to_m : 1.0; }
double mass_si(const mbx_units& u) { return u.mass_to_kg != 0 ? u.mass_to_kg : 1.0; }
double inertia_si(const mbx_units& u) {
    return u.inertia_to_kg_m2 != 0 ? u.inertia_to_kg_m2 : mass_si(u) * length_si(u) * length_si(u);
}

Mat3 rotation(const double m[9]) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = m[3 * i + j];
    return r;
}

Vec3 vec(const double v[3]) { return Vec3(v[0], v[1], v[2]); }

WorldPose world(const mbx_pose& pose, double length_factor) {
    return {rotation(pose.rotation), vec(pose.position) * length_factor};
}

const mbx_stub::Body& body_by_id(const mbx_stub::Assembly& a, const std::string& id) {
    for (const auto& b : a.bodies)
        if (b.id == id) return b;
    FAIL("no body " << id);
    throw 0;
}

const mbx_stub::Frame& frame_by_id(const mbx_stub::Assembly& a, const std::string& id) {
    for (const auto& f : a.frames)
        if (f.id == id) return f;
    FAIL("no frame " << id);
    throw 0;
}

const mbx_stub::Constraint& constraint_by_id(const mbx_stub::Assembly& a, const std::string& id) {
    for (const auto& c : a.constraints)
        if (c.id == id) return c;
    FAIL("no constraint " << id);
    throw 0;
}

WorldPose body_world(const mbx_stub::Body& b) { return world(b.pose, length_si(b.units)); }

WorldPose frame_world(const mbx_stub::Assembly& a, const mbx_stub::Frame& f) {
    const WorldPose local = world(f.pose, length_si(f.units));
    if (f.reference == MBX_FRAME_IN_WORLD) return local;
    const WorldPose body = body_world(body_by_id(a, f.body_id));
    return {body.R * local.R, body.apply(local.p)};
}

Vec3 axis_world(const mbx_stub::Assembly& a, const mbx_stub::Constraint& c, const mbx_stub::Primitive& p) {
    Vec3 axis = vec(p.axis);
    if (p.axis_reference == MBX_AXIS_IN_BASE_FRAME) axis = frame_world(a, frame_by_id(a, c.base_frame_id)).R * axis;
    return axis.normalized();
}

MassWorld mass_world(const mbx_stub::Body& b) {
    const WorldPose pose = body_world(b);
    MassWorld m;
    m.mass = b.mass * mass_si(b.units);
    m.com = pose.apply(vec(b.com) * length_si(b.units));
    m.inertia = pose.R * (rotation(b.inertia) * inertia_si(b.units)) * pose.R.transpose();
    return m;
}

MassWorld combine(const std::vector<MassWorld>& parts) {
    MassWorld total;
    for (const MassWorld& p : parts) {
        total.mass += p.mass;
        total.com += p.mass * p.com;
    }
    total.com /= total.mass;
    for (const MassWorld& p : parts) {
        const Vec3 d = p.com - total.com;
        total.inertia += p.inertia + p.mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
    }
    return total;
}

}  // namespace itest
