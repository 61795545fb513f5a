// A VRML97 scene as the file adapter needs it: the Transform hierarchy with
// accumulated world transforms, and the triangle meshes under each node.
// Produced by read_vrml (vrml_reader.h), consumed by match_shapes
// (shape_matching.h).
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace mbx_files {

// Triangles of one Shape (IndexedFaceSet, triangulated), in the local
// coordinates of the node that holds it.
struct VrmlMesh {
    std::string name;                 // DEF name of the Shape or geometry node, "" if none
    std::vector<double> vertices;     // 3 per vertex
    std::vector<uint32_t> triangles;  // 3 per triangle, 0-based
};

// A grouping node (Transform, Group, an Inline's content, a PROTO instance).
struct VrmlNode {
    int parent = -1;        // index into VrmlScene::nodes; -1 at top level
    std::string kind;       // "Transform", "Group", "Inline", or the PROTO name
    std::string name;       // DEF name, "" if none
    std::string part_name;  // CAD part name from a Model_Info-style PROTO in scope, "" if none
    std::string file;       // file the node was read from (Inlines: the inlined file)
    int line = 0;           // 1-based line of the node in `file`
    Eigen::Affine3d world = Eigen::Affine3d::Identity();  // local -> world, may hold scale
    std::vector<VrmlMesh> meshes;                         // shapes directly under this node
};

struct VrmlScene {
    std::vector<VrmlNode> nodes;        // depth first: a parent comes before its children
    std::string title;                  // WorldInfo title
    std::vector<std::string> info;      // WorldInfo info strings
    std::vector<std::string> warnings;  // "file:line: message" for skipped or unsupported content
};

// Bounds that make hostile input end in an error instead of exhausting the machine.
struct VrmlLimits {
    size_t max_depth = 256;             // nesting of nodes and PROTO expansion
    size_t max_inline_depth = 16;       // Inline chains (cycles are detected separately)
    size_t max_file_bytes = size_t(1) << 30;
    size_t max_total_values = size_t(1) << 28;  // numbers read over all files
    size_t max_nodes = size_t(1) << 22;
};

// Parse or semantic error with its location.
class VrmlError : public std::runtime_error {
public:
    VrmlError(std::string file, int line, const std::string& message)
        : std::runtime_error(file + ":" + std::to_string(line) + ": " + message), file_(std::move(file)), line_(line) {}
    const std::string& file() const { return file_; }
    int line() const { return line_; }

private:
    std::string file_;
    int line_;
};

}  // namespace mbx_files
