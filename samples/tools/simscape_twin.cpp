// MechanismBuilder::simscape: a PMXML sample's assembly exported again the way
// a current CAD exporter writes it (Simscape Multibody second generation, a
// STEP file per part), so that the same mechanism arrives through both
// formats and the tests can hold one against the other.
#include <algorithm>
#include <cctype>
#include <functional>
#include <set>
#include <stdexcept>

#include "mechanism_builder.h"
#include "simscape_document.h"

namespace mbx_samples {
namespace {

double metres_per(const std::string& unit) {
    if (unit == "m") return 1;
    if (unit == "mm") return 1e-3;
    if (unit == "in") return 0.0254;
    throw std::invalid_argument("simscape twin: length unit '" + unit + "'");
}

double kilograms_per(const std::string& unit) {
    if (unit == "kg") return 1;
    if (unit == "lbm") return 0.45359237;
    throw std::invalid_argument("simscape twin: mass unit '" + unit + "'");
}

std::string file_stem(const std::string& name) {
    std::string out;
    for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) ? char(std::tolower(static_cast<unsigned char>(c))) : '_';
    return out;
}

// The last segment of a PMXML node id ("44/45" -> "45"): unique among siblings.
std::string own_id(const std::string& node_id) { return node_id.substr(node_id.rfind('/') + 1); }

Eigen::Isometry3d in_metres(Eigen::Isometry3d x, double to_m) {
    x.translation() *= to_m;
    return x;
}

// A rotation whose z axis is `z`, x the world axis least along it made normal.
Eigen::Matrix3d z_along(const Eigen::Vector3d& z) {
    Eigen::Vector3d hint = Eigen::Vector3d::Zero();
    Eigen::Vector3d::Index least;
    z.cwiseAbs().minCoeff(&least);
    hint[least] = 1;
    Eigen::Matrix3d r;
    r.col(2) = z.normalized();
    r.col(0) = (hint - hint.dot(r.col(2)) * r.col(2)).normalized();
    r.col(1) = r.col(2).cross(r.col(0));
    return r;
}

// The Simscape joint type of a PMXML primitive chain and its frame's axes in the world.
std::pair<std::string, Eigen::Matrix3d> joint_type(const std::vector<PmxmlPrimitive>& p, const std::string& name) {
    const auto parallel = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a.cross(b).norm() < 1e-12; };
    if (p.size() == 1 && p[0].name == "weld") return {"Weld", Eigen::Matrix3d::Identity()};
    if (p.size() == 1 && p[0].name == "spherical") return {"Spherical", Eigen::Matrix3d::Identity()};
    if (p.size() == 1 && p[0].name == "revolute") return {"Revolute", z_along(p[0].axis)};
    if (p.size() == 1 && p[0].name == "prismatic") return {"Prismatic", z_along(p[0].axis)};
    if (p.size() == 2 && p[0].name == "prismatic" && p[1].name == "revolute" && parallel(p[0].axis, p[1].axis))
        return {"Cylindrical", z_along(p[0].axis)};
    if (p.size() == 2 && p[0].name == "revolute" && p[1].name == "revolute" && std::abs(p[0].axis.dot(p[1].axis)) < 1e-12) {
        Eigen::Matrix3d r;
        r.col(0) = p[0].axis.normalized();
        r.col(1) = p[1].axis.normalized();
        r.col(2) = r.col(0).cross(r.col(1));
        return {"Universal", r};
    }
    throw std::invalid_argument("simscape twin: joint " + name + " has no Simscape joint type");
}

}  // namespace

