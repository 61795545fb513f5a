#include "modelica_support.h"

#include <cmath>
#include <memory>

namespace mtest {

using namespace mbx;

namespace {

const std::string kMB = "Modelica.Mechanics.MultiBody.";

std::string quoted(const std::string& s) { return "'" + s + "'"; }

bool close(const Pose& a, const Pose& b, double tol) {
    return (a.position - b.position).norm() <= tol && (a.rotation - b.rotation).cwiseAbs().maxCoeff() <= tol;
}

}  // namespace

const msl::Index& msl_index() {
    static const std::unique_ptr<msl::Index> index = std::make_unique<msl::Index>(MBX_MSL_INDEX);
    return *index;
}

const OutputFile* Package::file(const std::string& relative) const {
    return xtest::find_file(files, "modelica/" + name + "/" + relative);
}

Package export_package(xtest::Translated& t, ExportSettings settings) {
    Package p;
    ExportModel model = xtest::export_model(t, std::move(settings));
    p.files = export_files(model, MBX_EXPORT_MODELICA);
    p.notes = model.notes();
    for (size_t b = 0; b < t.mechanism->bodies.size(); ++b)
        if (model.has_mesh(int(b))) p.stems[int(b)] = model.mesh_stem(int(b));
    for (const OutputFile& f : p.files) {
        const std::string suffix = "/Mechanics.mo";
        if (f.path.rfind("modelica/", 0) == 0 && f.path.size() > suffix.size() &&
            f.path.compare(f.path.size() - suffix.size(), suffix.size(), suffix) == 0) {
            p.name = f.path.substr(9, f.path.size() - 9 - suffix.size());
            p.mechanics_text = f.contents;
        }
    }
    REQUIRE_FALSE(p.name.empty());
    p.mechanics = msl::parse_model(p.mechanics_text);
    return p;
}

int joint_of(const Mechanism& m, const msl::Component& c) {
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Joint& joint = m.joints[j];
        const std::string tag = "(constraint " + quoted(m.assembly.constraints[size_t(joint.constraint)].id) +
                                ", primitive " + std::to_string(joint.primitive_index) + ")";
        if (c.description.find(tag) != std::string::npos) return int(j);
    }
    return -1;
}

size_t count_class(const msl::Model& model, const std::string& class_name) {
    size_t n = 0;
    for (const msl::Component& c : model.components) n += c.class_name == class_name;
    return n;
}

namespace {

// Components standing for each dynamic body (by CAD id in the description).
std::map<int, const msl::Component*> body_components(const Mechanism& m, const msl::Model& model) {
    std::map<int, const msl::Component*> out;
    for (const msl::Component& c : model.components) {
        if (c.class_name != kMB + "Parts.Body") continue;
        for (size_t b = 0; b < m.bodies.size(); ++b) {
            if (m.bodies[b].kind != MBX_RIGID_BODY_DYNAMIC) continue;
            if (c.description.find("(id " + quoted(m.bodies[b].id)) != std::string::npos) {
                CHECK_MESSAGE(out.count(int(b)) == 0, "two Body components for " << m.bodies[b].name);
                out[int(b)] = &c;
            }
        }
    }
    return out;
}

void check_frames(const Mechanism& m, const Package& p, const std::map<int, const msl::Component*>& bodies,
                  const std::vector<Pose>& expected, const msl::FramePoses& frames, const char* what) {
    for (const auto& body_component : bodies) {
        // (the checks' lambdas cannot capture a structured binding)
        const int b = body_component.first;
        const msl::Component* c = body_component.second;
        const auto it = frames.pose.find(c->name + ".frame_a");
        if (it == frames.pose.end()) {
            FAIL_CHECK(what << ": " << c->name << " is not reachable from the world");
            continue;
        }
        CHECK_MESSAGE(close(it->second, expected[size_t(b)], 1e-9),
                      what << ": " << c->name << " at " << it->second.position.transpose() << " instead of "
                           << expected[size_t(b)].position.transpose());
    }
    // Visual shapes sit in their body's frame.
    for (const auto& body_stem : p.stems) {
        const int b = body_stem.first;
        const auto& stem = body_stem.second;
        const std::string uri = "modelica://" + p.name + "/Resources/Meshes/" + stem + ".stl";
        bool found = false;
        for (const msl::Component& c : p.mechanics.components) {
            if (c.class_name != kMB + "Visualizers.FixedShape" || c.value("shapeType") != "\"" + uri + "\"") continue;
            found = true;
            const auto it = frames.pose.find(c.name + ".frame_a");
            REQUIRE_MESSAGE(it != frames.pose.end(), c.name << " is not reachable from the world");
            CHECK_MESSAGE(close(it->second, expected[size_t(b)], 1e-9), what << ": shape " << c.name << " misplaced");
        }
        CHECK_MESSAGE(found, "no FixedShape refers to " << uri << " (body " << m.bodies[size_t(b)].name << ")");
    }
}

}  // namespace

