#include "export/modelica/mechanics_writer.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "export/common/names.h"
#include "export/common/number_text.h"
#include "export/modelica/model_text.h"
#include "export/modelica/modelica_text.h"

namespace mbx {

namespace {

const std::string kMultiBody = "Modelica.Mechanics.MultiBody.";
const std::string kWorld = kMultiBody + "World";
const std::string kBody = kMultiBody + "Parts.Body";
const std::string kFixedTranslation = kMultiBody + "Parts.FixedTranslation";
const std::string kFixedRotation = kMultiBody + "Parts.FixedRotation";
const std::string kRevolute = kMultiBody + "Joints.Revolute";
const std::string kPrismatic = kMultiBody + "Joints.Prismatic";
const std::string kSpherical = kMultiBody + "Joints.Spherical";
const std::string kPlanarLoopRevolute = kMultiBody + "Joints.RevolutePlanarLoopConstraint";
const std::string kFixedShape = kMultiBody + "Visualizers.FixedShape";
const std::string kTwoAxesVectors = kMultiBody + "Types.RotationTypes.TwoAxesVectors";
const std::string kRotationalFlange = "Modelica.Mechanics.Rotational.Interfaces.Flange_a";
const std::string kTranslationalFlange = "Modelica.Mechanics.Translational.Interfaces.Flange_a";

// Axes of a planar loop further from exact than this (rad) are reported when
// they are made exactly parallel; below it the change is CAD rounding.
constexpr double kPlanarSnapNote = 1e-9;

const char* type_word(mbx_primitive_type t) {
    switch (t) {
    case MBX_PRIMITIVE_REVOLUTE: return "revolute";
    case MBX_PRIMITIVE_PRISMATIC: return "prismatic";
    case MBX_PRIMITIVE_SPHERICAL: return "spherical";
    case MBX_PRIMITIVE_WELD: break;
    }
    return "weld";
}


// Two significant digits: world.nominalLength only scales the default
// animation of joints and frames.
double round_2_digits(double v) {
    if (!(v > 0)) return 1;
    const double scale = std::pow(10.0, std::floor(std::log10(v)) - 1);
    return std::round(v / scale) * scale;
}

class MechanicsBuilder {
public:
    MechanicsBuilder(ExportModel& model, const std::string& package)
        : model_(model), m_(model.mechanism()), package_(package) {}

    ModelicaModel build();
    // After build(): each joint's flange names ("" when it has none).
    std::vector<JointFlanges> flanges() const;

private:
    std::string claim(const std::string& base, const char* fallback);
    void claim_names();
    void claim_flange_names();
    bool has_flanges(int j) const;
    void plan_loops();
    void snap_planar_axes(int loop_index);
    void note_limits();
    void note_redundant_loops();

    void add_world();
    void add_ground();
    void add_body(int b);
    void add_cut_joint(int j);
    void add_shape(int b);
    void add_flanges();

    // Connects `from` to a fixed frame holding `pose` (nothing when identity)
    // and returns the connector that now carries the moved frame.
    std::string attach_fixed(const std::string& from, const Pose& pose, const std::string& name,
                             const std::string& description, bool animate, std::vector<ModelicaConnect>& into);
    // parent frame -> [offset] -> joint -> [offset] -> `to` (or the returned end when `to` is "").
    std::string add_joint_chain(int j, const std::string& from, const std::string& to,
                                std::vector<ModelicaConnect>& into);
    std::string joint_description(int j) const;
    void connect(std::vector<ModelicaConnect>& into, const std::string& a, const std::string& b);

