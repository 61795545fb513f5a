#include "core/mobility/twist.h"

#include <algorithm>
#include <cmath>

namespace mbx::mobility {

TwistColumns joint_twists(const Joint& joint, const LoopFrame& frame, double prismatic_length) {
    const double sign = joint.reversed ? -1.0 : 1.0;
    const Vec3 arm = (joint.frame.position - frame.reference) / frame.length;
    TwistColumns s(6, joint.freedoms());
    switch (joint.type) {
        case MBX_PRIMITIVE_REVOLUTE:
            s.col(0) << sign * joint.axis, sign * arm.cross(joint.axis);
            break;
        case MBX_PRIMITIVE_PRISMATIC:
            s.col(0) << Vec3::Zero(), (sign * prismatic_length / frame.length) * joint.axis;
            break;
        case MBX_PRIMITIVE_SPHERICAL:
            for (int k = 0; k < 3; ++k) {
                Vec3 w = Vec3::Unit(k);
                s.col(k) << sign * w, sign * arm.cross(w);
            }
            break;
        case MBX_PRIMITIVE_WELD:
            break;
    }
    return s;
}

LoopFrame loop_frame(const Mechanism& mech, const Loop& loop, double min_length) {
    LoopFrame frame;
    if (loop.joints.empty()) return frame;
    Vec3 sum = Vec3::Zero();
    for (int j : loop.joints) sum += mech.joints[j].frame.position;
    frame.reference = sum / static_cast<double>(loop.joints.size());
    double reach = 0;
    for (int j : loop.joints) reach = std::max(reach, (mech.joints[j].frame.position - frame.reference).norm());
    frame.length = std::max(reach, min_length);
    return frame;
}

Eigen::MatrixXd loop_jacobian(const Mechanism& mech, const Loop& loop, const LoopFrame& frame,
                              const std::vector<double>* prismatic_length) {
    int columns = 0;
    for (int j : loop.joints) columns += mech.joints[j].freedoms();
    Eigen::MatrixXd jac(6, columns);
    int at = 0;
    for (size_t k = 0; k < loop.joints.size(); ++k) {
        const int j = loop.joints[k];
        const Joint& joint = mech.joints[j];
        const int f = joint.freedoms();
        const double unit = prismatic_length ? (*prismatic_length)[j] : frame.length;
        jac.middleCols(at, f) = loop.signs[k] * joint_twists(joint, frame, unit);
        at += f;
    }
    return jac;
}

Planarity loop_planarity(const Mechanism& mech, const Loop& loop, double angle_tolerance) {
    // The first revolute fixes the candidate normal; the mean of the
    // sign-aligned revolute axes then refines it for the prismatic test.
    const Vec3* first = nullptr;
    Vec3 sum = Vec3::Zero();
    int revolutes = 0;
    for (int j : loop.joints) {
        const Joint& joint = mech.joints[j];
        if (joint.type == MBX_PRIMITIVE_SPHERICAL) return {};
        if (joint.type != MBX_PRIMITIVE_REVOLUTE) continue;
        if (!first) first = &joint.axis;
        if (joint.axis.cross(*first).norm() > angle_tolerance) return {};
        sum += joint.axis.dot(*first) < 0 ? Vec3(-joint.axis) : joint.axis;
        ++revolutes;
    }
    if (revolutes < 2) return {};
    Vec3 n = sum.normalized();
    for (int j : loop.joints) {
        const Joint& joint = mech.joints[j];
        if (joint.type == MBX_PRIMITIVE_PRISMATIC && std::abs(joint.axis.dot(n)) > angle_tolerance) return {};
    }
    for (int k = 0; k < 3; ++k) {
        if (std::abs(n[k]) > angle_tolerance) {
            if (n[k] < 0) n = -n;
            break;
        }
    }
    return {true, n};
}

}  // namespace mbx::mobility
