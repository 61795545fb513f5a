// Where each solid of a STEP file sits: the assembly structure
// (NEXT_ASSEMBLY_USAGE_OCCURRENCE placed by a CONTEXT_DEPENDENT_SHAPE_-
// REPRESENTATION's ITEM_DEFINED_TRANSFORMATION) and MAPPED_ITEMs walked from
// the root representations down, so that a part used three times is three
// placed solids, each named by its product and its occurrence path.
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "host_adapters/step/brep.h"
#include "host_adapters/step/part21.h"

namespace mbx_step {

struct PlacedSolid {
    uint32_t solid = 0;                                     // into Brep::solids
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity(); // the solid's coordinates to the file's (metres)
    std::string product;     // the part's PRODUCT name (its id where the name is empty)
    std::string occurrence;  // the occurrences from the root, '/'-separated (empty for a lone part)
};

struct Assembly {
    std::vector<PlacedSolid> solids;  // in the order of the walk: each root, then depth first
    std::vector<Problem> problems;    // a transformation that is not a rigid motion, a cycle of occurrences
};

// Every use of every solid. A solid no root reaches (a part no assembly
// uses, or a file without product structure) is placed once where it is.
Assembly place_solids(const File& f, const Brep& b);

}  // namespace mbx_step
