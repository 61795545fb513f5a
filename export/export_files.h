// The exporters' front door: runs the selected formats over one mechanism and
// writes every file as one unit (temporaries, then renames), so an output
// directory never holds half an export.
#pragma once
#include <string>

#include "common/export_model.h"

namespace mbx {

// Files for `formats` (mbx_export_format bits; 0 = all). Mesh files that the
// model files refer to are included whether or not MBX_EXPORT_MESHES is set.
OutputFiles export_files(ExportModel& model, uint32_t formats);

// Writes `files` below `directory` (created if missing). Files marked
// keep_existing are skipped when already present.
void write_output_files(const std::string& directory, const OutputFiles& files);

}  // namespace mbx
