#include "screw_mobility.h"

#include <Eigen/Dense>
#include <deque>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

#include "stub_geometry.h"

namespace itest {
namespace {

using Twist = Eigen::Matrix<double, 6, 1>;

struct Sets {
    std::vector<size_t> parent;
    size_t add() {
        parent.push_back(parent.size());
        return parent.size() - 1;
    }
    size_t find(size_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    bool unite(size_t a, size_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return false;
        parent[b] = a;
        return true;
    }
};

struct Joint {
    mbx_primitive_type type = MBX_PRIMITIVE_REVOLUTE;
    Vec3 axis = Vec3::UnitZ(), point = Vec3::Zero();
    size_t base = 0, follower = 0;  // body on each CAD side
    size_t column = 0;      // first column in the closure matrix
    int freedoms() const { return type == MBX_PRIMITIVE_SPHERICAL ? 3 : 1; }
    std::string constraint;
    size_t primitive = 0;
};

int rank_of(const Eigen::MatrixXd& m) {
    if (m.rows() == 0 || m.cols() == 0) return 0;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
    const auto& s = svd.singularValues();
    const double threshold = 1e-9 * std::max(1.0, s.size() ? s(0) : 0.0);
    int r = 0;
    for (int i = 0; i < s.size(); ++i) r += s(i) > threshold;
    return r;
}

}  // namespace

OracleResult screw_mobility(const mbx_stub::Assembly& a) {
    // Rigid groups: parts joined by all-weld constraints, ground parts together.
    std::unordered_map<std::string, size_t> part;
    for (size_t i = 0; i < a.bodies.size(); ++i) part[a.bodies[i].id] = i;
    Sets parts;
    for (size_t i = 0; i < a.bodies.size(); ++i) parts.add();
    long ground = -1;
    for (size_t i = 0; i < a.bodies.size(); ++i) {
        if (!(a.bodies[i].flags & MBX_BODY_GROUND)) continue;
        if (ground < 0) ground = long(i);
        parts.unite(size_t(ground), i);
    }
    auto is_weld = [](const mbx_stub::Constraint& c) {
        for (const auto& p : c.chain)
            if (p.type != MBX_PRIMITIVE_WELD) return false;
        return true;
    };
    auto part_of_frame = [&](const std::string& frame_id) { return part.at(frame_by_id(a, frame_id).body_id); };
    for (const auto& c : a.constraints)
        if (is_weld(c)) parts.unite(part_of_frame(c.base_frame_id), part_of_frame(c.follower_frame_id));

    // Body 0 = ground group, then the other groups in part order.
    std::unordered_map<size_t, size_t> body_of_root;
    if (ground >= 0) body_of_root[parts.find(size_t(ground))] = 0;
    size_t bodies = 1;
    for (size_t i = 0; i < a.bodies.size(); ++i)
        if (body_of_root.emplace(parts.find(i), bodies).second) ++bodies;
    OracleResult r;
    r.rigid_bodies = bodies - 1;
    auto body_of_frame = [&](const std::string& frame_id) {
        return body_of_root.at(parts.find(part_of_frame(frame_id)));
    };

    // Joints in host order; union-find decides tree edge or cut.
    std::vector<Joint> joints;
    std::vector<size_t> cuts;
    Sets tree;
    for (size_t i = 0; i < bodies; ++i) tree.add();
    for (const auto& c : a.constraints) {
        if (is_weld(c)) continue;
        const size_t base = body_of_frame(c.base_frame_id), follower = body_of_frame(c.follower_frame_id);
        if (base == follower) continue;
        const Vec3 at = frame_world(a, frame_by_id(a, c.base_frame_id)).p;
        std::vector<size_t> moving;
        for (size_t k = 0; k < c.chain.size(); ++k)
            if (c.chain[k].type != MBX_PRIMITIVE_WELD) moving.push_back(k);
        size_t previous = base;
        for (size_t k = 0; k < moving.size(); ++k) {
            size_t next = follower;
            if (k + 1 < moving.size()) {
                next = tree.add();
                ++bodies;
                ++r.joint_nodes;
            }
            const auto& p = c.chain[moving[k]];
            Joint j;
            j.type = p.type;
            j.axis = axis_world(a, c, p);
            j.point = at;
            j.base = previous;
            j.follower = next;
            j.constraint = c.id;
            j.primitive = moving[k];
            if (!tree.unite(previous, next)) cuts.push_back(joints.size());
            joints.push_back(j);
            previous = next;
        }
    }
    r.joints = joints.size();

    // Orient the tree edges from ground (and from any floating root).
    std::vector<std::vector<size_t>> adjacent(bodies);
    std::vector<bool> is_cut(joints.size(), false);
    for (size_t c : cuts) is_cut[c] = true;
    for (size_t j = 0; j < joints.size(); ++j) {
        if (is_cut[j]) continue;
        adjacent[joints[j].base].push_back(j);
        adjacent[joints[j].follower].push_back(j);
    }
    std::vector<long> parent_joint(bodies, -1);
    std::vector<size_t> depth(bodies, 0);
    std::vector<bool> seen(bodies, false);
    for (size_t root = 0; root < bodies; ++root) {
        if (seen[root]) continue;
        seen[root] = true;
        std::deque<size_t> queue{root};
        while (!queue.empty()) {
            const size_t u = queue.front();
            queue.pop_front();
            for (size_t j : adjacent[u]) {
                const size_t v = joints[j].base == u ? joints[j].follower : joints[j].base;
                if (seen[v]) continue;
                seen[v] = true;
                parent_joint[v] = long(j);
                depth[v] = depth[u] + 1;
                queue.push_back(v);
            }
        }
    }

    size_t columns = 0;
    for (Joint& j : joints) {
        j.column = columns;
        columns += size_t(j.freedoms());
    }
    auto twists = [](const Joint& j) {
        Eigen::Matrix<double, 6, Eigen::Dynamic> t(6, j.freedoms());
        if (j.type == MBX_PRIMITIVE_SPHERICAL) {
            for (int k = 0; k < 3; ++k) {
                const Vec3 w = Vec3::Unit(k);
                t.col(k) << w, j.point.cross(w);
            }
        } else if (j.type == MBX_PRIMITIVE_PRISMATIC) {
            t.col(0) << Vec3::Zero(), j.axis;
        } else {
            t.col(0) << j.axis, j.point.cross(j.axis);
        }
        return t;
    };

    // Each loop: walk the tree path from the cut's follower side back to its
    // base side, then the cut; each step adds +-(follower relative to base).
    Eigen::MatrixXd closure = Eigen::MatrixXd::Zero(6 * Eigen::Index(cuts.size()), Eigen::Index(columns));
    for (size_t l = 0; l < cuts.size(); ++l) {
        const Joint& cut = joints[cuts[l]];
        std::vector<std::pair<size_t, double>> steps;  // joint, sign
        std::vector<std::pair<size_t, double>> down;
        size_t u = cut.follower, v = cut.base;  // walk u -> v
        while (u != v) {
            if (depth[u] >= depth[v]) {
                const size_t j = size_t(parent_joint[u]);
                const size_t up = joints[j].base == u ? joints[j].follower : joints[j].base;
                steps.push_back({j, joints[j].base == u ? 1.0 : -1.0});  // moving from u to its parent
                u = up;
            } else {
                const size_t j = size_t(parent_joint[v]);
                const size_t up = joints[j].base == v ? joints[j].follower : joints[j].base;
                down.push_back({j, joints[j].follower == v ? 1.0 : -1.0});  // later walked parent -> v
                v = up;
            }
        }
        steps.insert(steps.end(), down.rbegin(), down.rend());
        steps.push_back({cuts[l], 1.0});
        OracleLoop info;
        info.cut_constraint = cut.constraint;
        info.cut_primitive = cut.primitive;
        info.joint_count = steps.size();
        int loop_columns = 0;
        info.planar = true;
        for (const auto& s : steps) {
            const Joint& j = joints[s.first];
            closure.block(6 * Eigen::Index(l), Eigen::Index(j.column), 6, j.freedoms()) += s.second * twists(j);
            loop_columns += j.freedoms();
            if (j.type != MBX_PRIMITIVE_REVOLUTE || std::abs(std::abs(j.axis.dot(cut.axis)) - 1) > 1e-9)
                info.planar = false;
        }
        if (cut.type != MBX_PRIMITIVE_REVOLUTE) info.planar = false;
        const int rank = rank_of(closure.middleRows(6 * Eigen::Index(l), 6));
        info.dof = loop_columns - rank;
        info.redundant = 6 - rank;
        r.loops.push_back(info);
    }
    // Loops sharing no joint are independent blocks: rank them one group at a time.
    Sets groups;
    for (size_t l = 0; l < cuts.size(); ++l) groups.add();
    for (Eigen::Index c = 0; c < closure.cols(); ++c) {
        long first = -1;
        for (size_t l = 0; l < cuts.size(); ++l) {
            if (closure.block(6 * Eigen::Index(l), c, 6, 1).isZero(0)) continue;
            if (first < 0) first = long(l);
            else groups.unite(size_t(first), l);
        }
    }
    int rank = 0;
    for (size_t g = 0; g < cuts.size(); ++g) {
        if (groups.find(g) != g) continue;
        std::vector<size_t> rows;
        for (size_t l = 0; l < cuts.size(); ++l)
            if (groups.find(l) == g) rows.push_back(l);
        Eigen::MatrixXd m(6 * Eigen::Index(rows.size()), closure.cols());
        for (size_t k = 0; k < rows.size(); ++k)
            m.middleRows(6 * Eigen::Index(k), 6) = closure.middleRows(6 * Eigen::Index(rows[k]), 6);
        rank += rank_of(m);
    }
    r.dof = int(columns) - rank;
    r.redundant = int(6 * cuts.size()) - rank;
    return r;
}

}  // namespace itest
