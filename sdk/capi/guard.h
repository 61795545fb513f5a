// No exception crosses the C boundary: every entry point runs its body here.
#pragma once
#include <sys/resource.h>

#include <cstdio>
#include <cstring>
#include <new>

#include "sdk/capi/handles.h"

namespace mbx {

// A caller's argument the entry point cannot use (a null pointer, an index out of range).
[[noreturn]] inline void bad_argument(const std::string& what) {
    throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject{}, what);
}

// What a host reads when an allocation failed. Under an address-space limit
// (ulimit -v, a container's) that limit is what ran out: named, with its
// size, so the user knows what to raise (docs/limits.md, "Calibration memory").
inline std::string out_of_memory_message() {
    rlimit limit{};
    if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY)
        return "out of memory: the system could not give the run the memory it asked for";
    char text[160];
    std::snprintf(text, sizeof text,
                  "out of memory: the run needed more than the process's address-space limit of %.4g MiB "
                  "(RLIMIT_AS, ulimit -v)",
                  double(limit.rlim_cur) / (1024.0 * 1024.0));
    return text;
}

template <class Body>
mbx_status guarded(mbx_context* context, Body&& body) {
    try {
        body();
        if (context) context->clear();
        return MBX_OK;
    } catch (const Error& e) {
        return context ? context->fail(e.status(), e.what(), e.subject(), e.file(), e.line()) : e.status();
    } catch (const std::bad_alloc&) {
        return context ? context->fail(MBX_ERROR_OUT_OF_MEMORY, out_of_memory_message()) : MBX_ERROR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        return context ? context->fail(MBX_ERROR_INTERNAL, std::string("internal error: ") + e.what())
                       : MBX_ERROR_INTERNAL;
    } catch (...) {
        return context ? context->fail(MBX_ERROR_INTERNAL, "internal error") : MBX_ERROR_INTERNAL;
    }
}

// The raw value of a C enum field: a C host may store any int there, and
// reading it as the enum type would be undefined for values outside it.
template <class E>
int raw_enum(const E& e) {
    int raw = 0;
    static_assert(sizeof raw == sizeof e, "C enums are int-sized");
    std::memcpy(&raw, &e, sizeof raw);
    return raw;
}

// Copies a fully filled SDK-side struct into the caller's, which may be an
// older, smaller version: only the bytes it declared are written.
template <class T>
mbx_status copy_out(T* out, const T& full) {
    if (!out || out->struct_size < 2 * sizeof(uint32_t)) return MBX_ERROR_INVALID_ARGUMENT;
    const uint32_t size = out->struct_size;
    std::memcpy(static_cast<void*>(out), &full, size < sizeof(T) ? size : sizeof(T));
    out->struct_size = size;
    return MBX_OK;
}

}  // namespace mbx
