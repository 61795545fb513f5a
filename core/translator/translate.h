// The translator: assembly in, mechanism out (thesis section 2.6, with loops,
// weld merging, mobility and validation).
#pragma once
#include <functional>
#include <memory>

#include "core/assembly/assembly.h"
#include "core/progress.h"
#include "core/translator/mechanism.h"

namespace mbx {

// Builds the mechanism from an already pulled assembly. `findings` are those
// gathered while pulling; they come first in the report.
struct Mesh;
// Meshes of rigid body `body` in its frame (see assembly/shape_loader.h).
// Non-const: loading may add the host's late diagnostics to m.findings.
using ShapeFetcher = std::function<const std::vector<Mesh>&(Mechanism& m, int body)>;

std::unique_ptr<Mechanism> translate_assembly(Assembly assembly, Findings findings, const TranslateOptions& options,
                                              Progress& progress, const ShapeFetcher& shapes = {});

// Stages, callable one by one from tests. Each appends its findings.
void merge_welds(Mechanism& m, Progress& progress);
void build_tree(Mechanism& m, Progress& progress);
void validate(Mechanism& m, Progress& progress);
void check_mass_with_shapes(Mechanism& m, const ShapeFetcher& shapes, double centroid_tolerance, Progress& progress);

// Densities outside [kDensityMin, kDensityMax] kg/m^3 (CAD mass / CAD volume,
// parts with a volume only) and a host-stated assembly mass more than
// kAssemblyMassTolerance (relative) from the parts' sum; see mass_plausibility.cpp.
constexpr double kDensityMin = 50;
constexpr double kDensityMax = 25000;
constexpr double kAssemblyMassTolerance = 0.02;
void check_mass_plausibility(Mechanism& m);

}  // namespace mbx