    ExportModel& model_;
    const Mechanism& m_;
    std::string package_;
    NameTable names_;
    std::vector<std::string> body_name_;   // identifiers (ground and dynamic bodies)
    std::vector<std::string> joint_name_;
    std::vector<std::string> body_frame_;  // connector standing for each body's frame
    std::vector<Vec3> axis_;               // joint axis as written (joint frame)
    std::vector<char> in_loop_;
    std::vector<int> planar_loop_of_;      // joint -> planar loop it closes as RevolutePlanarLoopConstraint
    std::vector<char> needs_orientation_guess_;
    std::vector<std::array<std::string, 2>> flange_name_;  // axis_<joint>, support_<joint>

    ModelicaModel out_;
    std::vector<ModelicaConnect> tree_connects_, loop_connects_, shape_connects_, flange_connects_;
    std::vector<ModelicaComponent> flanges_;
};

std::string MechanicsBuilder::claim(const std::string& base, const char* fallback) {
    std::string s = sanitize_identifier(base, fallback);
    if (is_modelica_keyword(s)) s += "_";
    return names_.claim(s);
}

void MechanicsBuilder::claim_names() {
    // Fixed names and the names every class reference and the package path
    // start from must not be hidden by a component.
    for (const char* fixed : {"world", "Modelica", "ModelicaServices", "Complex", "Mechanics", "UserModel"})
        names_.reserve(fixed);
    names_.reserve(package_);
    // CAD names first, so a derived name ("crank_shape") never takes a part's own name.
    body_name_.assign(m_.bodies.size(), {});
    joint_name_.assign(m_.joints.size(), {});
    for (int b : model_.tree().order)
        if (m_.bodies[size_t(b)].kind != MBX_RIGID_BODY_JOINT_NODE)
            body_name_[size_t(b)] = claim(m_.bodies[size_t(b)].name, "body");
    for (size_t j = 0; j < m_.joints.size(); ++j) joint_name_[j] = claim(m_.joints[j].name, "joint");
}

bool MechanicsBuilder::has_flanges(int j) const {
    const Joint& joint = m_.joints[size_t(j)];
    return !joint.cut && planar_loop_of_[size_t(j)] < 0 &&
           (joint.type == MBX_PRIMITIVE_REVOLUTE || joint.type == MBX_PRIMITIVE_PRISMATIC);
}

void MechanicsBuilder::claim_flange_names() {
    // The flanges are the model's interface, so their names are claimed
    // before any derived name; only a CAD name can push them to a suffix.
    flange_name_.assign(m_.joints.size(), {});
    for (size_t j = 0; j < m_.joints.size(); ++j) {
        if (!has_flanges(int(j))) continue;
        flange_name_[j][0] = names_.claim("axis_" + joint_name_[j]);
        flange_name_[j][1] = names_.claim("support_" + joint_name_[j]);
    }
}

void MechanicsBuilder::plan_loops() {
    const size_t nj = m_.joints.size();
    axis_.resize(nj);
    for (size_t j = 0; j < nj; ++j) axis_[j] = model_.placement(int(j)).axis;
    in_loop_.assign(nj, 0);
    planar_loop_of_.assign(nj, -1);
    for (const Loop& loop : m_.loops)
        for (int j : loop.joints) in_loop_[size_t(j)] = 1;
    for (size_t li = 0; li < m_.loops.size(); ++li) {
        const Loop& loop = m_.loops[li];
        if (!loop.planar) continue;
        snap_planar_axes(int(li));
        if (m_.joints[size_t(loop.cut_joint)].type == MBX_PRIMITIVE_REVOLUTE)
            planar_loop_of_[size_t(loop.cut_joint)] = int(li);
    }
    // MSL has no planar-loop prismatic joint. The loop may be closed by any of
    // its revolutes (Modelica does not care which joint the tree cut), so one
    // of the loop's tree revolutes takes the role and gives up its flange.
    for (size_t li = 0; li < m_.loops.size(); ++li) {
        const Loop& loop = m_.loops[li];
        if (!loop.planar) continue;
        const Joint& cut = m_.joints[size_t(loop.cut_joint)];
        if (cut.type == MBX_PRIMITIVE_REVOLUTE) continue;
        int chosen = -1;
        for (int j : loop.joints) {
            const Joint& joint = m_.joints[size_t(j)];
            if (!joint.cut && joint.type == MBX_PRIMITIVE_REVOLUTE && planar_loop_of_[size_t(j)] < 0) {
                chosen = j;
                break;
            }
        }
        const std::string title = "planar loop " + std::to_string(li);
        if (chosen < 0) {
            model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, Subject::loop("loop" + std::to_string(li)),
                        title + " is cut at " + std::string(type_word(cut.type)) + " joint '" + cut.name +
                            "' and has no free revolute to carry MSL's RevolutePlanarLoopConstraint; its 3 "
                            "out-of-plane equations stay redundant and a Modelica tool may reject the model");
            continue;
        }
        planar_loop_of_[size_t(chosen)] = int(li);
        const Joint& joint = m_.joints[size_t(chosen)];
        model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, Subject::loop("loop" + std::to_string(li)),
                    title + " is cut at " + std::string(type_word(cut.type)) + " joint '" + cut.name +
                        "', but MSL has only a revolute planar-loop constraint: revolute '" + joint.name +
                        "' is written as Joints.RevolutePlanarLoopConstraint and has no axis flange");
    }
}