void check_package(xtest::Translated& t, const Package& p, bool strict_flange_names) {
    const Mechanism& m = *t.mechanism;
    const msl::Model& model = p.mechanics;

    const std::vector<std::string> errors = msl::check_model(msl_index(), model);
    for (const std::string& e : errors) FAIL_CHECK(e);

    // Package files.
    REQUIRE(p.file("package.mo"));
    REQUIRE(p.file("package.order"));
    REQUIRE(p.file("UserModel.mo"));
    CHECK(p.file("UserModel.mo")->keep_existing);
    CHECK_FALSE(p.file("Mechanics.mo")->keep_existing);
    CHECK(p.file("package.order")->contents == "Mechanics\nUserModel\n");
    const msl::Model user = msl::parse_model(p.file("UserModel.mo")->contents);
    CHECK(user.errors.empty());
    CHECK(user.within == p.name);
    CHECK(user.name == "UserModel");
    CHECK(user.extends == std::vector<std::string>{p.name + ".Mechanics"});
    CHECK(model.within == p.name);
    CHECK(model.name == "Mechanics");
    for (const auto& [b, stem] : p.stems) CHECK(p.file("Resources/Meshes/" + stem + ".stl"));

    // One Body per dynamic body, with the mechanism's mass data.
    size_t dynamic = 0;
    for (const RigidBody& b : m.bodies) dynamic += b.kind == MBX_RIGID_BODY_DYNAMIC;
    CHECK(count_class(model, kMB + "Parts.Body") == dynamic);
    const std::map<int, const msl::Component*> bodies = body_components(m, model);
    CHECK(bodies.size() == dynamic);
    for (const auto& [b, c] : bodies) {
        const RigidBody& body = m.bodies[size_t(b)];
        CAPTURE(body.name);
        CHECK(msl::parse_number(c->value("m")) == body.mass);
        CHECK((msl::parse_vector(c->value("r_CM")) - body.com).cwiseAbs().maxCoeff() <= 1e-14);
        const char* names[6] = {"I_11", "I_22", "I_33", "I_21", "I_31", "I_32"};
        const int rows[6] = {0, 1, 2, 1, 2, 2}, cols[6] = {0, 1, 2, 0, 0, 1};
        for (int k = 0; k < 6; ++k) {
            const double want = body.inertia(rows[k], cols[k]);
            const double got = msl::parse_number(c->value(names[k]));
            // number_text writes rounding noise below 1e-14 as 0.
            CHECK_MESSAGE(std::abs(got - want) <= (std::abs(want) < 1e-14 ? 1e-14 : 0.0), names[k]);
        }
    }

    // Planar loops: exactly one RevolutePlanarLoopConstraint each.
    size_t planar = 0;
    for (const Loop& loop : m.loops) planar += loop.planar;
    CHECK(count_class(model, kMB + "Joints.RevolutePlanarLoopConstraint") == planar);

    // Joint components: each mechanism joint (weld excepted) exactly once;
    // tree revolutes/prismatics expose axis and support on top-level flanges.
    std::map<int, const msl::Component*> joints;
    for (const msl::Component& c : model.components) {
        if (c.class_name.rfind(kMB + "Joints.", 0) != 0) continue;
        const int j = joint_of(m, c);
        REQUIRE_MESSAGE(j >= 0, c.name << " names no joint of the mechanism");
        CHECK_MESSAGE(joints.count(j) == 0, "joint " << m.joints[size_t(j)].name << " written twice");
        joints[j] = &c;
    }
    size_t actuated = 0;
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Joint& joint = m.joints[j];
        if (joint.type == MBX_PRIMITIVE_WELD) continue;
        REQUIRE_MESSAGE(joints.count(int(j)), "joint " << joint.name << " is missing");
        const msl::Component& c = *joints.at(int(j));
        const bool flanged = !joint.cut && (joint.type == MBX_PRIMITIVE_REVOLUTE || joint.type == MBX_PRIMITIVE_PRISMATIC) &&
                             c.class_name != kMB + "Joints.RevolutePlanarLoopConstraint";
        if (!flanged) {
            CHECK_FALSE(c.modifier("useAxisFlange"));
            continue;
        }
        ++actuated;
        const std::string flange = joint.type == MBX_PRIMITIVE_REVOLUTE
                                       ? "Modelica.Mechanics.Rotational.Interfaces.Flange_a"
                                       : "Modelica.Mechanics.Translational.Interfaces.Flange_a";
        for (const char* role : {"axis", "support"}) {
            // The top-level flange wired to this joint's flange: axis_<joint> / support_<joint>
            // unless a CAD name already took that (then with a numeric suffix).
            const std::string inner = c.name + "." + role;
            std::vector<std::string> tops;
            for (const auto& [a, b] : model.connects) {
                if (a == inner && b.find('.') == std::string::npos) tops.push_back(b);
                if (b == inner && a.find('.') == std::string::npos) tops.push_back(a);
            }
            REQUIRE_MESSAGE(tops.size() == 1, inner << " is wired to " << tops.size() << " top-level flanges");
            const msl::Component* f = model.find(tops[0]);
            REQUIRE(f);
            CHECK(f->class_name == flange);
            CHECK_MESSAGE(tops[0].rfind(std::string(role) + "_" + c.name, 0) == 0, tops[0] << " is not named after " << c.name);
            if (strict_flange_names) CHECK(tops[0] == std::string(role) + "_" + c.name);
        }
    }
    CHECK(count_class(model, "Modelica.Mechanics.Rotational.Interfaces.Flange_a") +
              count_class(model, "Modelica.Mechanics.Translational.Interfaces.Flange_a") ==
          2 * actuated);

    // Frame chain at zero coordinates: every body at its CAD pose, every loop closed.
    const msl::FramePoses zero = msl::compose_frames(model);
    for (const std::string& c : zero.conflicts) FAIL_CHECK("q = 0: " << c);
    check_frames(m, p, bodies, forward_kinematics(m, {}), zero, "q = 0");

    // Non-zero coordinates on the tree joints (loops left open): the axes and
    // their signs must agree with mbx's forward kinematics.
    std::vector<JointPosition> q(m.joints.size());
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const double s = (j % 2 ? -1.0 : 1.0) * (0.1 + 0.07 * double(j % 5));
        q[j].value = m.joints[j].type == MBX_PRIMITIVE_PRISMATIC ? 0.05 * s : s;
        q[j].rotation = Eigen::AngleAxisd(s, Vec3(1, 2, 3 + double(j % 3)).normalized());
    }
    const msl::JointMotion motion = [&](const msl::Component& c, Pose& a_to_b) {
        const int j = joint_of(m, c);
        if (j < 0 || m.joints[size_t(j)].cut) return false;
        const Joint& joint = m.joints[size_t(j)];
        if (joint.type == MBX_PRIMITIVE_SPHERICAL) {
            a_to_b.rotation = q[size_t(j)].rotation.toRotationMatrix();
            return true;
        }
        const Vec3 n = msl::parse_vector(c.value("n")).normalized();
        if (joint.type == MBX_PRIMITIVE_REVOLUTE) a_to_b.rotation = Eigen::AngleAxisd(q[size_t(j)].value, n).toRotationMatrix();
        else a_to_b.position = n * q[size_t(j)].value;
        return true;
    };
    const msl::FramePoses moved = msl::compose_frames(model, motion);
    for (const std::string& c : moved.conflicts) FAIL_CHECK("q != 0: " << c);
    check_frames(m, p, bodies, forward_kinematics(m, q), moved, "q != 0");
}

}  // namespace mtest
