// Mass properties of a closed triangle mesh as a solid of uniform density
// (divergence theorem over signed tetrahedra from the origin). Used to check
// CAD mass data against the part's own geometry: a wrong orientation layout,
// a mirrored part or a wrong unit shows up as a centroid far from the CAD CoM.
#pragma once
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace mbx {

struct MeshClosure {
    bool closed = false;          // every edge used exactly twice, in opposite directions
    size_t boundary_edges = 0;    // edges used once
    size_t nonmanifold_edges = 0; // edges used more than twice or twice in one direction
};

// Edge check: only a closed, consistently oriented mesh encloses a volume.
MeshClosure check_closure(const std::vector<uint32_t>& triangles);

struct SolidProperties {
    double volume = 0;               // m^3 (positive; orientation is corrected)
    Vec3 centroid = Vec3::Zero();
    Mat3 inertia_per_density = Mat3::Zero();  // about the centroid; multiply by mass/volume
};

// Accumulates several meshes (in one frame) into one solid.
class SolidAccumulator {
public:
    void add(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& triangles);
    SolidProperties result() const;

private:
    double volume_ = 0;
    Vec3 first_ = Vec3::Zero();
    Mat3 second_ = Mat3::Zero();  // integral of x x^T over the volume
};

}  // namespace mbx
