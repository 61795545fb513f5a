// An independent mobility oracle for stub assemblies: welds merged with a
// union-find, the spanning tree and cut joints chosen by the same rule the
// SDK documents (constraints in host order; a primitive whose edge would
// close a cycle is cut), then the rank of the screw (twist) loop-closure
// matrix by SVD. It exists to check the stub's hand-derived expectations and
// the generator's documented counts, so that a disagreement with the SDK can
// be pinned on the SDK rather than on the test data.
#pragma once

#include <string>
#include <vector>

#include "apps/stub_host/assemblies/stub_assembly.h"

namespace itest {

struct OracleLoop {
    std::string cut_constraint;  // id
    size_t cut_primitive = 0;    // chain index (0 = J_N)
    size_t joint_count = 0;
    int dof = 0;                 // this loop alone
    int redundant = 0;
    bool planar = false;         // every joint a revolute, all axes parallel
};

struct OracleResult {
    size_t rigid_bodies = 0;     // dynamic, ground excluded
    size_t joint_nodes = 0;
    size_t joints = 0;           // primitive joints, welds excluded
    int dof = 0;
    int redundant = 0;
    std::vector<OracleLoop> loops;
};

OracleResult screw_mobility(const mbx_stub::Assembly& a);

}  // namespace itest
