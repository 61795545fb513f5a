#include "mjcf/mjcf_export.h"

namespace mbx {

void export_mjcf(ExportModel&, OutputFiles&) {}  // placeholder until the mjcf writer lands

}  // namespace mbx
