#include <charconv>
#include <cmath>

#include "core/mechatronics/drive.h"
#include "core/mechatronics/joint_lookup.h"
#include "core/translator/mechanism.h"

namespace mbx {

std::vector<std::pair<const char*, double>> joint_dynamics_coefficients(const JointDynamicsSpec& s) {
    std::vector<std::pair<const char*, double>> out = {
        {"damping", s.damping},     {"coulomb", s.coulomb},   {"coulomb_velocity", s.coulomb_velocity},
        {"stiffness", s.stiffness}, {"armature", s.armature}, {"stribeck", s.stribeck},
        {"stribeck_velocity", s.stribeck_velocity}};
    if (s.coulomb_negative) out.emplace_back("coulomb_negative", *s.coulomb_negative);
    if (s.damping_negative) out.emplace_back("damping_negative", *s.damping_negative);
    return out;
}

std::vector<std::string> joint_dynamics_problems(const JointDynamicsSpec& s) {
    std::vector<std::string> out;
    if (!std::isfinite(s.offset)) out.push_back("offset must be finite");
    // exp(-(qd/0)^2) is a peak of zero width: a static friction the sliding
    // law never shows, which only the accurate mode would see.
    if (s.stribeck > 0 && !(s.stribeck_velocity > 0))
        out.push_back("stribeck needs a positive stribeck_velocity (the speed over which the peak decays)");
    if (const auto& t = s.transmission) {
        const std::pair<const char*, double> values[] = {{"stiffness", t->stiffness}, {"damping", t->damping},
                                                         {"motor_inertia", t->motor_inertia}, {"backlash", t->backlash}};
        bool finite = true;
        for (const auto& [name, value] : values)
            if (!std::isfinite(value) || value < 0) {
                out.push_back(std::string("transmission ") + name + " must be finite and not negative");
                finite = false;
            }
        if (finite && !(t->motor_inertia > 0))
            out.push_back("transmission motor_inertia must be positive (the motor side needs an inertia of its own)");
        if (finite && !(t->stiffness > 0) && !(t->backlash > 0))
            out.push_back("transmission needs a positive stiffness, or a backlash (a dead band between stops)");
    }
    return out;
}

namespace {
std::string shortest(double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, r.ptr);
}
}  // namespace

std::string joint_dynamics_beyond_symmetric(const ResolvedJointDynamics& r) {
    const std::string effort = r.linear ? " N" : " N m", speed = r.linear ? " m/s" : " rad/s";
    const std::string rate = r.linear ? " N s/m" : " N m s/rad";
    std::vector<std::string> parts;
    if (r.offset != 0) parts.push_back("the effort offset " + shortest(r.offset) + effort);
    if (r.coulomb_negative != r.coulomb)
        parts.push_back("the direction-dependent Coulomb friction " + shortest(r.coulomb) + " (q' > 0) / " +
                        shortest(r.coulomb_negative) + " (q' < 0)" + effort + ", written as their mean " +
                        shortest(r.symmetric_coulomb()));
    if (r.damping_negative != r.damping)
        parts.push_back("the direction-dependent damping " + shortest(r.damping) + " (q' > 0) / " +
                        shortest(r.damping_negative) + " (q' < 0)" + rate + ", written as their mean " +
                        shortest(r.symmetric_damping()));
    if (r.stribeck > 0)
        parts.push_back("the Stribeck peak " + shortest(r.stribeck) + effort + " over " + shortest(r.stribeck_velocity) +
                        speed + " (the static friction is written at the sliding level)");
    std::string out;
    for (size_t k = 0; k < parts.size(); ++k)
        out += (k == 0 ? "" : k + 1 == parts.size() ? " and " : ", ") + parts[k];
    return out;
}

