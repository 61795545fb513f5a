#include "mesh/mesh_export.h"

namespace mbx {

std::string encode_mesh(const std::vector<Mesh>&, const std::string&, mbx_mesh_format) { return {}; }
void export_body_meshes(ExportModel&, mbx_mesh_format, OutputFiles&) {}
void export_scene(ExportModel&, OutputFiles&) {}

}  // namespace mbx
