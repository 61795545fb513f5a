// Geometry to bodies by pose (thesis section 2.7.2): walk the VRML hierarchy;
// a node whose world position coincides with exactly one body's part frame
// (CS1) makes that body current for its subtree; several candidates are
// narrowed by orientation, then by name prefix ("Obj01" matches "Obj" and
// "Obj-1"); no candidate keeps the parent's body, so a VRML hierarchy deeper
// than the PMXML (a rigid sub-assembly exported as one body) gives that body
// several shapes. A spatial hash keeps the cost near-linear.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vrml_scene.h"

namespace mbx_files {

struct BodyPose {
    std::string id;
    std::string name;
    Eigen::Isometry3d world;  // part frame (CS1) in world, in the model length unit
};

struct MatchOptions {
    // Positions closer than this coincide (model length unit). 0 = 1e-4 times
    // the bounding-box diagonal of the body positions.
    double position_tolerance = 0;
    double angle_tolerance = 1e-3;  // radians, for the orientation filter
    // Length of one VRML unit in model units. 0 = automatic: the first of
    // 1, 0.001, 1000, 1/25.4, 25.4, 0.01, 100 that matches the most nodes.
    double vrml_scale = 0;
};

struct MatchedMesh {
    int body = -1;                    // index into the bodies passed in
    int node = -1;                    // VrmlScene node holding the mesh
    std::string name;                 // mesh or node name, for reports
    std::vector<double> vertices;     // body frame, model length unit
    std::vector<uint32_t> triangles;
};

struct MatchIssue {
    enum Kind { unmatched, ambiguous } kind;
    int node = -1;
    std::string message;  // names the node (DEF/part name, file:line) and the candidates
};

struct MatchResult {
    std::vector<MatchedMesh> meshes;
    std::vector<MatchIssue> issues;
    double vrml_scale = 1;   // the one used
    size_t matched_nodes = 0;
};

MatchResult match_shapes(const VrmlScene& scene, const std::vector<BodyPose>& bodies, const MatchOptions& options = {});

}  // namespace mbx_files
