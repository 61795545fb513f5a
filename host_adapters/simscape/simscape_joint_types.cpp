#include "simscape_joint_types.h"

#include <string>

namespace mbx_files {
namespace {

// Simscape Multibody's joint blocks: a revolute turns about the frames'
// common z axis, a prismatic slides along it; a pin-slot slides along x and
// turns about z; a planar slides in the xy plane and turns about z. The
// exporters write the first seven; the others are Simscape blocks a user's
// own tool may write.
const std::vector<SimscapeJointType>& table() {
    constexpr mbx_primitive_type R = MBX_PRIMITIVE_REVOLUTE, P = MBX_PRIMITIVE_PRISMATIC,
                                 S = MBX_PRIMITIVE_SPHERICAL, W = MBX_PRIMITIVE_WELD;
    constexpr int x = 0, y = 1, z = 2;
    static const std::vector<SimscapeJointType> types = {
        {"Revolute", {{R, z}}},
        {"Prismatic", {{P, z}}},
        {"Cylindrical", {{P, z}, {R, z}}},
        {"Spherical", {{S, z}}},
        {"Planar", {{P, x}, {P, y}, {R, z}}},
        {"Weld", {{W, z}}},
        {"PinSlot", {{P, x}, {R, z}}},
        {"Universal", {{R, x}, {R, y}}},
        {"Gimbal", {{R, x}, {R, y}, {R, z}}},
        {"Rectangular", {{P, x}, {P, y}}},
        {"Cartesian", {{P, x}, {P, y}, {P, z}}},
    };
    return types;
}

}  // namespace

const SimscapeJointType* simscape_joint_type(std::string_view element) {
    for (const SimscapeJointType& t : table())
        if (element == t.element) return &t;
    return nullptr;
}

std::string simscape_joint_type_names() {
    std::string out;
    for (const SimscapeJointType& t : table()) out += (out.empty() ? "" : ", ") + std::string(t.element);
    return out;
}

}  // namespace mbx_files
