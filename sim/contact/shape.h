// Collision shapes, decoupled from the rigid bodies they ride on (thesis
// section 3.x: several shapes per body, none tied to the body's inertia):
// each shape has its own pose in its body's frame, and environment shapes
// (a ground half-space, fixed obstacles) ride on the world, body 0.
#pragma once
#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

namespace mbx::sim::contact {

enum class ShapeKind { Sphere, Box, Cylinder, Capsule, HalfSpace, Convex };

struct ConvexHull {
    std::vector<Eigen::Vector3d> vertices;  // in the shape's frame
    // Faces as FCL wants them: for each face its vertex count, then its
    // vertex indices, counter-clockwise seen from outside.
    std::vector<int> faces;
    int face_count = 0;
};

struct Shape {
    ShapeKind kind = ShapeKind::Sphere;
    std::string name;
    int body = 0;  // sim body (0: the world)
    // Pose in the body frame.
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    // Sphere, capsule, cylinder: radius; capsule and cylinder: length along
    // the shape's z; box: full side lengths; half-space: the solid is z <= 0
    // of the shape's frame (its normal is the frame's +z).
    double radius = 0, length = 0;
    Eigen::Vector3d size = Eigen::Vector3d::Zero();
    std::shared_ptr<const ConvexHull> hull;
    // Filtering: a pair collides only if (a.group & b.mask) and (b.group & a.mask).
    unsigned group = 1, mask = ~0u;
    // Which contact material it is made of: a pair of shapes takes the
    // settings of its pair of materials (contact_step.h, MaterialPair).
    int material = 0;
    // Two shapes that both set this and overlap at the model's reference
    // (CAD) configuration never collide: the real parts do not interpenetrate
    // there, so the overlap is an artefact of the shapes (hulls of parts two
    // joints apart across a short link), not a contact. Set on the default hulls.
    bool skip_if_overlapping_at_reference = false;
};

}  // namespace mbx::sim::contact
