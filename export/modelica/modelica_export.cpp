#include "modelica/modelica_export.h"

namespace mbx {

void export_modelica(ExportModel&, OutputFiles&) {}  // placeholder until the modelica writer lands

}  // namespace mbx
