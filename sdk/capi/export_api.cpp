// mbx_mechanism_export: C options in, export/ modules run, notes appended to
// the mechanism's findings.
#include <cstring>
#include <filesystem>

#include "sdk/capi/export_model_of.h"
#include "sdk/capi/guard.h"
#include "core/mechatronics/xml_text.h"
#include "core/report/atomic_file.h"
#include "export/export_files.h"
#include "export/urdf/urdf_update.h"

using namespace mbx;

namespace {

// Notes join the findings once, however often the model is exported.
void keep_notes(Mechanism& m, const ExportModel& model) {
    for (const Finding& note : model.notes()) {
        bool known = false;
        for (const Finding& f : m.findings)
            known = known || (f.code == note.code && f.subject.id == note.subject.id && f.message == note.message);
        if (!known) m.findings.push_back(note);
    }
}

}  // namespace

extern "C" {

MBX_API mbx_status mbx_mechanism_export(mbx_context* context, mbx_mechanism* mechanism,
                                        const mbx_export_options* options, const char* directory) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!mechanism || !mechanism->model || !directory || !directory[0])
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechanism or directory is NULL or empty");
    if (options && options->struct_size < sizeof(uint32_t))
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "options.struct_size is not set");
    return guarded(context, [&] {
        ExportSettings settings;
        uint32_t formats = 0;
        if (options) {
            if (MBX_FIELD_FITS(options, mbx_export_options, formats)) formats = options->formats;
            if (MBX_FIELD_FITS(options, mbx_export_options, mesh_format)) {
                // A C host may store any int in the enum; reading it as
                // the C++ enum would be undefined for values out of range.
                int raw = 0;
                static_assert(sizeof raw == sizeof options->mesh_format, "C enums are int-sized");
                std::memcpy(&raw, &options->mesh_format, sizeof raw);
                if (raw != MBX_MESH_STL && raw != MBX_MESH_OBJ && raw != MBX_MESH_GLTF)
                    throw Error(MBX_ERROR_INVALID_ARGUMENT, {}, "unknown mesh_format " + std::to_string(raw));
                settings.mesh_format = mbx_mesh_format(raw);
            }
            if (MBX_FIELD_FITS(options, mbx_export_options, model_name) && options->model_name &&
                options->model_name[0])
                settings.model_name = options->model_name;
            if (MBX_FIELD_FITS(options, mbx_export_options, stop_time) && options->stop_time > 0)
                settings.stop_time = options->stop_time;
        }
        settings.scene_collision = formats & MBX_EXPORT_SCENE_COLLISION;
        formats &= ~uint32_t(MBX_EXPORT_SCENE_COLLISION);
        if (formats & ~uint32_t(MBX_EXPORT_ALL))
            throw Error(MBX_ERROR_INVALID_ARGUMENT, {}, "unknown export format bits " + std::to_string(formats));
        Mechanism& m = *mechanism->model;
        ExportModel model = export_model_of(mechanism, settings);
        write_output_files(directory, export_files(model, formats));
        keep_notes(m, model);
    });
}

MBX_API mbx_status mbx_mechanism_update_urdf(mbx_context* context, mbx_mechanism* mechanism, const char* urdf_path,
                                            const char* output_path) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!mechanism || !mechanism->model || !urdf_path || !urdf_path[0] || !output_path || !output_path[0])
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechanism, urdf_path or output_path is NULL or empty");
    return guarded(context, [&] {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(urdf_path, ec))
            throw Error(MBX_ERROR_INVALID_INPUT, {}, "not a regular file: " + std::string(urdf_path), urdf_path);
        std::string text;
        if (!read_text_file(urdf_path, text)) throw Error(MBX_ERROR_INVALID_INPUT, {}, "cannot read " + std::string(urdf_path), urdf_path);
        Mechanism& m = *mechanism->model;
        ExportModel model = export_model_of(mechanism, ExportSettings{});
        const UrdfUpdate update = update_urdf(model, text, urdf_path);
        write_file_atomically(output_path, update.text);
        keep_notes(m, model);
    });
}

}  // extern "C"
