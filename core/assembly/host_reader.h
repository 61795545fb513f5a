// Pulls an assembly through a host's mbx_host callback table: checks the
// table's version, converts units to SI and poses to world, re-orthonormalizes
// rotations, and rejects what cannot be repaired (NaN, dangling references)
// with an Error naming the body, frame or constraint.
#pragma once
#include "core/assembly/assembly.h"
#include "core/progress.h"
#include "mbx/mbx.h"

namespace mbx {

struct HostReadOptions {
    double orthonormality_tolerance = 1e-5;  // warn above this deviation
    double orthonormality_limit = 0.05;      // refuse above this: not a rotation at all
};

Assembly read_host(const mbx_host* host, const HostReadOptions& options, Progress& progress, Findings& findings);

// Turns the host's diagnostics from index `from` on into findings and returns
// how many the host holds now (`from` if it has no diagnostics callbacks).
size_t pull_host_diagnostics(const mbx_host& host, size_t from, Findings& findings);

// True when the table is large enough to hold `field_end` bytes.
inline bool host_has(const mbx_host* host, size_t field_end) { return host->struct_size >= field_end; }

}  // namespace mbx