std::vector<ResolvedJointDynamics> resolve_joint_dynamics(const MechatronicSpec& spec, const Mechanism& m,
                                                          std::vector<DriveError>& errors) {
    std::vector<ResolvedJointDynamics> out;
    if (spec.joint_dynamics.empty()) return out;
    out.reserve(spec.joint_dynamics.size());
    const JointIndex joints_of = index_joints_by_constraint(m);
    std::vector<int> given(m.joints.size(), -1);  // joint -> spec index that claimed it
    for (size_t index = 0; index < spec.joint_dynamics.size(); ++index) {
        const JointDynamicsSpec& s = spec.joint_dynamics[index];
        const std::string who = s.joint.constraint_id;
        auto error = [&](std::string message) { errors.push_back({s.file, s.line, who, std::move(message)}); };

        std::string why;
        const int j = find_joint(s.joint, joints_of, m, why);
        if (j < 0) {
            error(why);
            continue;
        }
        const Joint& joint = m.joints[size_t(j)];
        if (joint.type != MBX_PRIMITIVE_REVOLUTE && joint.type != MBX_PRIMITIVE_PRISMATIC) {
            error("joint '" + joint.name + "' is " + (joint.type == MBX_PRIMITIVE_SPHERICAL ? "spherical" : "a weld") +
                  ": joint dynamics act on one coordinate, so only prismatic and revolute joints take them");
            continue;
        }
        if (joint.cut) {
            // The simulator closes a cut joint as constraint rows without a
            // coordinate, and MJCF and URDF have no joint there at all.
            error("joint '" + joint.name +
                  "' closes a loop (cut joint) and has no coordinate: give the joint dynamics to a tree joint of the "
                  "loop instead");
            continue;
        }
        if (given[size_t(j)] >= 0) {
            const JointDynamicsSpec& first = spec.joint_dynamics[size_t(given[size_t(j)])];
            error("joint '" + joint.name + "' is given joint dynamics twice" +
                  (first.line > 0 ? " (the first at line " + std::to_string(first.line) + ")" : std::string()));
            continue;
        }
        const bool linear = joint.type == MBX_PRIMITIVE_PRISMATIC;
        const bool angle_unit = s.unit == "rad" || s.unit == "deg";
        const bool length_unit = s.unit == "m" || s.unit == "mm";
        if ((linear && angle_unit) || (!linear && length_unit)) {
            error("positions in '" + s.unit + "' for the " + (linear ? "prismatic" : "revolute") + " joint '" +
                  joint.name + "'");
            continue;
        }
        // Checked again here: the C API fills specs without the file reader.
        bool good = true;
        for (const auto& [name, value] : joint_dynamics_coefficients(s))
            if (!std::isfinite(value) || value < 0) {
                error(std::string(name) + " of joint '" + joint.name + "' must be finite and not negative");
                good = false;
            }
        if (!std::isfinite(s.rest)) {
            error("rest of joint '" + joint.name + "' must be finite");
            good = false;
        }
        for (const std::string& problem : joint_dynamics_problems(s)) {
            error("joint '" + joint.name + "': " + problem);
            good = false;
        }
        if (s.limited && !(std::isfinite(s.lower) && std::isfinite(s.upper) && s.lower <= s.upper)) {
            error("limits of joint '" + joint.name + "' must be finite with lower <= upper");
            good = false;
        }
        if (!good) continue;

        ResolvedJointDynamics r;
        r.spec = s;
        r.joint = j;
        r.source = int(index);
        r.name = joint.name;
        r.linear = linear;
#define MBX_COPY_FROM_SPEC(field) r.field = s.field;
        MBX_JOINT_DYNAMICS_SCALARS(MBX_COPY_FROM_SPEC)
#undef MBX_COPY_FROM_SPEC
        r.damping_negative = s.damping_negative.value_or(s.damping);
        r.coulomb_negative = s.coulomb_negative.value_or(s.coulomb);
        r.limited = s.limited;
        r.transmission = s.transmission;
        given[size_t(j)] = int(index);
        out.push_back(std::move(r));
    }
    return out;
}

}  // namespace mbx
