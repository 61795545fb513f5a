#include "mechanism_builder.h"

#include <set>
#include <stdexcept>

namespace mbx_samples {

PmxmlPrimitive weld() { return {"weld", Eigen::Vector3d::Constant(0.57735)}; }
PmxmlPrimitive revolute(const Eigen::Vector3d& axis) { return {"revolute", axis.normalized()}; }
PmxmlPrimitive prismatic(const Eigen::Vector3d& axis) { return {"prismatic", axis.normalized()}; }
// Exporters still write an axis; a spherical primitive has none to give.
PmxmlPrimitive spherical() { return {"spherical", Eigen::Vector3d::UnitZ()}; }

MechanismBuilder::MechanismBuilder(const std::string& model_name, const PmxmlUnits& units, double density)
    : density_(density) {
    doc_.model_name = model_name;
    doc_.units = units;
    doc_.subsystems.push_back(PmxmlSubsystem{model_name, model_name, {}, {}, {}});
    subsystems_.push_back(SubsystemInfo{});
    subsystems_[0].root_part = new_body(0, "RootPart", Eigen::Isometry3d::Identity(), true);
}

int MechanismBuilder::new_body(int subsystem, const std::string& name, const Eigen::Isometry3d& cs1, bool helper) {
    const PmxmlSubsystem& s = doc_.subsystems[size_t(subsystem)];
    PmxmlBody b;
    b.name = name;
    if (helper) b.node_id = s.node_id + "/RootPart";
    else b.node_id = subsystem == 0 ? std::to_string(next_node_++) : s.node_id + "/" + std::to_string(next_node_++);
    PmxmlFrame cg, frame;
    cg.name = "CG";
    cg.node_id = b.node_id + "::CG(AUTOGEN)";
    cg.position = cs1.translation();
    cg.rotation = cs1.linear();  // the CG frame always shares the part frame's axes
    frame.name = "CS1";
    frame.node_id = b.node_id + "::CS1(AUTOGEN)";
    frame.position = cs1.translation();
    frame.rotation = cs1.linear();
    b.frames = {cg, frame};
    doc_.bodies.push_back(std::move(b));
    const int index = int(doc_.bodies.size() - 1);
    doc_.subsystems[size_t(subsystem)].bodies.push_back(index);

    BodyInfo info;
    info.subsystem = subsystem;
    info.cs1 = cs1;
    info.cg = cs1.translation();
    info.helper = helper;
    info.placement.name = name;
    info.placement.pose = cs1;
    bodies_.push_back(std::move(info));
    return index;
}

void MechanismBuilder::set_mass(int body, const SolidProperties& p, const Eigen::Vector3d& color) {
    PmxmlBody& b = doc_.bodies[size_t(body)];
    BodyInfo& info = bodies_[size_t(body)];
    b.mass = density_ * p.volume;
    b.inertia = density_ * doc_.units.inertia_factor * p.inertia;
    b.volume = p.volume;
    b.area = p.area;
    b.has_color = true;
    b.color = color;
    info.mass = b.mass;
    info.cg = info.cs1 * p.centroid;
    b.frames[0].position = info.cg;
}

int MechanismBuilder::add_subsystem(int parent, const std::string& name, const Eigen::Isometry3d& placement) {
    const std::string parent_id = doc_.subsystems[size_t(parent)].node_id;
    const std::string node_id = parent == 0 ? std::to_string(next_node_++) : parent_id + "/" + std::to_string(next_node_++);
    doc_.subsystems.push_back(PmxmlSubsystem{name, node_id, {}, {}, {}});
    const int index = int(doc_.subsystems.size() - 1);
    doc_.subsystems[size_t(parent)].children.push_back(index);
    SubsystemInfo info;
    info.parent = parent;
    info.placement = placement;
    subsystems_.push_back(info);
    subsystems_[size_t(parent)].children.push_back(index);
    subsystems_[size_t(index)].root_part = new_body(index, "RootPart", placement, true);
    return index;
}

int MechanismBuilder::add_part(int subsystem, const std::string& name, const Eigen::Isometry3d& cs1,
                               std::vector<VrmlShape> shapes, const std::string& file_name) {
    const int b = new_body(subsystem, name, cs1, false);
    std::vector<const Solid*> solids;
    for (const VrmlShape& s : shapes) solids.push_back(&s.solid);
    set_mass(b, properties(solids), shapes.front().color);
    BodyInfo& info = bodies_[size_t(b)];
    info.placement.url = file_name;
    info.files.push_back(VrmlGeometryFile{file_name, name, std::move(shapes)});
    return b;
}

int MechanismBuilder::add_rigid_assembly(int subsystem, const std::string& name, const Eigen::Isometry3d& cs1,
                                         std::vector<SubPart> parts) {
    const int b = new_body(subsystem, name, cs1, false);
    // The body's mass data is that of all its parts, in the body frame.
    std::vector<Solid> in_body;
    for (const SubPart& p : parts)
        for (const VrmlShape& s : p.shapes) in_body.push_back(transformed(s.solid, p.pose));
    std::vector<const Solid*> solids;
    for (const Solid& s : in_body) solids.push_back(&s);
    set_mass(b, properties(solids), parts.front().shapes.front().color);
    BodyInfo& info = bodies_[size_t(b)];
    info.placement.type = "assembly";
    for (SubPart& p : parts) {
        VrmlPlacement child;
        child.name = p.name;
        child.pose = p.pose;
        child.url = p.file_name;
        info.placement.children.push_back(child);
        info.files.push_back(VrmlGeometryFile{p.file_name, p.name, std::move(p.shapes)});
    }
    return b;
}

int MechanismBuilder::add_shared_part(int subsystem, const std::string& name, const Eigen::Isometry3d& cs1,
                                      const SolidProperties& unit_density, const std::string& url,
                                      const Eigen::Vector3d& color) {
    const int b = new_body(subsystem, name, cs1, false);
    set_mass(b, unit_density, color);
    bodies_[size_t(b)].placement.url = url;
    return b;
}

void MechanismBuilder::set_shape_in_place(int body, const VrmlShape& shape) {
    VrmlPlacement& p = bodies_[size_t(body)].placement;
    p.url.clear();
    p.shapes = {shape};
}

int MechanismBuilder::add_frame(int body, const Eigen::Vector3d& at, const std::string& joint_node_id) {
    PmxmlBody& b = doc_.bodies[size_t(body)];
    PmxmlFrame f;
    f.ref = next_ref_++;
    f.name = "CS" + std::to_string(b.frames.size());
    f.node_id = joint_node_id + "::" + b.node_id + "(AUTOGEN)";
    f.position = at;
    b.frames.push_back(f);
    return f.ref;
}

int MechanismBuilder::common_subsystem(int a, int b) const {
    std::set<int> above_a;
    for (int s = bodies_[size_t(a)].subsystem; s >= 0; s = subsystems_[size_t(s)].parent) above_a.insert(s);
    for (int s = bodies_[size_t(b)].subsystem; s >= 0; s = subsystems_[size_t(s)].parent)
        if (above_a.count(s)) return s;
    return 0;
}

void MechanismBuilder::add_joint(int base, int follower, const Eigen::Vector3d& at,
                                 std::vector<PmxmlPrimitive> primitives, const std::string& status) {
    if (finished_) throw std::logic_error("add_joint after finish");
    const PmxmlBody& b = doc_.bodies[size_t(base)];
    const PmxmlBody& f = doc_.bodies[size_t(follower)];
    PmxmlJoint j;
    j.name = b.name + "--" + f.name;
    j.node_id = b.node_id + ":-:" + f.node_id;
    j.status = status;
    j.base_ref = add_frame(base, at, j.node_id);
    j.follower_ref = add_frame(follower, at, j.node_id);
    j.primitives = std::move(primitives);
    joints_.push_back(JointInfo{base, follower, at, j.primitives});
    doc_.joints.push_back(std::move(j));
    // Stored where both bodies are visible, as exporters do.
    doc_.subsystems[size_t(common_subsystem(base, follower))].joints.push_back(int(doc_.joints.size() - 1));
}

void MechanismBuilder::weld_to_root_part(int subsystem, int body) {
    add_joint(root_part(subsystem), body, bodies_[size_t(body)].cs1.translation(), {weld()});
}

const PmxmlDocument& MechanismBuilder::finish() {
    if (finished_) return doc_;
    // RootParts carry the centre of mass of what they hold; the top one and
    // the ground frame sit on the assembly's (FORMAT_NOTES section 5.5).
    std::vector<double> mass(subsystems_.size(), 0);
    std::vector<Eigen::Vector3d> moment(subsystems_.size(), Eigen::Vector3d::Zero());
    for (const BodyInfo& b : bodies_) {
        if (b.helper) continue;
        for (int s = b.subsystem; s >= 0; s = subsystems_[size_t(s)].parent) {
            mass[size_t(s)] += b.mass;
            moment[size_t(s)] += b.mass * b.cg;
        }
    }
    for (size_t s = 0; s < subsystems_.size(); ++s) {
        const Eigen::Vector3d com =
            mass[s] > 0 ? Eigen::Vector3d(moment[s] / mass[s]) : Eigen::Vector3d(subsystems_[s].placement.translation());
        doc_.bodies[size_t(subsystems_[s].root_part)].frames[0].position = com;
    }
    const Eigen::Vector3d com = doc_.bodies[size_t(subsystems_[0].root_part)].frames[0].position;
    const PmxmlBody& root = doc_.bodies[size_t(subsystems_[0].root_part)];
    PmxmlJoint j;
    j.name = "RootGround--RootPart";
    j.node_id = root.node_id + ":-:RootGround";
    doc_.ground_frame.ref = next_ref_++;
    doc_.ground_frame.name = "CS1";
    doc_.ground_frame.node_id = root.node_id + ":-:RootGround::RootGround(AUTOGEN)";
    doc_.ground_frame.position = com;
    j.base_ref = doc_.ground_frame.ref;
    j.follower_ref = add_frame(subsystems_[0].root_part, com, j.node_id);
    j.primitives = {weld()};
    doc_.joints.push_back(j);
    doc_.subsystems[0].joints.push_back(int(doc_.joints.size() - 1));
    finished_ = true;
    return doc_;
}

VrmlPlacement MechanismBuilder::nested(int subsystem) const {
    const SubsystemInfo& s = subsystems_[size_t(subsystem)];
    const Eigen::Isometry3d to_local = s.placement.inverse();
    VrmlPlacement p;
    p.name = doc_.subsystems[size_t(subsystem)].name;
    p.type = "assembly";
    p.pose = s.placement;
    for (int b : doc_.subsystems[size_t(subsystem)].bodies) {
        if (bodies_[size_t(b)].helper) continue;
        VrmlPlacement child = bodies_[size_t(b)].placement;
        child.pose = to_local * child.pose;
        p.children.push_back(std::move(child));
    }
    for (int c : s.children) {
        VrmlPlacement child = nested(c);
        child.pose = to_local * child.pose;
        p.children.push_back(std::move(child));
    }
    return p;
}

VrmlAssembly MechanismBuilder::vrml(const std::string& file_name, double unit_in_model, bool nest_subsystems) const {
    VrmlAssembly a;
    a.file_name = file_name;
    a.title = doc_.model_name;
    a.unit_in_model = unit_in_model;
    if (nest_subsystems) {
        VrmlPlacement top = nested(0);
        a.placements = std::move(top.children);
    } else {
        for (const BodyInfo& b : bodies_)
            if (!b.helper) a.placements.push_back(b.placement);
    }
    for (const BodyInfo& b : bodies_)
        for (const VrmlGeometryFile& f : b.files) a.geometry.push_back(f);
    for (const VrmlGeometryFile& f : shared_files_) a.geometry.push_back(f);
    return a;
}

}  // namespace mbx_samples
