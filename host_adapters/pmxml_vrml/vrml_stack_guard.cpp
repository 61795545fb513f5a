#include "vrml_stack_guard.h"

#include <cstddef>

#if defined(__linux__)
#include <pthread.h>
#endif

namespace mbx_files::vrml {
namespace {

// Left free below the last check: room to build the error message, throw
// and unwind, and for the non-recursive calls between two checks (reading
// and parsing an Inline file starts a fresh parse from a deep frame).
constexpr uintptr_t reserve = 256 * 1024;
// Used where the thread's stack cannot be asked for.
constexpr uintptr_t fallback_budget = 1024 * 1024;

}  // namespace

StackGuard::StackGuard() {
    const auto here = reinterpret_cast<uintptr_t>(__builtin_frame_address(0));
    limit_ = here > fallback_budget ? here - fallback_budget : 0;
#if defined(__linux__)
    pthread_attr_t attr;
    if (pthread_getattr_np(pthread_self(), &attr) == 0) {
        void* addr = nullptr;
        size_t size = 0;
        if (pthread_attr_getstack(&attr, &addr, &size) == 0 && addr) {
            const auto bottom = reinterpret_cast<uintptr_t>(addr);
            limit_ = here > bottom + reserve ? bottom + reserve : here;
        }
        pthread_attr_destroy(&attr);
    }
#endif
}

}  // namespace mbx_files::vrml
