// Findings about the data itself: mass properties a real body cannot have,
// massless dynamic bodies, and joints whose two frames are not at one place.
#include <cstdio>

#include "core/text_format.h"
#include "core/translator/mass_properties.h"
#include "core/translator/translate.h"

namespace mbx {
namespace {

void check_parts(Mechanism& m) {
    for (const Part& p : m.assembly.parts) {
        Subject s = Subject::body(p.id, p.name);
        if (p.mass < 0) {
            m.add(MBX_SEVERITY_ERROR, MBX_FINDING_NEGATIVE_MASS, s,
                  "part '" + p.name + "' has negative mass " + formatted("%g kg", p.mass) +
                      "; it is left out of its rigid body's mass properties");
            continue;
        }
        if (p.is_helper() || p.is_ground() || p.mass == 0) continue;
        Vec3 l;
        switch (check_inertia(p.inertia, l)) {
            case InertiaIssue::none: break;
            case InertiaIssue::semi_definite:
                m.add(MBX_SEVERITY_WARNING, MBX_FINDING_INERTIA_NOT_POSITIVE_DEFINITE, s,
                      "inertia of part '" + p.name + "' is only positive semi-definite (principal moments " +
                          formatted("%.6g, %.6g, %.6g kg m^2", l[0], l[1], l[2]) + ")");
                break;
            case InertiaIssue::not_positive_definite:
                m.add(MBX_SEVERITY_ERROR, MBX_FINDING_INERTIA_NOT_POSITIVE_DEFINITE, s,
                      "inertia of part '" + p.name + "' is not positive definite (principal moments " +
                          formatted("%.6g, %.6g, %.6g kg m^2", l[0], l[1], l[2]) +
                          "); CAD exports of mirrored parts often look like this");
                break;
            case InertiaIssue::triangle_inequality:
                m.add(MBX_SEVERITY_ERROR, MBX_FINDING_INERTIA_TRIANGLE_INEQUALITY, s,
                      "inertia of part '" + p.name + "' breaks the triangle inequality (principal moments " +
                          formatted("%.6g, %.6g, %.6g kg m^2", l[0], l[1], l[2]) + ": the two smaller sum to less than the largest)");
                break;
        }
    }
}

void check_bodies(Mechanism& m) {
    for (const RigidBody& b : m.bodies) {
        if (b.kind != MBX_RIGID_BODY_DYNAMIC || b.mass > 0) continue;
        m.add(MBX_SEVERITY_ERROR, MBX_FINDING_ZERO_MASS_BODY, Subject::rigid_body(b.id, b.name),
              "rigid body '" + b.name + "' (" + std::to_string(b.parts.size()) +
                  " part(s)) has no mass; a simulator cannot move it");
    }
}

// Base and follower frames of a joint are one point seen from two bodies.
// Offsets along a prismatic axis are a legal initial slide, not an error.
void check_joint_frames(Mechanism& m) {
    const Assembly& a = m.assembly;
    std::vector<char> has_cut(a.constraints.size(), 0);
    for (const Joint& j : m.joints)
        if (j.cut) has_cut[size_t(j.constraint)] = 1;
    for (size_t ci = 0; ci < a.constraints.size(); ++ci) {
        const Constraint& c = a.constraints[ci];
        if (c.is_weld()) continue;
        Vec3 d = a.frames[size_t(c.follower_frame)].world.position - a.frames[size_t(c.base_frame)].world.position;
        for (const Primitive& p : c.chain)
            if (p.type == MBX_PRIMITIVE_PRISMATIC) d -= p.axis * p.axis.dot(d);
        const double gap = d.norm();
        if (gap <= m.length_tolerance) continue;
        const bool cut = has_cut[ci];
        m.add(cut ? MBX_SEVERITY_ERROR : MBX_SEVERITY_WARNING, MBX_FINDING_JOINT_FRAMES_APART,
              Subject::constraint(c.id, c.name),
              "frames '" + a.frames[size_t(c.base_frame)].name + "' and '" + a.frames[size_t(c.follower_frame)].name +
                  "' of joint '" + c.name + "' are " + formatted("%.6g mm", gap * 1e3) +
                  " apart at the assembly pose (tolerance " + formatted("%.3g mm", m.length_tolerance * 1e3) + ")" +
                  (cut ? "; the loop this joint closes cannot close" : "; the joint is placed at the base frame"));
    }
}

}  // namespace

void validate(Mechanism& m, Progress& progress) {
    progress.stage("validate", 0);
    check_parts(m);
    check_bodies(m);
    check_joint_frames(m);
    progress.finish();
}

}  // namespace mbx