void MechanicsBuilder::note_redundant_loops() {
    // Redundancy beyond the planar out-of-plane equations (spherical loops,
    // special geometry) has no MSL joint that removes it.
    for (size_t li = 0; li < m_.loops.size(); ++li) {
        const Loop& loop = m_.loops[li];
        const int extra = loop.redundant - (loop.planar ? 3 : 0);
        if (extra <= 0) continue;
        model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, Subject::loop("loop" + std::to_string(li)),
                    "loop " + std::to_string(li) + " (cut joint '" + m_.joints[size_t(loop.cut_joint)].name + "') has " +
                        std::to_string(extra) +
                        " redundant closure equations that no MSL joint removes (RevolutePlanarLoopConstraint "
                        "covers planar loops only); a Modelica tool will likely report a singular system there");
    }
}

void MechanicsBuilder::snap_planar_axes(int loop_index) {
    // RevolutePlanarLoopConstraint asserts that the loop stays planar to
    // 1e-10 m; axes parallel only within the planarity tolerance would drift
    // out of plane as the loop moves, so they are written exactly parallel.
    const Loop& loop = m_.loops[size_t(loop_index)];
    const Vec3 normal = loop.planar_normal.normalized();
    double largest = 0;
    for (int j : loop.joints) {
        const Joint& joint = m_.joints[size_t(j)];
        const Vec3 n = m_.bodies[size_t(joint.parent)].pose.rotation.transpose() * normal;
        Vec3& a = axis_[size_t(j)];
        Vec3 snapped = a;
        if (joint.type == MBX_PRIMITIVE_REVOLUTE) {
            snapped = a.dot(n) >= 0 ? n : Vec3(-n);
        } else if (joint.type == MBX_PRIMITIVE_PRISMATIC) {
            const Vec3 in_plane = a - a.dot(n) * n;
            if (in_plane.norm() > 0.5) snapped = in_plane.normalized();
        }
        largest = std::max(largest, (snapped - a).norm());
        a = snapped;
    }
    if (largest > kPlanarSnapNote)
        model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION,
                    Subject::loop("loop" + std::to_string(loop_index)),
                    "planar loop " + std::to_string(loop_index) +
                        ": joint axes written exactly parallel to the loop normal (largest change " +
                        number_text(largest) + " rad), as MSL's RevolutePlanarLoopConstraint requires");
}

void MechanicsBuilder::note_limits() {
    std::string names;
    for (const Joint& joint : m_.joints) {
        if (!joint.has_limits) continue;
        names += (names.empty() ? "" : ", ") + quoted_identifier(joint.name);
    }
    if (names.empty()) return;
    model_.note(MBX_SEVERITY_WARNING, MBX_FINDING_EXPORT_APPROXIMATION, Subject::model(model_.settings().model_name),
                "Modelica MultiBody joints have no position limits; the limits of joints " + names +
                    " are not in the Modelica model");
}

