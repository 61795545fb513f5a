// Internal: one function per built-in assembly (builtin_<name>.cpp).
#pragma once

#include "stub_assembly.h"

namespace mbx_stub {
namespace builtins {

Assembly fourbar();
Assembly double_cardan();
Assembly planar_sixbar();
Assembly six_axis_arm();

}  // namespace builtins
}  // namespace mbx_stub
