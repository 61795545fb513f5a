#include <algorithm>
#include <utility>

#include "builtins.h"

namespace mbx_stub {
namespace {

using Factory = Assembly (*)();

// Sorted by name.
const std::pair<const char*, Factory> kBuiltins[] = {
    {"double_cardan", builtins::double_cardan},
    {"fourbar", builtins::fourbar},
    {"planar_sixbar", builtins::planar_sixbar},
    {"six_axis_arm", builtins::six_axis_arm},
};

}  // namespace

std::vector<std::string> builtin_names() {
    std::vector<std::string> names;
    for (const auto& b : kBuiltins) names.emplace_back(b.first);
    std::sort(names.begin(), names.end());
    return names;
}

bool builtin_assembly(const std::string& name, Assembly& out) {
    for (const auto& b : kBuiltins) {
        if (name == b.first) {
            out = b.second();
            return true;
        }
    }
    return false;
}

}  // namespace mbx_stub