void MechanicsBuilder::connect(std::vector<ModelicaConnect>& into, const std::string& a, const std::string& b) {
    into.push_back({{}, a, b});
}

std::string MechanicsBuilder::attach_fixed(const std::string& from, const Pose& pose, const std::string& name,
                                           const std::string& description, bool animate,
                                           std::vector<ModelicaConnect>& into) {
    if (is_identity_pose(pose)) return from;
    ModelicaComponent c;
    c.name = names_.claim(name);
    c.description = description;
    c.modifiers.emplace_back("r", modelica_vector(pose.position));
    if ((pose.rotation - Mat3::Identity()).cwiseAbs().maxCoeff() <= 1e-12) {
        c.class_name = kFixedTranslation;
    } else {
        c.class_name = kFixedRotation;
        c.modifiers.emplace_back("rotationType", kTwoAxesVectors);
        c.modifiers.emplace_back("n_x", modelica_vector(pose.rotation.col(0)));
        c.modifiers.emplace_back("n_y", modelica_vector(pose.rotation.col(1)));
    }
    if (!animate) c.modifiers.emplace_back("animation", "false");
    connect(into, from, c.name + ".frame_a");
    out_.components.push_back(std::move(c));
    return out_.components.back().name + ".frame_b";
}

std::string MechanicsBuilder::joint_description(int j) const {
    const Joint& joint = m_.joints[size_t(j)];
    std::string d = std::string(type_word(joint.type)) + " " + quoted_identifier(joint.name);
    if (joint.constraint >= 0 && size_t(joint.constraint) < m_.assembly.constraints.size())
        d += " (constraint " + quoted_identifier(m_.assembly.constraints[size_t(joint.constraint)].id) + ", primitive " +
             std::to_string(joint.primitive_index) + ")";
    const int planar = planar_loop_of_[size_t(j)];
    if (joint.cut)
        d += std::string(", cut joint closing ") + (planar >= 0 ? "planar " : "") + "loop " + std::to_string(joint.loop);
    else if (planar >= 0)
        d += ", closing planar loop " + std::to_string(planar);
    return d;
}

