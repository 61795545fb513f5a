// mbx_mechanism_export: C options in, export/ modules run, notes appended to
// the mechanism's findings.
#include <cstring>

#include "sdk/capi/export_model_of.h"
#include "sdk/capi/guard.h"
#include "export/export_files.h"

using namespace mbx;

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
        // Notes join the findings once, however often the model is exported.
        for (const Finding& note : model.notes()) {
            bool known = false;
            for (const Finding& f : m.findings)
                known = known || (f.code == note.code && f.subject.id == note.subject.id && f.message == note.message);
            if (!known) m.findings.push_back(note);
        }
    });
}

}  // extern "C"
