// Welded parts become one rigid body; ground parts become the ground.
#include <algorithm>

#include "core/union_find.h"
#include "core/translator/mass_properties.h"
#include "core/translator/translate.h"

namespace mbx {

void merge_welds(Mechanism& m, Progress& progress) {
    const Assembly& a = m.assembly;
    const size_t n = a.parts.size();
    const size_t world = n;  // extra set standing for the ground
    UnionFind sets(n + 1);
    for (size_t i = 0; i < n; ++i)
        if (a.parts[i].is_ground()) sets.unite(i, world);

    progress.stage("merge welds", a.constraints.size());
    for (const Constraint& c : a.constraints) {
        progress.tick();
        if (!c.is_weld()) continue;
        ++m.weld_count;
        const size_t p = size_t(a.frames[size_t(c.base_frame)].part);
        const size_t q = size_t(a.frames[size_t(c.follower_frame)].part);
        if (!sets.unite(p, q)) {
            ++m.collapsed_weld_loops;
            m.add(MBX_SEVERITY_INFO, MBX_FINDING_WELD_LOOP_COLLAPSED, Subject::constraint(c.id, c.name),
                  "weld '" + c.name + "' joins parts already welded together ('" + a.parts[p].name + "' and '" +
                      a.parts[q].name + "'); the loop it closes collapsed into one rigid body");
        }
    }

    // Clusters numbered in order of their first part, ground first: the same
    // input always gives the same body order.
    // A cluster of helper parts only (a CAD "RootPart" welded to nothing
    // real) that no joint touches carries nothing: it is dropped, not made a
    // massless dynamic body.
    std::vector<char> has_real(n + 1, 0), jointed(n + 1, 0);
    for (size_t i = 0; i < n; ++i)
        if (!a.parts[i].is_helper()) has_real[sets.find(i)] = 1;
    for (const Constraint& c : a.constraints) {
        if (c.is_weld()) continue;
        jointed[sets.find(size_t(a.frames[size_t(c.base_frame)].part))] = 1;
        jointed[sets.find(size_t(a.frames[size_t(c.follower_frame)].part))] = 1;
    }
    const size_t ground_root = sets.find(world);

    std::vector<int> cluster_of_root(n + 1, -1);
    cluster_of_root[ground_root] = 0;
    m.bodies.clear();
    m.bodies.emplace_back();
    m.bodies[0].kind = MBX_RIGID_BODY_GROUND;
    m.bodies[0].id = "ground";
    m.bodies[0].name = "ground";
    m.part_body.assign(n, -1);
    for (size_t i = 0; i < n; ++i) {
        const size_t root = sets.find(i);
        if (root != ground_root && !has_real[root] && !jointed[root]) {
            const Part& part = a.parts[i];
            m.add(MBX_SEVERITY_INFO, MBX_FINDING_HELPER_BODY_DROPPED, Subject::body(part.id, part.name),
                  "helper part '" + part.name + "' is attached to no real part and was dropped");
            continue;
        }
        int& cluster = cluster_of_root[root];
        if (cluster < 0) {
            cluster = int(m.bodies.size());
            m.bodies.emplace_back();
        }
        m.part_body[i] = cluster;
        m.bodies[size_t(cluster)].parts.push_back(int(i));
    }

    // Principal part: the heaviest non-helper part (first on ties); its frame
    // becomes the body frame so exported bodies sit where the CAD part sits.
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        RigidBody& body = m.bodies[b];
        int principal = -1;
        for (int p : body.parts) {
            const Part& part = a.parts[size_t(p)];
            if (part.is_helper()) continue;
            if (principal < 0 || part.mass > a.parts[size_t(principal)].mass) principal = p;
        }
        if (principal < 0 && !body.parts.empty()) principal = body.parts.front();
        body.principal_part = principal;
        if (b == 0) {
            body.pose = Pose();  // ground frame is the world
        } else {
            body.pose = a.parts[size_t(principal)].pose;
            body.id = a.parts[size_t(principal)].id;
            body.name = a.parts[size_t(principal)].name;
        }
        MassAccumulator acc(body.pose);
        for (int p : body.parts) {
            const Part& part = a.parts[size_t(p)];
            if (part.mass < 0) continue;  // reported by validation; would poison the compound
            acc.add(part.mass, part.com, part.inertia, part.pose);
        }
        MassProperties mp = acc.result();
        body.mass = mp.mass;
        body.com = mp.com;
        body.inertia = mp.inertia;
    }
    progress.finish();
}

}  // namespace mbx
