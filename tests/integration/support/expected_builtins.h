// The hand-derived translation of each builtin (derivations in the comments
// of plugin_stub/assemblies/builtin_*.cpp). One table, used both to check the
// stub data against an independent screw oracle and to check the SDK.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace itest {

struct JointRef {
    std::string constraint;  // full constraint id
    uint32_t primitive = 0;  // chain index (0 = J_N)
};

struct ExpectedLoop {
    JointRef cut;
    std::vector<JointRef> members;  // every joint around the loop, cut included
    int dof = 0;
    uint32_t redundant = 0;
    int gruebler = 0;  // sum f - 6, or - 3 when planar
    bool planar = false;
};

struct ExpectedBuiltin {
    std::string name;
    uint32_t parts = 0, rigid_bodies = 0, joint_nodes = 0, joints = 0;
    uint32_t revolutes = 0, prismatics = 0, sphericals = 0, welds = 0;
    uint32_t loops = 0, planar_loops = 0;
    int dof = 0;
    int gruebler = 0;  // spatial: 6 * (moving bodies incl. nodes) - sum (6 - f)
    uint32_t redundant = 0;
    std::vector<ExpectedLoop> loop_list;          // in loop order (= host order of the cuts)
    std::vector<std::vector<std::string>> merged;  // parts that must end up in one rigid body
    std::vector<std::string> in_ground;            // parts that must end up in the ground body
    std::vector<JointRef> reversed;                // joints whose tree parent is the CAD follower
};

const std::vector<ExpectedBuiltin>& expected_builtins();
const ExpectedBuiltin& expected_builtin(const std::string& name);

}  // namespace itest
