// What the joint-dynamics tests share (exports and the simulator): a
// description file's <joint> entries resolved against a mechanism, a joint
// by name, and a carriage-pendulum assembly with one prismatic and one
// revolute joint to put them on.
#pragma once
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "apps/stub_host/assemblies/builder.h"
#include "drives_support.h"

namespace xtest {

// `joints` (<joint> elements) resolved against `m`; REQUIREs a clean file.
inline std::vector<mbx::ResolvedJointDynamics> resolve_joints(const mbx::Mechanism& m, const std::string& joints) {
    mbx::MechatronicSpec spec;
    std::vector<mbx::DriveError> errors;
    mbx::load_drive_text("<mechatronics version=\"1\">\n" + joints + "</mechatronics>\n", "joints.xml", "", spec, errors);
    for (const mbx::DriveError& e : errors) FAIL_CHECK(e.text());
    std::vector<mbx::ResolvedJointDynamics> out = mbx::resolve_joint_dynamics(spec, m, errors);
    for (const mbx::DriveError& e : errors) FAIL_CHECK(e.text());
    REQUIRE(errors.empty());
    return out;
}

inline int joint_named(const mbx::Mechanism& m, const std::string& name) {
    for (size_t j = 0; j < m.joints.size(); ++j)
        if (m.joints[j].name == name) return int(j);
    FAIL("no joint " << name);
    return -1;
}

// A carriage on a prismatic joint along x ("<prefix>/slide") carrying a
// pendulum on a revolute about x ("<prefix>/pivot", CAD limits +-2 rad when
// `pivot_limits`) that hangs along -z: a point-like bob of kBobMass at
// kLength below the pivot.
constexpr double kLength = 0.4, kBobMass = 2.0, kBobInertia = 1e-3;
inline mbx_memory::Assembly carriage_pendulum(const std::string& prefix, bool pivot_limits) {
    namespace build = mbx_stub::build;
    const mbx_units si{1, 1, 1};
    mbx_memory::Assembly a;
    a.name = "carriage pendulum";
    build::Builder b(a, prefix, si, si);
    const build::Mat3 I = build::Mat3::Identity();
    b.body("base", "Base", MBX_BODY_GROUND, 10, I, build::Vec3(0, 0, 0), build::Vec3(0, 0, 0), I);
    b.body("carriage", "Carriage", 0, 3, I, build::Vec3(0, 0, 0), build::Vec3(0, 0, 0),
           build::box_inertia(3, 0.2, 0.2, 0.05));
    b.body("bob", "Bob", 0, kBobMass, I, build::Vec3(0, 0, -kLength), build::Vec3(0, 0, -kLength), kBobInertia * I);
    build::Prim slide;
    slide.type = MBX_PRIMITIVE_PRISMATIC;
    slide.axis = build::Vec3(1, 0, 0);
    b.joint("slide", "base", "carriage", build::Vec3(0, 0, 0), I, {slide}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    const build::Prim pivot = pivot_limits ? build::revolute(build::Vec3(1, 0, 0), MBX_AXIS_IN_WORLD, -2, 2)
                                           : build::revolute(build::Vec3(1, 0, 0));
    b.joint("pivot", "carriage", "bob", build::Vec3(0, 0, 0), I, {pivot}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    return a;
}

}  // namespace xtest
