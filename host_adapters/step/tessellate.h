// Solids of a STEP B-rep as closed triangle meshes, and their mass
// properties. Each edge is discretised once and shared by the faces that
// meet there, so a closed shell gives a mesh whose every edge has two
// triangles; each face is triangulated in its surface's parameter plane
// (periodic surfaces unrolled, a seam or pole added where a face wraps round)
// and refined until every edge of it lies within the chord tolerance of the
// surface. Normals point out of the material (a void's shell inward).
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

#include "host_adapters/step/brep.h"
#include "host_adapters/step/evaluate.h"

namespace mbx_step {

struct TriangleMesh {
    std::vector<Eigen::Vector3d> points;
    std::vector<std::array<uint32_t, 3>> triangles;
};

struct SolidMesh {
    std::string name;
    uint32_t solid = 0;          // index into Brep::solids
    TriangleMesh mesh;
    double chord = 0;  // the chord tolerance the mesh was made with (metres)
    size_t faces_meshed = 0, faces_failed = 0;
    size_t sense_disagreements = 0;  // faces whose same-sense flag contradicts their bounds (the bounds win)
    std::vector<Problem> problems;  // faces that could not be meshed, by entity
};

std::vector<SolidMesh> tessellate(const Brep& b, const Tolerance& tolerance);

// (Closure and mass properties of the meshes: core/geometry/mesh_properties.h.)

}  // namespace mbx_step
