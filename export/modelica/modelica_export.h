// Modelica Standard Library 4.0 MultiBody package (see docs/exporters.md).
#pragma once
#include "export/common/export_model.h"

namespace mbx {

// Appends the package's files: modelica/<Name>/package.mo, package.order,
// the generated mechanical model, the user model (keep_existing) and the
// STL meshes under Resources/Meshes.
void export_modelica(ExportModel& model, OutputFiles& out);

}  // namespace mbx
