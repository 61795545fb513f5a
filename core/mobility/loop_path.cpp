#include "core/mobility/loop_path.h"

#include <algorithm>
#include <string>

namespace mbx::mobility {
namespace {

[[noreturn]] void fail(int loop_index, const std::string& what) {
    std::string id = "loop" + std::to_string(loop_index);
    throw Error(MBX_ERROR_INTERNAL, Subject::loop(id), "Loop " + std::to_string(loop_index) + ": " + what);
}

bool valid_body(const Mechanism& mech, int b) { return b >= 0 && b < static_cast<int>(mech.bodies.size()); }

// The tree joint above `body`, checked so a corrupt tree cannot make the
// walk loop forever: its child must be `body` and its parent strictly higher.
int joint_above(const Mechanism& mech, int body, int loop_index) {
    int j = mech.bodies[body].parent_joint;
    if (j < 0 || j >= static_cast<int>(mech.joints.size())) return -1;
    const Joint& joint = mech.joints[j];
    if (joint.cut || joint.child != body || !valid_body(mech, joint.parent) ||
        mech.bodies[joint.parent].depth >= mech.bodies[body].depth)
        fail(loop_index, "tree joint \"" + joint.name + "\" does not lead up the spanning tree from body \"" +
                             mech.bodies[body].name + "\".");
    return j;
}

}  // namespace

void trace_loop(Mechanism& mech, int loop_index) {
    Loop& loop = mech.loops[loop_index];
    int cut = loop.cut_joint;
    if (cut < 0 || cut >= static_cast<int>(mech.joints.size()) || !mech.joints[cut].cut)
        fail(loop_index, "its cut joint index " + std::to_string(cut) + " is not a cut joint.");
    const Joint& cj = mech.joints[cut];
    if (!valid_body(mech, cj.parent) || !valid_body(mech, cj.child))
        fail(loop_index, "cut joint \"" + cj.name + "\" does not connect two bodies.");

    // Step the deeper end up until both meet at the lowest common ancestor.
    // Stepping only the deeper one (ties: the parent side) can never pass
    // the LCA, even if depths skip values.
    std::vector<int> up_from_child, up_from_parent;
    int c = cj.child, p = cj.parent;
    while (c != p) {
        bool step_parent = mech.bodies[p].depth >= mech.bodies[c].depth;
        int& body = step_parent ? p : c;
        int j = joint_above(mech, body, loop_index);
        if (j < 0)
            fail(loop_index, "cut joint \"" + cj.name + "\" connects bodies \"" + mech.bodies[cj.parent].name +
                                 "\" and \"" + mech.bodies[cj.child].name + "\" of separate trees.");
        (step_parent ? up_from_parent : up_from_child).push_back(j);
        body = mech.joints[j].parent;
    }

    loop.joints.clear();
    loop.signs.clear();
    loop.joints.reserve(1 + up_from_child.size() + up_from_parent.size());
    loop.signs.reserve(loop.joints.capacity());
    loop.joints.push_back(cut);
    loop.signs.push_back(-1);
    for (int j : up_from_child) {
        loop.joints.push_back(j);
        loop.signs.push_back(+1);
    }
    for (auto it = up_from_parent.rbegin(); it != up_from_parent.rend(); ++it) {
        loop.joints.push_back(*it);
        loop.signs.push_back(-1);
    }
}

}  // namespace mbx::mobility
