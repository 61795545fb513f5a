// A bound on recursion by the stack actually left, not by a level count:
// how many levels fit depends on the build (sanitizers multiply frame
// sizes) and on the thread the reader runs on. The parser and the scene
// builder check it at every nesting level next to VrmlLimits::max_depth,
// so even a caller that sets max_depth very high gets a VrmlError, not a
// stack overflow.
#pragma once
#include <cstdint>

namespace mbx_files::vrml {

class StackGuard {
public:
    // Measures the current thread's stack; create it on the thread that reads.
    StackGuard();

    bool exhausted() const { return reinterpret_cast<uintptr_t>(__builtin_frame_address(0)) < limit_; }

private:
    uintptr_t limit_ = 0;  // lowest frame address allowed (stacks grow down)
};

}  // namespace mbx_files::vrml