std::string MechanicsBuilder::add_joint_chain(int j, const std::string& from, const std::string& to,
                                              std::vector<ModelicaConnect>& into) {
    const Joint& joint = m_.joints[size_t(j)];
    const JointPlacement& p = model_.placement(j);
    const RigidBody& parent = m_.bodies[size_t(joint.parent)];
    const RigidBody& child = m_.bodies[size_t(joint.child)];
    // A frame drawn as a cylinder would only clutter a body that shows its mesh.
    const bool animate_parent_side = !model_.has_mesh(joint.parent);
    const bool animate_child_side = !model_.has_mesh(joint.child);
    const std::string& name = joint_name_[size_t(j)];
    std::string end;
    if (joint.type == MBX_PRIMITIVE_WELD) {
        end = attach_fixed(from, p.parent_to_joint * p.joint_to_child, name,
                           "weld " + quoted_identifier(joint.name) + ": frame of " + quoted_identifier(child.name) + " on " + quoted_identifier(parent.name),
                           animate_parent_side, into);
    } else {
        std::string at = attach_fixed(from, p.parent_to_joint, name + "_offset_a",
                                      "frame of joint " + quoted_identifier(joint.name) + " on " + quoted_identifier(parent.name),
                                      animate_parent_side, into);
        ModelicaComponent c;
        c.name = name;
        c.description = joint_description(j);
        const bool planar_constraint = planar_loop_of_[size_t(j)] >= 0;
        switch (joint.type) {
        case MBX_PRIMITIVE_REVOLUTE:
            c.class_name = planar_constraint ? kPlanarLoopRevolute : kRevolute;
            if (has_flanges(j)) c.modifiers.emplace_back("useAxisFlange", "true");
            c.modifiers.emplace_back("n", modelica_vector(axis_[size_t(j)]));
            break;
        case MBX_PRIMITIVE_PRISMATIC:
            c.class_name = kPrismatic;
            if (has_flanges(j)) c.modifiers.emplace_back("useAxisFlange", "true");
            c.modifiers.emplace_back("n", modelica_vector(axis_[size_t(j)]));
            break;
        default:
            c.class_name = kSpherical;
            // In a chain the relative rotation makes the better states (and
            // starts at the CAD pose); in a loop the joint must stay a pure
            // constraint or the states would be over-determined.
            if (!joint.cut && !in_loop_[size_t(j)]) c.modifiers.emplace_back("enforceStates", "true");
            break;
        }
        if (has_flanges(j)) {
            const bool rotational = joint.type == MBX_PRIMITIVE_REVOLUTE;
            for (int k = 0; k < 2; ++k) {
                ModelicaComponent f;
                f.class_name = rotational ? kRotationalFlange : kTranslationalFlange;
                f.name = flange_name_[size_t(j)][size_t(k)];
                f.description = std::string(k == 0 ? "drive" : "support (bearing)") + " flange of " +
                                type_word(joint.type) + " " + quoted_identifier(joint.name);
                connect(flange_connects_, name + (k == 0 ? ".axis" : ".support"), f.name);
                flanges_.push_back(std::move(f));
            }
        }
        connect(into, at, name + ".frame_a");
        out_.components.push_back(std::move(c));
        end = attach_fixed(name + ".frame_b", p.joint_to_child, name + "_offset_b",
                           "frame of " + quoted_identifier(child.name) + " in joint " + quoted_identifier(joint.name), animate_child_side,
                           into);
    }
    if (to.empty()) return end;
    if (end != to) connect(into, end, to);
    return to;
}

void MechanicsBuilder::add_world() {
    // World size for the default joint and frame animation: the spread of
    // body origins and joint points.
    Eigen::AlignedBox3d box;
    for (const RigidBody& b : m_.bodies) box.extend(b.pose.position);
    for (const Joint& j : m_.joints) box.extend(j.frame.position);
    ModelicaComponent w;
    w.inner = true;
    w.class_name = kWorld;
    w.name = "world";
    const MountingSpec& mounting = model_.settings().mounting;
    if (mounting.given && (mounting.tilt_x != 0 || mounting.tilt_y != 0)) {
        // The description's mounting tilt turns gravity in the base frame.
        const Vec3 n = tilted_gravity(Vec3(0, 0, -1), mounting);
        w.description = "gravity 9.81 m/s2 along -z turned by the mounting's tilt (the description file's <mounting>)";
        w.modifiers.emplace_back("n", "{" + number_text(n.x()) + ", " + number_text(n.y()) + ", " + number_text(n.z()) + "}");
    } else {
        w.description = "gravity 9.81 m/s2 along -z: the CAD assemblies are mostly z-up";
        w.modifiers.emplace_back("n", "{0, 0, -1}");
    }
    const double size = box.isEmpty() ? 0 : box.diagonal().norm();
    if (size > 0) w.modifiers.emplace_back("nominalLength", number_text(round_2_digits(size)));
    out_.components.push_back(std::move(w));
}

void MechanicsBuilder::add_ground() {
    const RigidBody& ground = m_.bodies[0];
    const size_t first = out_.components.size();
    // Ground is fixed: its mass does not matter, only its pose and geometry.
    body_frame_[0] = attach_fixed("world.frame_b", ground.pose, body_name_[0] + "_pose",
                                  "pose of the ground body " + quoted_identifier(ground.name) + " in the world",
                                  !model_.has_mesh(0), tree_connects_);
    add_shape(0);
    if (out_.components.size() > first) out_.components[first].comment = "Ground " + quoted_identifier(ground.name);
}

