// A joint named by stable CAD ids, as every user description keys it.
#pragma once
#include <string>

namespace mbx {

// Joint by stable CAD id: the host constraint and the primitive within its
// chain (0 = J_N next to the base); -1 picks the constraint's only
// prismatic or revolute primitive.
struct JointRef {
    std::string constraint_id;
    int primitive = -1;
};

}  // namespace mbx
