// Pieces shared by the JSON and text reports. Internal to report/.
#pragma once
#include <cstddef>
#include <vector>

#include "core/translator/mechanism.h"

namespace mbx::report_detail {

const char* joint_type_name(mbx_primitive_type type);
const char* body_kind_name(mbx_rigid_body_kind kind);

// Reports describe whatever they are given, including hand-built or broken
// mechanisms, so every index is checked before use.
template <class T>
bool valid_index(const std::vector<T>& v, long long i) {
    return i >= 0 && static_cast<unsigned long long>(i) < v.size();
}

// Joints grouped by their parent body, in joint order (compressed rows: one
// allocation instead of a vector per body, which matters at 100k bodies).
struct JointsByParent {
    std::vector<std::size_t> offset;  // bodies + 1 entries
    std::vector<int> joints;

    const int* begin(std::size_t body) const { return joints.data() + offset[body]; }
    const int* end(std::size_t body) const { return joints.data() + offset[body + 1]; }
};
JointsByParent joints_by_parent(const Mechanism& m, bool include_cut_joints);

struct Counts {
    std::size_t dynamic_bodies = 0;
    std::size_t joint_nodes = 0;
    std::size_t revolute = 0, prismatic = 0, spherical = 0;
    std::size_t cut_joints = 0;
    std::size_t planar_loops = 0;
    std::size_t info = 0, warnings = 0, errors = 0;
};
Counts count(const Mechanism& m);

}  // namespace mbx::report_detail
