// mbx_mechanism_write_view: the view page of view/, written like an export
// (temporary, then rename) from the same ExportModel.
#include "sdk/capi/export_model_of.h"
#include "sdk/capi/guard.h"
#include "export/export_files.h"
#include "view/view_page.h"

using namespace mbx;

extern "C" {

MBX_API mbx_status mbx_mechanism_write_view(mbx_context* context, mbx_mechanism* mechanism,
                                            const mbx_view_options* options, const char* directory) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!mechanism || !mechanism->model || !directory || !directory[0])
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechanism or directory is NULL or empty");
    if (options && options->struct_size < sizeof(uint32_t))
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "options.struct_size is not set");
    return guarded(context, [&] {
        ExportSettings settings;
        std::string trajectory;
        if (options) {
            if (MBX_FIELD_FITS(options, mbx_view_options, trajectory) && options->trajectory)
                trajectory = options->trajectory;
            if (MBX_FIELD_FITS(options, mbx_view_options, title) && options->title && options->title[0])
                settings.model_name = options->title;
        }
        ExportModel model = export_model_of(mechanism, settings);
        write_output_files(directory, view_files(model, trajectory));
    });
}

}  // extern "C"
