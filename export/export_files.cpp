#include "export_files.h"

#include <sys/stat.h>

#include "mesh/mesh_export.h"
#include "mjcf/mjcf_export.h"
#include "modelica/modelica_export.h"
#include "core/report/atomic_file.h"
#include "urdf/urdf_export.h"

namespace mbx {

OutputFiles export_files(ExportModel& model, uint32_t formats) {
    if (formats == 0) formats = MBX_EXPORT_ALL;
    const mbx_mesh_format chosen = model.settings().mesh_format;
    OutputFiles out;
    if (formats & MBX_EXPORT_MODELICA) export_modelica(model, out);
    if (formats & MBX_EXPORT_MJCF) export_mjcf(model, out);
    if (formats & MBX_EXPORT_URDF) export_urdf(model, out);

    // Mesh files: the chosen format when asked for, and whatever the model
    // files refer to.
    bool wanted[3] = {false, false, false};
    if (formats & MBX_EXPORT_MESHES) wanted[chosen] = true;
    if (formats & MBX_EXPORT_MJCF) wanted[mjcf_mesh_format(chosen)] = true;
    if (formats & MBX_EXPORT_URDF) wanted[urdf_mesh_format(chosen)] = true;
    for (int f = 0; f < 3; ++f)
        if (wanted[f]) export_body_meshes(model, mbx_mesh_format(f), out);
    if (formats & MBX_EXPORT_MESHES) export_scene(model, out, model.settings().scene_collision);
    return out;
}

void write_output_files(const std::string& directory, const OutputFiles& files) {
    std::vector<std::pair<std::string, std::string>> batch;
    batch.reserve(files.size());
    for (const OutputFile& f : files) {
        const std::string path = directory + "/" + f.path;
        struct stat st;
        if (f.keep_existing && ::stat(path.c_str(), &st) == 0) continue;
        batch.emplace_back(path, f.contents);
    }
    write_files_atomically(batch);
}

}  // namespace mbx
