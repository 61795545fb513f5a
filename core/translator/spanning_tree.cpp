// Joint chains become massless joint nodes and primitive joints (thesis
// 2.6.4). Constraints are taken in host order; a follower edge that would
// close a cycle is not added to the tree, and its J_1 becomes the cut joint of
// a new loop. The tree is then rooted at ground (and at the first body of
// each floating component) to give every edge its parent-to-child direction.
#include <deque>

#include "core/union_find.h"
#include "core/translator/translate.h"

namespace mbx {
namespace {

struct Edge {
    int joint;
    int base_side;      // body on the CAD base side of this primitive
    int follower_side;  // body on the CAD follower side
};

std::string chain_name(const std::string& name, size_t k, size_t n) {
    return n == 1 ? name : name + "#" + std::to_string(k);
}

}  // namespace

void build_tree(Mechanism& m, Progress& progress) {
    const Assembly& a = m.assembly;
    m.joints.clear();
    m.loops.clear();
    UnionFind sets(m.bodies.size());
    std::vector<Edge> tree_edges;
    tree_edges.reserve(a.constraints.size());

    progress.stage("build tree", a.constraints.size());
    for (size_t ci = 0; ci < a.constraints.size(); ++ci) {
        progress.tick();
        const Constraint& c = a.constraints[ci];
        if (c.is_weld()) continue;
        const Frame& base_frame = a.frames[size_t(c.base_frame)];
        const int base = m.part_body[size_t(base_frame.part)];
        const int follower = m.part_body[size_t(a.frames[size_t(c.follower_frame)].part)];
        if (base == follower) {
            m.add(MBX_SEVERITY_WARNING, MBX_FINDING_SELF_CONSTRAINT, Subject::constraint(c.id, c.name),
                  "joint '" + c.name + "' connects parts welded into one rigid body ('" +
                      m.bodies[size_t(base)].name + "'); it cannot move and was ignored");
            continue;
        }
        // Welds inside a mixed chain add no freedom and no offset at the
        // assembly pose, so only the moving primitives become joints.
        std::vector<const Primitive*> moving;
        for (const Primitive& p : c.chain)
            if (p.type != MBX_PRIMITIVE_WELD) moving.push_back(&p);
        const size_t n = moving.size();

        int previous = base;
        for (size_t k = 0; k < n; ++k) {
            const bool last = k + 1 == n;  // J_1, next to the follower
            int next;
            if (last) {
                next = follower;
            } else {
                next = int(m.bodies.size());
                RigidBody node;
                node.kind = MBX_RIGID_BODY_JOINT_NODE;
                node.id = c.id + "#" + std::to_string(k);
                node.name = c.name + "#" + std::to_string(k);
                node.pose = base_frame.world;
                m.bodies.push_back(std::move(node));
                sets.add();
            }
            Joint j;
            j.type = moving[k]->type;
            j.name = chain_name(c.name, k, n);
            j.constraint = int(ci);
            j.primitive_index = int(moving[k] - c.chain.data());
            j.axis = moving[k]->axis;
            j.frame = base_frame.world;
            j.has_limits = moving[k]->has_limits;
            j.lower = moving[k]->lower;
            j.upper = moving[k]->upper;
            const int index = int(m.joints.size());
            if (sets.unite(size_t(previous), size_t(next))) {
                tree_edges.push_back({index, previous, next});
            } else {
                j.cut = true;
                j.parent = previous;
                j.child = next;
                j.loop = int(m.loops.size());
                Loop loop;
                loop.cut_joint = index;
                m.loops.push_back(std::move(loop));
            }
            m.joints.push_back(std::move(j));
            previous = next;
        }
    }

    // Orient the tree: breadth-first from ground, then from every body no
    // edge reached (a floating component), in body order.
    std::vector<std::vector<int>> adjacent(m.bodies.size());
    for (size_t e = 0; e < tree_edges.size(); ++e) {
        adjacent[size_t(tree_edges[e].base_side)].push_back(int(e));
        adjacent[size_t(tree_edges[e].follower_side)].push_back(int(e));
    }
    std::vector<char> seen(m.bodies.size(), 0);
    std::deque<int> queue;
    m.floating_roots = 0;
    for (size_t root = 0; root < m.bodies.size(); ++root) {
        if (seen[root]) continue;
        if (root != 0) {
            ++m.floating_roots;
            const RigidBody& b = m.bodies[root];
            if (adjacent[root].empty())
                m.add(MBX_SEVERITY_WARNING, MBX_FINDING_BODY_UNCONNECTED, Subject::rigid_body(b.id, b.name),
                      "rigid body '" + b.name + "' is connected to nothing; it floats freely (6 DoF)");
            else
                m.add(MBX_SEVERITY_WARNING, MBX_FINDING_FLOATING_SUBASSEMBLY, Subject::rigid_body(b.id, b.name),
                      "rigid body '" + b.name +
                          "' and the bodies jointed to it are not connected to ground; they float freely (6 DoF)");
        }
        seen[root] = 1;
        m.bodies[root].depth = 0;
        queue.push_back(int(root));
        while (!queue.empty()) {
            const int u = queue.front();
            queue.pop_front();
            for (int e : adjacent[size_t(u)]) {
                const Edge& edge = tree_edges[size_t(e)];
                const int v = edge.base_side == u ? edge.follower_side : edge.base_side;
                if (seen[size_t(v)]) continue;
                seen[size_t(v)] = 1;
                Joint& j = m.joints[size_t(edge.joint)];
                j.parent = u;
                j.child = v;
                j.reversed = edge.base_side != u;
                m.bodies[size_t(v)].parent_joint = edge.joint;
                m.bodies[size_t(v)].depth = m.bodies[size_t(u)].depth + 1;
                queue.push_back(v);
            }
        }
    }
    progress.finish();
}

}  // namespace mbx
