// Closed triangle meshes for sample and generated parts, and their mass
// properties, so that every PMXML centre of mass and inertia the tools write
// is the one the part's own geometry gives.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

namespace mbx_samples {

// A closed surface; triangles counter-clockwise seen from outside.
struct Solid {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<std::array<uint32_t, 3>> triangles;
};

// Box of edge lengths `size` centred on `pose`'s origin, along its axes.
Solid box(const Eigen::Vector3d& size, const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity());
// Cylinder along `pose`'s z, centred on its origin, as a prism of `segments` sides.
Solid cylinder(double radius, double length, int segments,
               const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity());
// Tube (a bore through a cylinder) along `pose`'s z, centred on its origin.
Solid tube(double inner_radius, double outer_radius, double length, int segments,
           const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity());
// Box from `a` to `b` (its long axis), of the given width and height; the
// width direction is the one of `side` normal to the axis.
Solid bar(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double width, double height,
          const Eigen::Vector3d& side, double overhang);

Solid transformed(const Solid& solid, const Eigen::Isometry3d& pose);

// Uniform unit density. Inertia is the tensor (negated products) about the
// centroid, in the mesh's axes.
struct SolidProperties {
    double volume = 0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    double area = 0;
};

// Of several disjoint solids taken as one body.
SolidProperties properties(const std::vector<const Solid*>& solids);
inline SolidProperties properties(const Solid& solid) { return properties(std::vector<const Solid*>{&solid}); }

// Rotation whose x axis is `x` and whose y axis is the part of `y_hint`
// normal to it.
Eigen::Matrix3d frame_from_x(const Eigen::Vector3d& x, const Eigen::Vector3d& y_hint);

Eigen::Isometry3d make_pose(const Eigen::Vector3d& position,
                            const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity());

}  // namespace mbx_samples
