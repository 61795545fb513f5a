#include "simscape_assembly.h"

#include <map>
#include <unordered_map>
#include <unordered_set>

#include "mate_inference.h"
#include "simscape_joint_types.h"

namespace mbx_files {
namespace {

mbx_pose pose_of(const Eigen::Isometry3d& x) {
    mbx_pose pose{};
    for (int i = 0; i < 3; ++i) {
        pose.position[i] = x.translation()[i];
        for (int j = 0; j < 3; ++j) pose.rotation[3 * i + j] = x.linear()(i, j);
    }
    return pose;
}

Eigen::Isometry3d isometry(const SimscapeTransform& t) {
    Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
    x.linear() = t.rotation;
    x.translation() = t.translation;
    return x;
}

std::string q(const std::string& s) { return "'" + s + "'"; }

class Builder {
public:
    explicit Builder(const SimscapeModel& m) : m_(m) {}

    SimscapeAssembly run() {
        a_.name = m_.root_name;
        a_.source = m_.file;
        units_ = {m_.length_to_m, m_.mass_to_kg, m_.mass_to_kg * m_.length_to_m * m_.length_to_m};
        a_.diagnostics = m_.diagnostics;
        paths_.resize(m_.instances.size());
        names_.resize(m_.instances.size());
        body_of_.assign(m_.instances.size(), -1);
        for (size_t i = 0; i < m_.instances.size(); ++i) {
            const SimscapeInstance& in = m_.instances[i];
            const std::string parent_path = in.parent >= 0 ? paths_[size_t(in.parent)] + "/" : "";
            paths_[i] = parent_path + in.uid;
            names_[i] = (in.parent >= 0 ? names_[size_t(in.parent)] + "/" : "") + in.name;
            by_parent_uid_[key(in.parent, in.uid)] = int(i);
            if (in.part >= 0) add_body(int(i));
        }
        // Grounded sub-assemblies fix every part below them.
        for (size_t i = 0; i < m_.instances.size(); ++i)
            if (m_.instances[i].grounded && m_.instances[i].part < 0)
                for (int leaf : leaves(int(i))) a_.bodies[size_t(body_of_[size_t(leaf)])].flags |= MBX_BODY_GROUND;
        weld_rigid();
        add_joints(m_.root, -1, "");
        for (size_t i = 0; i < m_.instances.size(); ++i) {
            const SimscapeInstance& in = m_.instances[i];
            if (in.assembly >= 0)
                add_joints(m_.assemblies[size_t(in.assembly)].mechanism, int(i), paths_[i] + "/");
        }
        return {std::move(a_), std::move(body_parts_)};
    }

private:
    static std::string key(int parent, const std::string& uid) { return std::to_string(parent) + ":" + uid; }

    void add_body(int instance) {
        const SimscapeInstance& in = m_.instances[size_t(instance)];
        const SimscapePart& part = m_.parts[size_t(in.part)];
        mbx_memory::Body b;
        b.id = paths_[size_t(instance)];
        b.name = names_[size_t(instance)];
        b.flags = in.grounded ? MBX_BODY_GROUND : 0;
        b.units = units_;
        b.mass = part.mass;
        for (int k = 0; k < 3; ++k) b.com[k] = part.com[k];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) b.inertia[3 * r + c] = part.inertia(r, c);
        b.pose = pose_of(in.world);
        if (!part.has_mass_properties)
            diagnostic(MBX_SEVERITY_WARNING, "simscape_no_mass_properties", MBX_SUBJECT_BODY, b.id, b.name, part.line,
                       "part " + q(part.name) + " of instance " + q(b.name) +
                           " has no <MassProperties>: the body is massless");
        body_of_[size_t(instance)] = int(a_.bodies.size());
        body_parts_.push_back({b.id, b.name, in.part});
        a_.bodies.push_back(std::move(b));
    }

    // The instances of parts at or below `instance`, in file order.
    std::vector<int> leaves(int instance) const {
        std::vector<int> out, stack{instance};
        while (!stack.empty()) {
            const int i = stack.back();
            stack.pop_back();
            if (body_of_[size_t(i)] >= 0) out.push_back(i);
            const std::vector<int>& c = m_.instances[size_t(i)].children;
            for (auto it = c.rbegin(); it != c.rend(); ++it) stack.push_back(*it);
        }
        return out;
    }

