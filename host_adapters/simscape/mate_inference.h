// Joints from CAD mates: what SolidWorks, Creo and Inventor exports give
// instead of joints. Each mate between two parts, at the exported pose,
// blocks some of the second part's motion relative to the first: its
// geometry gives constraint rows on the relative twist (a coincident plane
// pair removes the translation along the normal and the two rotations about
// in-plane axes; a concentric axis pair the two translations across the axis
// and the two rotations about axes across it; ...). The rank of the stacked
// rows (by singular values with the mobility analysis' rule, tau = 1e-9 *
// max(1, largest)) gives the motion left, and that motion names the joint.
// The rules are in docs/simscape.md.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace mbx_files {

// One geometry of a mate, in world coordinates at the exported pose.
struct MateGeometry {
    std::string type;  // plane, cylinder, circle, sphere, point, line (lower case)
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // a plane's normal, a cylinder's or line's direction
};

struct Mate {
    std::string type, name;  // Coincident, Concentric, Parallel, Perpendicular, Distance, Angle
    int line = 0;
    MateGeometry first, second;  // on the base part, on the follower part
};

// What the mates between one pair of parts leave: a joint type of the
// Simscape table (docs/simscape.md) with its frame (z the axis, the origin
// its anchor; a planar or rectangular joint's x and y its sliding directions).
struct InferredJoint {
    std::string type;  // "" when the motion left is none of the table's
    Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
    int freedoms = 6;  // of the relative motion left
    std::vector<int> redundant;  // mates (indices) that hold nothing the earlier ones do not
};

struct MateProblem {
    int mate = -1;
    bool error = false;  // the mate cannot hold at the exported pose (or its geometry is unusable)
    std::string message;
};

// `length` is the assembly's size, against which positions count as equal.
InferredJoint infer_joint(const std::vector<Mate>& mates, double length, std::vector<MateProblem>& problems);

}  // namespace mbx_files