SimscapeXmlDocument MechanismBuilder::simscape(const std::string& directory, const StepLengthUnit& step_unit) const {
    const double to_m = metres_per(doc_.units.length), to_kg = kilograms_per(doc_.units.mass);
    const double density = density_ * to_kg / (to_m * to_m * to_m);  // kg/m^3
    SimscapeXmlDocument d;
    d.root_name = doc_.model_name;
    d.root_uid = file_stem(doc_.model_name) + "-root";
    d.digits = 10;

    auto add_part = [&](const std::string& name, const std::string& uid, const std::vector<VrmlShape>& shapes) {
        std::vector<Solid> solids;
        for (const VrmlShape& shape : shapes) {
            Solid s = shape.solid;
            for (Eigen::Vector3d& v : s.vertices) v *= to_m;
            solids.push_back(std::move(s));
        }
        std::vector<const Solid*> list;
        for (const Solid& s : solids) list.push_back(&s);
        const SolidProperties p = properties(list);
        SimscapeXmlPart part;
        part.uid = uid;
        part.name = name;
        part.mass = density * p.volume;
        part.com = p.centroid;
        part.inertia = density * p.inertia;
        part.geometry_file = file_stem(name) + ".step";
        part.colour << shapes.front().color, 1;
        write_step_part(directory + "/" + part.geometry_file, name, solids, step_unit);
        d.parts.push_back(part);
        return part.uid;
    };

    std::set<int> grounded;
    for (const JointInfo& j : joints_)
        if (j.base == subsystems_[0].root_part) grounded.insert(j.follower);

    // Where each body's joints attach: the uids from the top down to the part
    // instance (a rigid sub-assembly's first part), and that instance's pose.
    std::vector<std::vector<std::string>> path(bodies_.size());
    std::vector<Eigen::Isometry3d> part_pose(bodies_.size(), Eigen::Isometry3d::Identity());
    std::vector<std::vector<std::string>> subsystem_path(subsystems_.size());

    std::function<std::vector<SimscapeXmlInstance>(int)> children_of = [&](int s) {
        const Eigen::Isometry3d to_local = subsystems_[size_t(s)].placement.inverse();
        std::vector<SimscapeXmlInstance> out;
        for (int b : doc_.subsystems[size_t(s)].bodies) {
            const BodyInfo& info = bodies_[size_t(b)];
            if (info.helper) continue;
            if (info.files.empty()) throw std::invalid_argument("simscape twin: body " + doc_.bodies[size_t(b)].name + " has no shapes");
            const std::string& name = doc_.bodies[size_t(b)].name;
            SimscapeXmlInstance instance;
            instance.uid = "M" + own_id(doc_.bodies[size_t(b)].node_id);
            instance.name = name + " <1>";
            instance.local = in_metres(to_local * info.cs1, to_m);
            instance.grounded = s == 0 && grounded.count(b);
            path[size_t(b)] = subsystem_path[size_t(s)];
            path[size_t(b)].push_back(instance.uid);
            part_pose[size_t(b)] = info.cs1;
            if (info.placement.type == "assembly") {
                // A rigid CAD sub-assembly: its parts inside one rigid instance.
                instance.rigid = true;
                instance.entity_uid = file_stem(name) + "-asm";
                d.assemblies.push_back({instance.entity_uid, name, {}});
                for (size_t k = 0; k < info.files.size(); ++k) {
                    const VrmlPlacement& child = info.placement.children[k];
                    SimscapeXmlInstance part;
                    part.uid = "M" + std::to_string(k + 1);
                    part.name = child.name + " <1>";
                    part.entity_uid = add_part(child.name, file_stem(child.name) + "-part", info.files[k].shapes);
                    part.local = in_metres(child.pose, to_m);
                    if (k == 0) {
                        path[size_t(b)].push_back(part.uid);
                        part_pose[size_t(b)] = info.cs1 * child.pose;
                    }
                    instance.children.push_back(part);
                }
            } else {
                instance.entity_uid = add_part(name, file_stem(name) + "-part", info.files[0].shapes);
            }
            out.push_back(instance);
        }
        for (int c : subsystems_[size_t(s)].children) {
            const std::string& name = doc_.subsystems[size_t(c)].name;
            SimscapeXmlInstance instance;
            instance.uid = "M" + own_id(doc_.subsystems[size_t(c)].node_id);
            instance.name = name + " <1>";
            instance.entity_uid = file_stem(name) + "-asm";
            instance.local = in_metres(to_local * subsystems_[size_t(c)].placement, to_m);
            subsystem_path[size_t(c)] = subsystem_path[size_t(s)];
            subsystem_path[size_t(c)].push_back(instance.uid);
            d.assemblies.push_back({instance.entity_uid, name, {}});
            instance.children = children_of(c);
            out.push_back(instance);
        }
        return out;
    };
    d.instances = children_of(0);

    // Joints where both bodies are visible, paths from there; RootPart welds
    // are the grounded flags above (a sub-assembly's RootPart holds nothing).
    for (const JointInfo& j : joints_) {
        if (bodies_[size_t(j.base)].helper || bodies_[size_t(j.follower)].helper) continue;
        const std::string name = doc_.bodies[size_t(j.base)].name + "--" + doc_.bodies[size_t(j.follower)].name;
        const auto [type, axes] = joint_type(j.primitives, name);
        Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
        at.linear() = axes;
        at.translation() = j.at;
        const int scope = common_subsystem(j.base, j.follower);
        const size_t depth = subsystem_path[size_t(scope)].size();
        auto frame = [&](int body) {
            SimscapeXmlFrame f;
            f.path.assign(path[size_t(body)].begin() + long(depth), path[size_t(body)].end());
            f.transform = in_metres(part_pose[size_t(body)].inverse() * at, to_m);
            return f;
        };
        SimscapeXmlJoint joint{type, name, frame(j.base), frame(j.follower)};
        if (scope == 0) {
            d.joints.push_back(joint);
            continue;
        }
        const std::string uid = file_stem(doc_.subsystems[size_t(scope)].name) + "-asm";
        for (SimscapeXmlAssembly& a : d.assemblies)
            if (a.uid == uid) a.joints.push_back(joint);
    }
    return d;
}

}  // namespace mbx_samples