    void diagnostic(mbx_severity severity, const char* code, mbx_subject_kind kind, const std::string& id,
                    const std::string& name, int line, const std::string& message) {
        mbx_memory::Diagnostic d;
        d.severity = severity;
        d.code = code;
        d.subject_kind = kind;
        d.subject_id = id;
        d.subject_name = name;
        d.file = m_.file;
        d.line = line;
        d.message = message;
        a_.diagnostics.push_back(std::move(d));
    }

    std::string add_frame(int body, const std::string& id, const std::string& name, const Eigen::Isometry3d& world) {
        mbx_memory::Frame f;
        f.id = id;
        f.name = name;
        f.body_id = a_.bodies[size_t(body)].id;
        f.reference = MBX_FRAME_IN_WORLD;
        f.units = units_;
        f.pose = pose_of(world);
        a_.frames.push_back(std::move(f));
        return id;
    }

    // A joint of the table between two bodies, its frames at their world poses,
    // its primitives along the base frame's axes.
    void add_joint(const SimscapeJointType& type, const std::string& id, const std::string& name, int base,
                   const Eigen::Isometry3d& base_world, int follower, const Eigen::Isometry3d& follower_world) {
        mbx_memory::Constraint c;
        c.id = id;
        c.name = name;
        c.base_frame_id = add_frame(base, id + "/base", name + " (base)", base_world);
        c.follower_frame_id = add_frame(follower, id + "/follower", name + " (follower)", follower_world);
        for (const SimscapePrimitive& p : type.chain) {
            mbx_memory::Primitive prim;
            prim.type = p.type;
            prim.axis_reference = MBX_AXIS_IN_BASE_FRAME;
            for (int k = 0; k < 3; ++k) prim.axis[k] = k == p.axis ? 1.0 : 0.0;
            c.chain.push_back(prim);
        }
        a_.constraints.push_back(std::move(c));
    }

    // Welds every part below a rigid sub-assembly, and the members of each
    // rigid group, to the first of them.
    void weld_rigid() {
        std::map<std::pair<int, std::string>, std::vector<int>> groups;
        for (size_t i = 0; i < m_.instances.size(); ++i) {
            const SimscapeInstance& in = m_.instances[i];
            if (in.rigid && in.part < 0) weld(leaves(int(i)), "rigid sub-assembly " + q(names_[i]), paths_[i]);
            if (!in.rigid_group.empty()) groups[{in.parent, in.rigid_group}].push_back(int(i));
        }
        for (const auto& [group, members] : groups) {
            std::vector<int> all;
            for (int i : members)
                for (int leaf : leaves(i)) all.push_back(leaf);
            const std::string scope = group.first >= 0 ? paths_[size_t(group.first)] + "/" : "";
            weld(all, "rigid group " + q(group.second), scope + "rigidGroup:" + group.second);
        }
    }

    void weld(const std::vector<int>& instances, const std::string& why, const std::string& id) {
        if (instances.size() < 2) return;
        const int first = body_of_[size_t(instances[0])];
        const Eigen::Isometry3d at = m_.instances[size_t(instances[0])].world;
        for (size_t k = 1; k < instances.size(); ++k) {
            const int other = body_of_[size_t(instances[k])];
            const std::string cid = id + "#" + std::to_string(k);
            mbx_memory::Constraint c;
            c.id = cid;
            c.name = why + ": " + a_.bodies[size_t(other)].name;
            c.base_frame_id = add_frame(first, cid + "/base", c.name + " (base)", at);
            c.follower_frame_id = add_frame(other, cid + "/follower", c.name + " (follower)", at);
            c.chain.push_back({MBX_PRIMITIVE_WELD, MBX_AXIS_IN_BASE_FRAME, {0, 0, 1}, false, 0, 0});
            a_.constraints.push_back(std::move(c));
        }
    }

