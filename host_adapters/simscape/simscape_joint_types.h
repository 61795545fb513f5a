// Simscape's joint blocks as mbx primitives: what each typed joint element
// of an import file becomes. A joint type is one entry in the table
// (simscape_joint_types.cpp).
#pragma once
#include <string_view>
#include <vector>

#include "mbx/mbx.h"

namespace mbx_files {

// One primitive along an axis of the base frame (0 = x, 1 = y, 2 = z).
struct SimscapePrimitive {
    mbx_primitive_type type;
    int axis;
};

struct SimscapeJointType {
    const char* element;  // the element's name in <Joints>
    // From the base frame to the follower frame, in Simscape's order.
    std::vector<SimscapePrimitive> chain;
};

// The entry for an element name, or null for one mbx does not know.
const SimscapeJointType* simscape_joint_type(std::string_view element);
// The element names known, for messages ("Revolute, Prismatic, ...").
std::string simscape_joint_type_names();

}  // namespace mbx_files