void MechanicsBuilder::add_shape(int b) {
    if (!model_.has_mesh(b)) return;
    const RigidBody& body = m_.bodies[size_t(b)];
    ModelicaComponent s;
    s.class_name = kFixedShape;
    s.name = names_.claim(body_name_[size_t(b)] + "_shape");
    s.description = "mesh of " + quoted_identifier(body.name);
    s.modifiers = {{"shapeType", modelica_string("modelica://" + package_ + "/" + modelica_mesh_path(model_, b))},
                   {"r_shape", "{0, 0, 0}"},
                   {"lengthDirection", "{1, 0, 0}"},
                   {"widthDirection", "{0, 1, 0}"},
                   {"length", "1"},
                   {"width", "1"},
                   {"height", "1"},
                   // extra = 0: the file is drawn unscaled, its coordinates in metres in frame_a.
                   {"extra", "0"}};
    connect(shape_connects_, body_frame_[size_t(b)], s.name + ".frame_a");
    out_.components.push_back(std::move(s));
}

void MechanicsBuilder::add_body(int b) {
    const RigidBody& body = m_.bodies[size_t(b)];
    const size_t first = out_.components.size();
    const bool dynamic = body.kind != MBX_RIGID_BODY_JOINT_NODE;
    const std::string frame = dynamic ? body_name_[size_t(b)] + ".frame_a" : std::string();
    if (body.parent_joint >= 0) {
        const int j = body.parent_joint;
        body_frame_[size_t(b)] =
            add_joint_chain(j, body_frame_[size_t(m_.joints[size_t(j)].parent)], frame, tree_connects_);
    } else {
        body_frame_[size_t(b)] = frame;
    }
    if (dynamic) {
        ModelicaComponent c;
        c.class_name = kBody;
        c.name = body_name_[size_t(b)];
        c.description = "body " + quoted_identifier(body.name) + " (id " + quoted_identifier(body.id) +
                        (body.parts.size() > 1 ? ", " + std::to_string(body.parts.size()) + " welded parts" : "") +
                        ")";
        // MSL: I_ij about the centre of mass, resolved in frame_a (the body frame).
        const Mat3& I = body.inertia;
        c.modifiers = {{"m", number_text(body.mass)},        {"r_CM", modelica_vector(body.com)},
                       {"I_11", number_text(I(0, 0))},       {"I_22", number_text(I(1, 1))},
                       {"I_33", number_text(I(2, 2))},       {"I_21", number_text(I(1, 0))},
                       {"I_31", number_text(I(2, 0))},       {"I_32", number_text(I(2, 1))}};
        const Vec3 angles = cardan_angles_123(body.pose.rotation);
        if (body.parent_joint < 0) {
            // A floating root: absolute states, starting (and at rest) at the CAD pose.
            c.modifiers.emplace_back("r_0(start = " + modelica_vector(body.pose.position) + ", each fixed = true)", "");
            c.modifiers.emplace_back("v_0(each fixed = true)", "");
            c.modifiers.emplace_back("angles_fixed", "true");
            c.modifiers.emplace_back("angles_start", modelica_vector(angles));
            c.modifiers.emplace_back("w_0_fixed", "true");
            c.modifiers.emplace_back("enforceStates", "true");
        } else if (needs_orientation_guess_[size_t(b)]) {
            // Below a spherical joint that stays a pure constraint, the
            // body's own orientation may become a state: start it at the CAD pose.
            c.modifiers.emplace_back("angles_start", modelica_vector(angles));
        }
        if (model_.has_mesh(b)) c.modifiers.emplace_back("animation", "false");
        out_.components.push_back(std::move(c));
        add_shape(b);
    }
    if (out_.components.size() > first)
        out_.components[first].comment = std::string(dynamic ? "Body " : "Joint node ") + quoted_identifier(body.name);
}