    // The body a joint frame's path names (from the children of `scope`;
    // -1: the root assembly), the world datum for the root assembly's uid;
    // -1 with `why` set where it names none.
    int resolve(const SimscapeFrameRef& ref, int scope, Eigen::Isometry3d& world, std::string& why) {
        if (scope < 0 && ref.path.size() == 1 && ref.path[0] == m_.root_uid && !m_.root_uid.empty()) {
            world = isometry(ref.transform);
            return world_body();
        }
        int at = scope;
        for (const std::string& uid : ref.path) {
            const auto it = by_parent_uid_.find(key(at, uid));
            if (it == by_parent_uid_.end()) {
                why = "its instance path names " + q(uid) + ", which is no instance " +
                      (at < 0 ? std::string("of the root assembly") : "below " + q(names_[size_t(at)]));
                return -1;
            }
            at = it->second;
        }
        world = m_.instances[size_t(at)].world * isometry(ref.transform);
        if (body_of_[size_t(at)] >= 0) return body_of_[size_t(at)];
        // A sub-assembly instance: its first part carries the frame.
        const std::vector<int> below = leaves(at);
        if (below.empty()) {
            why = "its instance path names " + q(names_[size_t(at)]) + ", which holds no part";
            return -1;
        }
        return body_of_[size_t(below.front())];
    }

    int world_body() {
        if (world_ >= 0) return world_;
        mbx_memory::Body b;
        b.id = m_.root_uid;
        b.name = m_.root_name.empty() ? "world" : m_.root_name + " (world)";
        b.flags = MBX_BODY_GROUND | MBX_BODY_HELPER;
        b.units = units_;
        b.pose = pose_of(Eigen::Isometry3d::Identity());
        world_ = int(a_.bodies.size());
        a_.bodies.push_back(std::move(b));
        return world_;
    }

    void add_joints(const SimscapeMechanism& mech, int scope, const std::string& prefix) {
        for (const SimscapeJoint& j : mech.joints) {
            std::string id = prefix + j.name;
            if (j.name.empty() || !joint_ids_.insert(id).second) {
                // (unnamed or repeated: numbered in file order, which a re-export keeps)
                const std::string base = prefix + (j.name.empty() ? j.type : j.name);
                int n = 2;
                while (!joint_ids_.insert(base + "#" + std::to_string(n)).second) ++n;
                id = base + "#" + std::to_string(n);
            }
            const SimscapeJointType* type = simscape_joint_type(j.type);
            if (!type) {
                diagnostic(MBX_SEVERITY_WARNING, "simscape_unknown_joint", MBX_SUBJECT_CONSTRAINT, id, j.name, j.line,
                           "joint " + q(j.name) + " is a <" + j.type + ">, which mbx does not know (it knows " +
                               simscape_joint_type_names() + "); it is left out");
                continue;
            }
            Eigen::Isometry3d base_world, follower_world;
            std::string why;
            const int base = resolve(j.base, scope, base_world, why);
            const int follower = base >= 0 ? resolve(j.follower, scope, follower_world, why) : -1;
            if (base < 0 || follower < 0) {
                diagnostic(MBX_SEVERITY_WARNING, "simscape_joint_unresolved", MBX_SUBJECT_CONSTRAINT, id, j.name,
                           base < 0 ? j.base.line : j.follower.line,
                           j.type + " joint " + q(j.name) + ": " + why + "; the joint is left out");
                continue;
            }
            add_joint(*type, id, j.name.empty() ? id : j.name, base, base_world, follower, follower_world);
        }
        if (!mech.mates.empty() && mech.joints.empty()) joints_from_mates(mech, scope, prefix);
    }

