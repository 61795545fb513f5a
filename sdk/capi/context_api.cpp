// Library, status and context entry points.
#include "sdk/capi/guard.h"

using namespace mbx;

extern "C" {

MBX_API const char* mbx_version(void) { return MBX_VERSION_STRING; }
MBX_API uint32_t mbx_abi_version(void) { return MBX_ABI_VERSION; }

MBX_API const char* mbx_status_name(mbx_status status) {
    switch (status) {
        case MBX_OK: return "MBX_OK";
        case MBX_ERROR_INVALID_ARGUMENT: return "MBX_ERROR_INVALID_ARGUMENT";
        case MBX_ERROR_HOST_CALLBACK: return "MBX_ERROR_HOST_CALLBACK";
        case MBX_ERROR_INVALID_INPUT: return "MBX_ERROR_INVALID_INPUT";
        case MBX_ERROR_CANCELLED: return "MBX_ERROR_CANCELLED";
        case MBX_ERROR_IO: return "MBX_ERROR_IO";
        case MBX_ERROR_OUT_OF_MEMORY: return "MBX_ERROR_OUT_OF_MEMORY";
        case MBX_ERROR_VERSION: return "MBX_ERROR_VERSION";
        case MBX_ERROR_INTERNAL: return "MBX_ERROR_INTERNAL";
        case MBX_ERROR_SIMULATION: return "MBX_ERROR_SIMULATION";
    }
    return "MBX_ERROR_UNKNOWN";
}

MBX_API mbx_status mbx_context_create(mbx_context** out_context) {
    if (!out_context) return MBX_ERROR_INVALID_ARGUMENT;
    *out_context = nullptr;
    try {
        *out_context = new mbx_context();
    } catch (...) {
        return MBX_ERROR_OUT_OF_MEMORY;
    }
    return MBX_OK;
}

MBX_API void mbx_context_destroy(mbx_context* context) { delete context; }

MBX_API const char* mbx_context_last_error(const mbx_context* context) {
    return context ? context->message.c_str() : "context is NULL";
}

MBX_API mbx_status mbx_context_last_error_info(const mbx_context* context, mbx_error_info* out_info) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    mbx_error_info info{};
    info.struct_size = sizeof info;
    info.status = context->status;
    info.subject_kind = context->subject.kind;
    info.subject_id = context->subject.id.c_str();
    info.subject_name = context->subject.name.c_str();
    info.file = context->file.c_str();
    info.line = context->line;
    info.message = context->message.c_str();
    return copy_out(out_info, info);
}

MBX_API mbx_status mbx_context_set_progress(mbx_context* context, mbx_progress_fn progress, void* user_data) {
    if (!context) return MBX_ERROR_INVALID_ARGUMENT;
    context->progress = progress;
    context->progress_user = user_data;
    return MBX_OK;
}

}  // extern "C"
