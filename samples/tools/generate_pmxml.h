// Synthetic PMXML + VRML assemblies of any size, deterministic by seed, for
// benchmarks and scale tests of the file adapter. Layout, like a CAD export:
//
//   RootGround =weld= RootPart =weld= BASE =weld= PEDESTAL_k (one per 25
//   top-level sub-assemblies); every Subsystem has its own RootPart, welded
//   only to its first part (the dangling helper exporters write), and hangs
//   from a pedestal (top level) or from the last part of the previous
//   sub-assembly (nested, up to 3 deep). Inside a sub-assembly, a chain of
//   bars in one plane (random per sub-assembly), axes normal to it, built of
//     R  a bar on a revolute                      1 part, 1 R,          dof +1
//     W  a bar on a revolute, a bar welded to it  2 parts, 1 R, 1 weld, dof +1
//     L  a parallelogram four-bar hung from the   3 parts, 4 R, 1 loop, dof +1,
//        previous bar, its closing joint last        redundant +3 (planar)
//   first R, then W, L, R, W, L, ... (R when the quota has no room left).
// Bars come in four lengths; their geometry lives in four shared VRML files
// (or, optionally, in place in the assembly file), so 100k parts stay a few
// tens of MB of VRML. Every part frame is at least 40 mm from every other.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace mbx_samples {

struct GeneratorOptions {
    size_t parts = 1000;          // PMXML bodies other than RootParts (at least 1: BASE)
    uint32_t seed = 1;
    size_t subsystem_size = 40;   // parts per sub-assembly
    bool inline_geometry = false; // shapes in the assembly file instead of shared Inlines
    int digits = 10;              // significant digits in the PMXML (real exporters: 6)
};

// Exact counts of what was written and what the SDK must make of it.
struct GeneratedCounts {
    std::string xml_path, wrl_path;
    size_t parts = 0;          // bodies other than RootParts
    size_t root_parts = 0;     // 1 + subsystems
    size_t subsystems = 0;
    size_t simple_joints = 0;  // SimpleJoints, welds included
    size_t welds = 0;          // weld SimpleJoints, RootGround--RootPart included
    size_t revolutes = 0;
    size_t loops = 0;
    size_t rigid_bodies = 0;   // dynamic bodies after weld merging (ground excluded)
    int dof = 0;
    int redundant = 0;
    size_t vrml_nodes = 0;     // Transforms in the assembly file (parts + subsystems)
};

// Writes "<name>.xml", "<name>_a.wrl" and the shared bar files into
// `directory` (which must exist). Throws std::runtime_error on I/O errors.
GeneratedCounts generate_pmxml(const std::string& directory, const std::string& name, const GeneratorOptions& options);

}  // namespace mbx_samples
