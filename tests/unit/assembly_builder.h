// Builds mbx::Assembly objects directly (no host) for white-box tests.
#pragma once
#include <string>

#include "core/assembly/assembly.h"
#include "core/math.h"

namespace test {

inline mbx::Mat3 rot_z(double angle) { return Eigen::AngleAxisd(angle, mbx::Vec3::UnitZ()).toRotationMatrix(); }
inline mbx::Mat3 rot_x(double angle) { return Eigen::AngleAxisd(angle, mbx::Vec3::UnitX()).toRotationMatrix(); }

class AssemblyBuilder {
public:
    mbx::Assembly a;

    int part(const std::string& id, double mass, const mbx::Vec3& position, uint32_t flags = 0,
             const mbx::Mat3& rotation = mbx::Mat3::Identity(),
             const mbx::Mat3& inertia = mbx::Vec3(0.01, 0.02, 0.025).asDiagonal(),
             const mbx::Vec3& com = mbx::Vec3::Zero()) {
        mbx::Part p;
        p.id = id;
        p.name = id;
        p.flags = flags;
        p.mass = mass;
        p.com = com;
        p.inertia = inertia;
        p.pose.rotation = rotation;
        p.pose.position = position;
        a.parts.push_back(p);
        return int(a.parts.size() - 1);
    }
    int frame(int part, const mbx::Vec3& world_position) {
        mbx::Frame f;
        f.id = "F" + std::to_string(a.frames.size());
        f.name = f.id;
        f.part = part;
        f.world.position = world_position;
        a.frames.push_back(f);
        return int(a.frames.size() - 1);
    }
    // Constraint between two parts at one world point; chain of primitives.
    int joint(const std::string& id, int base, int follower, const mbx::Vec3& at,
              std::initializer_list<mbx_primitive_type> chain, const mbx::Vec3& axis = mbx::Vec3::UnitZ()) {
        mbx::Constraint c;
        c.id = id;
        c.name = id;
        c.base_frame = frame(base, at);
        c.follower_frame = frame(follower, at);
        for (mbx_primitive_type t : chain) {
            mbx::Primitive p;
            p.type = t;
            p.axis = axis.normalized();
            c.chain.push_back(p);
        }
        a.constraints.push_back(c);
        return int(a.constraints.size() - 1);
    }
    int revolute(const std::string& id, int base, int follower, const mbx::Vec3& at,
                 const mbx::Vec3& axis = mbx::Vec3::UnitZ()) {
        return joint(id, base, follower, at, {MBX_PRIMITIVE_REVOLUTE}, axis);
    }
    int weld(const std::string& id, int base, int follower) {
        return joint(id, base, follower, a.parts[size_t(follower)].pose.position, {MBX_PRIMITIVE_WELD});
    }
};

}  // namespace test
