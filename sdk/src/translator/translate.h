// The translator: assembly in, mechanism out (thesis section 2.6, with loops,
// weld merging, mobility and validation).
#pragma once
#include <memory>

#include "assembly/assembly.h"
#include "core/progress.h"
#include "translator/mechanism.h"

namespace mbx {

// Builds the mechanism from an already pulled assembly. `findings` are those
// gathered while pulling; they come first in the report.
std::unique_ptr<Mechanism> translate_assembly(Assembly assembly, Findings findings, const TranslateOptions& options,
                                              Progress& progress);

// Stages, callable one by one from tests. Each appends its findings.
void merge_welds(Mechanism& m, Progress& progress);
void build_tree(Mechanism& m, Progress& progress);
void validate(Mechanism& m, Progress& progress);

}  // namespace mbx
