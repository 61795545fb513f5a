// Internal: composes stub assemblies from SI world geometry and stores them
// in whatever host units the assembly declares, so the builtins can be
// written (and checked by hand) in metres while the SDK still receives
// millimetres, grams, frames relative to bodies and axes in frame axes.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <unordered_map>
#include <vector>

#include "stub_assembly.h"

namespace mbx_stub {
namespace build {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

mbx_pose make_pose(const Mat3& rotation, const Vec3& position);
Mat3 rotation_of(const mbx_pose& pose);
Vec3 position_of(const mbx_pose& pose);

Mat3 axis_angle(const Vec3& axis, double angle);
// A rotation whose x axis is `x` and whose y axis is as close to `y_hint` as
// x allows (y_hint must not be parallel to x).
Mat3 rotation_x_to(const Vec3& x, const Vec3& y_hint);
// A rotation whose z axis is `z`, turned about z by `twist`, so that axis
// components given in this frame are not trivially (0,0,1).
Mat3 rotation_z_to(const Vec3& z, double twist);

// Solid box of edge lengths (a, b, c) along its own x, y, z axes.
Mat3 box_inertia(double mass, double a, double b, double c);
// Triangle mesh of a box of edge lengths `size`, centred at `centre` and
// turned by `rotation` in the body frame. SI; Builder converts.
Mesh box_mesh(const std::string& name, const Vec3& size, const Mat3& rotation, const Vec3& centre);

// SI factor of a units struct, with the "0 means SI" defaults of mbx.h.
double length_factor(const mbx_units& u);
double mass_factor(const mbx_units& u);
double inertia_factor(const mbx_units& u);

struct Prim {
    mbx_primitive_type type = MBX_PRIMITIVE_REVOLUTE;
    Vec3 axis = Vec3::UnitZ();  // world, SI
    mbx_axis_reference reference = MBX_AXIS_IN_WORLD;
    bool has_limits = false;
    double lower = 0, upper = 0;  // rad (revolute) or m (prismatic)
};

Prim revolute(const Vec3& axis, mbx_axis_reference reference = MBX_AXIS_IN_WORLD);
Prim revolute(const Vec3& axis, mbx_axis_reference reference, double lower, double upper);
Prim spherical();
Prim weld();

class Builder {
public:
    // Ids are "<prefix>/<local name>". Bodies and meshes use body_units,
    // frames use frame_units (they may differ: the SDK must convert each).
    Builder(Assembly& out, std::string prefix, mbx_units body_units, mbx_units frame_units);

    // Pose and CoM in world SI; inertia about the CoM in the body axes, SI.
    Body& body(const std::string& local, const std::string& name, uint32_t flags, double mass,
               const Mat3& rotation, const Vec3& position, const Vec3& com_world, const Mat3& inertia_body);

    // A CAD joint at world point `at`: one frame on each body there, both
    // with world rotation `frame_rotation`, and the chain (world axes).
    Constraint& joint(const std::string& local, const std::string& base_body, const std::string& follower_body,
                      const Vec3& at, const Mat3& frame_rotation, const std::vector<Prim>& chain,
                      mbx_frame_reference base_reference, mbx_frame_reference follower_reference);

    // Mesh given in SI in the body frame.
    void mesh(const std::string& body_local, Mesh mesh);

    std::string id(const std::string& local) const { return prefix_ + "/" + local; }
    Mat3 body_rotation(const std::string& local) const;
    Vec3 body_position(const std::string& local) const;  // world, SI

private:
    Frame& frame(const std::string& local, const std::string& body_local, const Mat3& rotation, const Vec3& at,
                 mbx_frame_reference reference);
    const Body& find(const std::string& local) const;

    Assembly& out_;
    std::string prefix_;
    mbx_units body_units_, frame_units_;
    std::unordered_map<std::string, size_t> body_index_;
};

}  // namespace build
}  // namespace mbx_stub
