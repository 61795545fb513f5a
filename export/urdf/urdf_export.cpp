#include "urdf/urdf_export.h"

namespace mbx {

void export_urdf(ExportModel&, OutputFiles&) {}  // placeholder until the urdf writer lands

}  // namespace mbx