void MechanicsBuilder::add_cut_joint(int j) {
    const Joint& joint = m_.joints[size_t(j)];
    const size_t first = out_.components.size();
    add_joint_chain(j, body_frame_[size_t(joint.parent)], body_frame_[size_t(joint.child)], loop_connects_);
    if (out_.components.size() > first)
        out_.components[first].comment = "Cut joint " + quoted_identifier(joint.name) + " closing loop " + std::to_string(joint.loop);
}

void MechanicsBuilder::add_flanges() {
    if (flanges_.empty()) return;
    flanges_.front().comment = "Drive flanges of the tree joints (axis and bearing), for a mechatronic model";
    for (ModelicaComponent& f : flanges_) out_.components.push_back(std::move(f));
}

ModelicaModel MechanicsBuilder::build() {
    const size_t nb = m_.bodies.size();
    claim_names();
    plan_loops();
    claim_flange_names();
    note_limits();
    note_redundant_loops();

    needs_orientation_guess_.assign(nb, 0);
    for (size_t b = 1; b < nb; ++b) {
        for (int j = m_.bodies[b].parent_joint; j >= 0;) {
            const Joint& joint = m_.joints[size_t(j)];
            if (joint.type == MBX_PRIMITIVE_SPHERICAL && in_loop_[size_t(j)]) needs_orientation_guess_[b] = 1;
            const RigidBody& up = m_.bodies[size_t(joint.parent)];
            j = up.kind == MBX_RIGID_BODY_JOINT_NODE ? up.parent_joint : -1;
        }
    }

    const ExportSettings& settings = model_.settings();
    out_.header = "Generated by mbx from " + quoted_identifier(settings.model_name) +
                  ". Do not edit: every export rewrites this file.\n"
                  "Put your changes in UserModel.mo (it extends this model and mbx never overwrites it).";
    out_.within = package_;
    out_.name = "Mechanics";
    out_.description = "Multibody model of " + quoted_identifier(settings.model_name) + " (generated by mbx)";

    body_frame_.assign(nb, {});
    add_world();
    add_ground();
    for (int b : model_.tree().order)
        if (b != 0) add_body(b);
    for (size_t j = 0; j < m_.joints.size(); ++j)
        if (m_.joints[j].cut) add_cut_joint(int(j));
    add_flanges();

    const auto append = [this](std::vector<ModelicaConnect>& group, const char* comment) {
        if (group.empty()) return;
        group.front().comment = comment;
        for (ModelicaConnect& c : group) out_.connects.push_back(std::move(c));
    };
    append(tree_connects_, "Spanning tree: parent frame -> joint -> child frame");
    append(loop_connects_, "Loop closures (cut joints)");
    append(shape_connects_, "Visual shapes");
    append(flange_connects_, "Drive flanges");

    const double stop = settings.stop_time > 0 ? settings.stop_time : 10;
    out_.annotation = "experiment(StopTime = " + number_text(stop) + ", Interval = " + number_text(stop / 500) +
                      ", Tolerance = 1e-06)";
    return std::move(out_);
}

std::vector<JointFlanges> MechanicsBuilder::flanges() const {
    std::vector<JointFlanges> out(flange_name_.size());
    for (size_t j = 0; j < flange_name_.size(); ++j) out[j] = {flange_name_[j][0], flange_name_[j][1]};
    return out;
}

}  // namespace

std::string modelica_mesh_path(ExportModel& model, int body) {
    return "Resources/Meshes/" + model.mesh_stem(body) + ".stl";
}

std::string write_mechanics(ExportModel& model, const std::string& package, std::vector<JointFlanges>* flanges) {
    MechanicsBuilder builder(model, package);
    std::string text = format_model(builder.build());
    if (flanges) *flanges = builder.flanges();
    return text;
}

}  // namespace mbx
