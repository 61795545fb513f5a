// A part's closed meshes as an AP214 STEP file the way CAD systems write a
// part of flat faces: product structure, one MANIFOLD_SOLID_BREP per solid,
// every set of connected coplanar triangles one ADVANCED_FACE on a PLANE
// (outer bound and holes), edges shared between faces. The Simscape samples'
// parts are written with it; mbx's STEP reader and OpenCASCADE read them back.
#pragma once
#include <string>
#include <vector>

#include "solid_mesh.h"

namespace mbx_samples {

struct StepLengthUnit {
    std::string name;  // "mm", "m" or "inch"
    double metres;     // one unit in metres
};
StepLengthUnit step_millimetre();
StepLengthUnit step_metre();
StepLengthUnit step_inch();

// `solids` in metres, in the part frame. Deterministic text.
std::string step_part(const std::string& product_name, const std::vector<Solid>& solids, const StepLengthUnit& unit);
// Written whole or not at all (temp + rename); throws std::runtime_error.
void write_step_part(const std::string& path, const std::string& product_name, const std::vector<Solid>& solids,
                     const StepLengthUnit& unit);

}  // namespace mbx_samples
