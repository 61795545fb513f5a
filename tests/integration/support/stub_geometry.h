// What the stub data means in SI world coordinates, recomputed here from the
// raw host values and units -- independently of the SDK and of the stub's
// own builder -- so tests can check the SDK's conversions against it.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include <mbx/mbx.h>

#include "apps/stub_host/assemblies/stub_assembly.h"

namespace itest {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

double length_si(const mbx_units& u);   // 0 means 1
double mass_si(const mbx_units& u);
double inertia_si(const mbx_units& u);  // 0 means mass * length^2

Mat3 rotation(const double row_major[9]);
Vec3 vec(const double v[3]);

struct WorldPose {
    Mat3 R = Mat3::Identity();
    Vec3 p = Vec3::Zero();
    Vec3 apply(const Vec3& local) const { return R * local + p; }
};
WorldPose world(const mbx_pose& pose, double length_factor);

const mbx_stub::Body& body_by_id(const mbx_stub::Assembly& a, const std::string& id);
const mbx_stub::Frame& frame_by_id(const mbx_stub::Assembly& a, const std::string& id);
const mbx_stub::Constraint& constraint_by_id(const mbx_stub::Assembly& a, const std::string& id);

WorldPose body_world(const mbx_stub::Body& b);
WorldPose frame_world(const mbx_stub::Assembly& a, const mbx_stub::Frame& f);
// Unit world axis of a primitive (IN_WORLD or IN_BASE_FRAME).
Vec3 axis_world(const mbx_stub::Assembly& a, const mbx_stub::Constraint& c, const mbx_stub::Primitive& p);

// Mass properties in world terms: inertia about the CoM in world axes.
struct MassWorld {
    double mass = 0;
    Vec3 com = Vec3::Zero();
    Mat3 inertia = Mat3::Zero();
};
MassWorld mass_world(const mbx_stub::Body& b);
// Compound of rigidly joined parts: parallel-axis theorem about the common CoM.
MassWorld combine(const std::vector<MassWorld>& parts);

}  // namespace itest