    // Where an export gives mates and no joints (SolidWorks, Creo, Inventor):
    // the mates between each pair of parts make one joint (mate_inference.h).
    // A mate's geometry is given in its instance's frame, as a joint frame is.
    void joints_from_mates(const SimscapeMechanism& mech, int scope, const std::string& prefix) {
        struct Pair {
            int base = -1, follower = -1;
            std::vector<Mate> mates;
            std::vector<const SimscapeMate*> source;
        };
        std::map<std::pair<int, int>, Pair> pairs;
        std::vector<std::pair<int, int>> order;  // pairs in the file's order
        double length = 0;
        for (const SimscapeInstance& in : m_.instances) length = std::max(length, in.world.translation().norm());
        length = std::max(2 * length, 1e-3);
        for (const SimscapeMate& mate : mech.mates) {
            const std::string who = mate.type + " mate '" + mate.name + "'";
            if (mate.geometry.size() != 2) {
                diagnostic(MBX_SEVERITY_WARNING, "simscape_mate_unread", MBX_SUBJECT_FILE, m_.file, mate.name, mate.line,
                           who + " has " + std::to_string(mate.geometry.size()) +
                               " geometries where two belong; it is left out");
                continue;
            }
            int body[2];
            Mate m;
            m.type = mate.type;
            m.name = mate.name;
            m.line = mate.line;
            bool ok = true;
            for (int k = 0; k < 2 && ok; ++k) {
                const SimscapeMateGeometry& g = mate.geometry[size_t(k)];
                Eigen::Isometry3d world;
                std::string why;
                body[k] = g.at.path.empty() ? -1 : resolve(g.at, scope, world, why);
                if (body[k] < 0) {
                    diagnostic(MBX_SEVERITY_WARNING, "simscape_mate_unread", MBX_SUBJECT_FILE, m_.file, mate.name, g.line,
                               who + ": " + (why.empty() ? std::string("a geometry names no instance") : why) +
                                   "; it is left out");
                    ok = false;
                    break;
                }
                // The geometry in the instance's frame (the path's transform, usually none, before it).
                MateGeometry& out = k == 0 ? m.first : m.second;
                out.type = g.geom_type;
                out.position = world * g.position;
                out.axis = world.linear() * g.axis;
            }
            if (!ok) continue;
            if (body[0] == body[1]) {
                diagnostic(MBX_SEVERITY_WARNING, "simscape_mate_unread", MBX_SUBJECT_FILE, m_.file, mate.name, mate.line,
                           who + " joins a part to itself; it is left out");
                continue;
            }
            const std::pair<int, int> key(std::min(body[0], body[1]), std::max(body[0], body[1]));
            auto [it, added] = pairs.try_emplace(key);
            if (added) {
                it->second.base = body[0];
                it->second.follower = body[1];
                order.push_back(key);
            }
            if (body[0] != it->second.base) std::swap(m.first, m.second);
            it->second.mates.push_back(std::move(m));
            it->second.source.push_back(&mate);
        }
        for (const auto& key : order) {
            const Pair& pair = pairs[key];
            std::vector<MateProblem> problems;
            const InferredJoint joint = infer_joint(pair.mates, length, problems);
            std::string names;
            for (const Mate& m : pair.mates) names += (names.empty() ? "" : ", ") + m.name;
            const std::string between =
                "'" + a_.bodies[size_t(pair.base)].name + "' and '" + a_.bodies[size_t(pair.follower)].name + "'";
            const std::string id = prefix + "mates:" + a_.bodies[size_t(pair.base)].id + "~" + a_.bodies[size_t(pair.follower)].id;
            for (const MateProblem& p : problems)
                diagnostic(p.error ? MBX_SEVERITY_ERROR : MBX_SEVERITY_WARNING,
                           p.error ? "simscape_mate_impossible" : "simscape_mate_unread", MBX_SUBJECT_CONSTRAINT, id,
                           pair.source[size_t(p.mate)]->name, pair.source[size_t(p.mate)]->line, p.message);
            for (int r : joint.redundant)
                diagnostic(MBX_SEVERITY_WARNING, "simscape_mate_redundant", MBX_SUBJECT_CONSTRAINT, id,
                           pair.source[size_t(r)]->name, pair.source[size_t(r)]->line,
                           pair.mates[size_t(r)].type + " mate '" + pair.mates[size_t(r)].name + "' between " + between +
                               " holds nothing the mates before it do not");
            const SimscapeJointType* type = joint.type.empty() ? nullptr : simscape_joint_type(joint.type);
            if (!type) {
                if (joint.freedoms < 6)
                    diagnostic(MBX_SEVERITY_WARNING, "simscape_mates_no_joint", MBX_SUBJECT_CONSTRAINT, id, names,
                               pair.source.front()->line,
                               "the mates between " + between + " (" + names + ") leave " +
                                   std::to_string(joint.freedoms) +
                                   " freedoms that no joint type has; the parts are left unjoined by them");
                continue;
            }
            add_joint(*type, id, joint.type + " from mates " + names, pair.base, joint.frame, pair.follower, joint.frame);
        }
    }

    const SimscapeModel& m_;
    mbx_memory::Assembly a_;
    std::vector<SimscapeBodyPart> body_parts_;
    mbx_units units_{1, 1, 1};
    std::vector<std::string> paths_, names_;
    std::vector<int> body_of_;  // instance -> body, -1 for sub-assemblies
    std::unordered_map<std::string, int> by_parent_uid_;
    std::unordered_set<std::string> joint_ids_;
    int world_ = -1;
};

}  // namespace

SimscapeAssembly to_assembly(const SimscapeModel& model) { return Builder(model).run(); }

}  // namespace mbx_files
