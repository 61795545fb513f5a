// The boundary representation of every solid in a STEP file: solids, their
// shells, faces with their bounds, and the edges and vertices the faces
// share (each edge once, however many faces use it, so that a tessellation
// can discretise it once). Geometry is in metres, each solid read in the
// units of the representation that holds it.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "host_adapters/step/geometry.h"
#include "host_adapters/step/part21.h"

namespace mbx_step {

struct Vertex {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    uint32_t entity = kUnresolved;
};

struct Edge {
    uint32_t entity = kUnresolved;
    uint32_t start = kUnresolved, end = kUnresolved;  // into Brep::vertices
    Curve curve;
    bool same_sense = true;  // the curve runs from start to end
};

struct OrientedEdge {
    uint32_t edge = kUnresolved;  // into Brep::edges
    bool forward = true;          // traversed from the edge's start to its end
};

struct Loop {
    enum class Kind { Edges, Vertex, Poly } kind = Kind::Edges;
    std::vector<OrientedEdge> edges;          // Edges
    uint32_t vertex = kUnresolved;            // Vertex: a degenerate bound (a cone's apex)
    std::vector<Eigen::Vector3d> polygon;     // Poly: a faceted B-rep's loop
    bool orientation = true;  // false: traversed against the order written
    bool outer = false;       // a FACE_OUTER_BOUND
    uint32_t entity = kUnresolved;
};

struct Face {
    uint32_t entity = kUnresolved;  // instance index; id and line as written, for findings
    uint64_t id = 0;
    int line = 0;
    Surface surface;          // a faceted face's plane is its polygon's
    bool same_sense = true;   // the face's normal is the surface's
    std::vector<Loop> bounds;
};

struct Shell {
    uint32_t entity = kUnresolved;
    bool closed = true;
    bool reversed = false;  // an oriented shell turned inside out (a void)
    std::vector<uint32_t> faces;  // into Brep::faces
};

// AP242's tessellated geometry: the triangles as the file gives them.
struct Triangles {
    std::vector<Eigen::Vector3d> points;                  // metres
    std::vector<std::array<uint32_t, 3>> triangles;      // counter-clockwise seen from outside
};

struct Solid {
    std::string name;
    uint32_t entity = kUnresolved;
    // MANIFOLD_SOLID_BREP, BREP_WITH_VOIDS, FACETED_BREP, SHELL_BASED_SURFACE_MODEL; or TESSELLATED_SOLID,
    // TESSELLATED_SHELL (then `tessellated` holds its triangles and `shells` is empty)
    std::string type;
    std::vector<Shell> shells;  // the outer one first, then voids
    Triangles tessellated;
    ContextUnits units;
};

struct Brep {
    std::string path;  // the file read, for findings
    std::vector<Vertex> vertices;
    std::vector<Edge> edges;
    std::vector<Face> faces;
    std::vector<Solid> solids;
    std::vector<Problem> problems;  // the reader's and the geometry's
};

// Every solid of the file, in the order written.
Brep read_breps(const File& f);

}  // namespace mbx_step
