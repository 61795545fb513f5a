// Finding the mechanism joint a description names by its stable CAD ids
// (constraint id and primitive index). Drives and joint dynamics share it, so
// a reference means the same joint for both.
#pragma once
#include <string>
#include <unordered_map>
#include <vector>

#include "core/mechatronics/drive.h"

namespace mbx {

struct Mechanism;

// Constraint id -> its Mechanism::joints indices (empty for welds merged
// away), hashed once so lookups stay flat on large assemblies.
using JointIndex = std::unordered_map<std::string, std::vector<int>>;
JointIndex index_joints_by_constraint(const Mechanism& m);

// "constraint 'C1' primitive 1", for messages.
std::string joint_ref_text(const JointRef& ref);

// The one joint `ref` names, or -1 with `why`: an unknown constraint id, a
// primitive index the chain does not have, or (primitive -1) a constraint
// without, or with several, prismatic or revolute primitives. The joint's
// kind and whether it is cut are the caller's to judge.
int find_joint(const JointRef& ref, const JointIndex& joints_of, const Mechanism& m, std::string& why);

}  // namespace mbx
