// Translation and report entry points.
#include <algorithm>
#include <cstring>

#include "core/assembly/host_reader.h"
#include "sdk/capi/guard.h"
#include "core/report/report.h"
#include "core/translator/translate.h"

using namespace mbx;

namespace {

// Reads only the option fields the caller's struct holds.
TranslateOptions read_options(const mbx_translate_options* in) {
    TranslateOptions o;
    if (!in) return o;
    if (MBX_FIELD_FITS(in, mbx_translate_options, length_tolerance) && in->length_tolerance > 0)
        o.length_tolerance = in->length_tolerance;
    if (MBX_FIELD_FITS(in, mbx_translate_options, orthonormality_tolerance) && in->orthonormality_tolerance > 0)
        o.orthonormality_tolerance = in->orthonormality_tolerance;
    if (MBX_FIELD_FITS(in, mbx_translate_options, rank_tolerance) && in->rank_tolerance > 0)
        o.rank_tolerance = in->rank_tolerance;
    if (MBX_FIELD_FITS(in, mbx_translate_options, flags))
        o.check_mass_with_shapes = in->flags & MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES;
    if (MBX_FIELD_FITS(in, mbx_translate_options, centroid_tolerance) && in->centroid_tolerance > 0)
        o.centroid_tolerance = in->centroid_tolerance;
    return o;
}

}  // namespace

extern "C" {

MBX_API mbx_status mbx_translate(mbx_context* context, const mbx_host* host, const mbx_translate_options* options,
                                 mbx_mechanism** out_mechanism) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!out_mechanism) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "out_mechanism is NULL");
    *out_mechanism = nullptr;
    if (!host) return context->fail(MBX_ERROR_INVALID_ARGUMENT, "host table is NULL");
    if (options && options->struct_size < sizeof(uint32_t))
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "options.struct_size is not set");
    return guarded(context, [&] {
        const TranslateOptions opts = read_options(options);
        Progress progress(context->progress, context->progress_user);
        Findings findings;
        HostReadOptions read;
        read.orthonormality_tolerance = opts.orthonormality_tolerance;
        Assembly assembly = read_host(host, read, progress, findings);
        auto handle = std::make_unique<mbx_mechanism>();
        std::memcpy(&handle->host, host, std::min<size_t>(host->struct_size, sizeof(mbx_host)));
        handle->host.struct_size = std::min<uint32_t>(host->struct_size, sizeof(mbx_host));
        handle->has_host = true;
        // Shapes fetched by the mass check stay cached for later consumers.
        mbx_mechanism* h = handle.get();
        auto fetch = [h](Mechanism& m, int body) -> const std::vector<Mesh>& { return h->body_shapes(m, body); };
        handle->model = translate_assembly(std::move(assembly), std::move(findings), opts, progress, fetch);
        *out_mechanism = handle.release();
    });
}

MBX_API void mbx_mechanism_destroy(mbx_mechanism* mechanism) { delete mechanism; }

MBX_API mbx_status mbx_mechanism_release_host(mbx_mechanism* mechanism) {
    if (!mechanism) return MBX_ERROR_INVALID_ARGUMENT;
    mechanism->has_host = false;
    mechanism->host = mbx_host{};
    return MBX_OK;
}

MBX_API mbx_status mbx_mechanism_write_report(mbx_context* context, const mbx_mechanism* mechanism,
                                              const char* directory) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    if (!mechanism || !directory || !directory[0])
        return context->fail(MBX_ERROR_INVALID_ARGUMENT, "mechanism or directory is NULL or empty");
    return guarded(context, [&] { write_report(*mechanism->model, directory, &mechanism->drives, &mechanism->joint_dynamics); });
}

}  // extern "C"
