// MJCF read back by MuJoCo 2.2: body poses from MuJoCo's own kinematics at
// random joint coordinates equal mbx's forward kinematics (node chains merged
// into one body, spherical joints as ball quaternions, floating roots), the
// inertials MuJoCo compiled equal mbx's, and names and limits arrive intact.
#include <cmath>
#include <random>

#include "export/common/names.h"
#include "mujoco_assemblies.h"
#include "mujoco_helpers.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

struct Case {
    std::string label;
    std::function<std::unique_ptr<xtest::Translated>()> open;
};

std::vector<Case> kinematic_cases() {
    std::vector<Case> cases;
    for (const std::string& name : mbx_stub::builtin_names())
        cases.push_back({name, [name] { return xtest::translate_builtin(name); }});
    cases.push_back({"spatial", [] { return xtest::translate(xtest::mjcf_assemblies::spatial()); }});
    // The committed samples: PMXML with VRML shapes, spherical and prismatic joints, loops.
    for (const auto& [folder, xml] : std::vector<std::pair<std::string, std::string>>{
             {"double_cardan", "double_cardan"},
             {"five_axis_arm", "five_axis_arm"},
             {"fourbar_imperial", "fourbar"},
             {"joints_showcase", "joints_showcase"}}) {
        const std::string path = std::string(MBX_SAMPLES_DIR) + "/" + folder + "/" + xml;
        cases.push_back({"sample " + folder, [path] {
                             mbx_files::FileAdapterOptions o;
                             o.shapes_path = path + "_a.wrl";
                             return xtest::translate_file(path + ".xml", o);
                         }});
    }
    return cases;
}

// The MuJoCo body holding joint j, and that joint's layout entry.
const MjcfJoint* find_joint(const MjcfLayout& layout, int j, const MjcfBody** owner) {
    for (const MjcfBody& b : layout.bodies)
        for (const MjcfJoint& mj : b.joints)
            if (mj.joint == j) {
                *owner = &b;
                return &mj;
            }
    return nullptr;
}

// Writes mbx coordinates into qpos. A ball's quaternion is the joint-frame
// rotation seen in the MuJoCo body's frame at qpos0: the joint frame has the
// tree parent's axes, so with R_p and R_b the world rotations of the parent
// and of the MuJoCo body at the assembly pose, q_ball = Y q Y^T, Y = R_b^T R_p.
void set_qpos(const xtest::MuJoCoRun& run, const Mechanism& m, const std::vector<JointPosition>& q) {
    mjModel* model = run.model.get();
    mju_copy(run.data->qpos, model->qpos0, model->nq);
    for (size_t j = 0; j < m.joints.size(); ++j) {
        const Joint& joint = m.joints[j];
        if (joint.cut) continue;
        const MjcfBody* owner = nullptr;
        const MjcfJoint* mj = find_joint(run.layout, int(j), &owner);
        REQUIRE(mj);
        const int id = mj_name2id(model, mjOBJ_JOINT, mj->name.c_str());
        REQUIRE(id >= 0);
        mjtNum* qpos = run.data->qpos + model->jnt_qposadr[id];
        if (joint.type == MBX_PRIMITIVE_SPHERICAL) {
            CHECK(model->jnt_type[id] == mjJNT_BALL);
            const Mat3 y = m.bodies[size_t(owner->body)].pose.rotation.transpose() *
                           m.bodies[size_t(joint.parent)].pose.rotation;
            const Eigen::Quaterniond ball(Mat3(y * q[j].rotation.toRotationMatrix() * y.transpose()));
            qpos[0] = ball.w();
            qpos[1] = ball.x();
            qpos[2] = ball.y();
            qpos[3] = ball.z();
        } else {
            CHECK(model->jnt_type[id] == (joint.type == MBX_PRIMITIVE_PRISMATIC ? mjJNT_SLIDE : mjJNT_HINGE));
            qpos[0] = q[j].value;
        }
    }
}

std::vector<JointPosition> random_coordinates(const Mechanism& m, std::mt19937& rng) {
    std::uniform_real_distribution<double> angle(-1.2, 1.2), shift(-0.05, 0.05), unit(-1, 1);
    std::vector<JointPosition> q(m.joints.size());
    for (size_t j = 0; j < m.joints.size(); ++j) {
        switch (m.joints[j].type) {
        case MBX_PRIMITIVE_REVOLUTE: q[j].value = angle(rng); break;
        case MBX_PRIMITIVE_PRISMATIC: q[j].value = shift(rng); break;
        case MBX_PRIMITIVE_SPHERICAL:
            q[j].rotation = Eigen::AngleAxisd(angle(rng), Vec3(unit(rng), unit(rng), unit(rng)).normalized());
            break;
        case MBX_PRIMITIVE_WELD: break;
        }
    }
    return q;
}

}  // namespace

TEST_CASE("MJCF: MuJoCo kinematics equal mbx forward kinematics at random coordinates") {
    for (const Case& c : kinematic_cases()) {
        CAPTURE(c.label);
        auto t = c.open();
        const Mechanism& m = *t->mechanism;
        mbx_test::TempDir dir("mbx_mjcf_fk");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        CHECK(run.load_message.empty());

        std::mt19937 rng(20240601);
        for (int trial = 0; trial < 6; ++trial) {
            // Trial 0: all coordinates zero, i.e. qpos0 is the CAD assembly pose.
            const std::vector<JointPosition> q =
                trial == 0 ? std::vector<JointPosition>(m.joints.size()) : random_coordinates(m, rng);
            set_qpos(run, m, q);
            mj_kinematics(run.model.get(), run.data.get());
            const std::vector<Pose> expected = forward_kinematics(m, q);
            int compared = 0;
            for (size_t b = 1; b < m.bodies.size(); ++b) {
                const int id = run.body_id(int(b));
                if (m.bodies[b].kind == MBX_RIGID_BODY_DYNAMIC) REQUIRE(id > 0);
                if (id <= 0) continue;  // a node merged into the body below it
                CAPTURE(m.bodies[b].name);
                CAPTURE(trial);
                const Pose got = run.pose(id);
                CHECK((got.position - expected[b].position).norm() < 1e-9);
                CHECK(xtest::rotation_error(got.rotation, expected[b].rotation) < 1e-9);
                ++compared;
            }
            CHECK(compared >= 3);
        }
    }
}

TEST_CASE("MJCF: node chains become several joints in one body, floating roots a free joint") {
    auto t = xtest::translate(xtest::mjcf_assemblies::spatial());
    const Mechanism& m = *t->mechanism;
    mbx_test::TempDir dir("mbx_mjcf_nodes");
    xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
    const mjModel* model = run.model.get();

    int nodes = 0, dynamic = 0;
    for (const RigidBody& b : m.bodies) {
        nodes += b.kind == MBX_RIGID_BODY_JOINT_NODE;
        dynamic += b.kind == MBX_RIGID_BODY_DYNAMIC;
    }
    REQUIRE(nodes == 2);  // universal and cylindrical joints
    CHECK(model->nbody == 1 + dynamic);  // world + dynamic bodies; the two nodes are merged away

    // crank: universal joint = two hinges; slider: slide then hinge; float: free.
    auto joints_of = [&](const std::string& body) {
        const int id = mj_name2id(model, mjOBJ_BODY, body.c_str());
        REQUIRE(id > 0);
        std::vector<int> types;
        for (int k = 0; k < model->body_jntnum[id]; ++k) types.push_back(model->jnt_type[model->body_jntadr[id] + k]);
        return types;
    };
    CHECK(joints_of("Crank") == std::vector<int>{mjJNT_HINGE, mjJNT_HINGE});
    CHECK(joints_of("Slider") == std::vector<int>{mjJNT_SLIDE, mjJNT_HINGE});
    CHECK(joints_of("Coupler") == std::vector<int>{mjJNT_BALL});
    CHECK(joints_of("Float") == std::vector<int>{mjJNT_FREE});
    CHECK(joints_of("Float_arm") == std::vector<int>{mjJNT_HINGE});
    // The arm is nested in the floating body.
    CHECK(model->body_parentid[mj_name2id(model, mjOBJ_BODY, "Float_arm")] == mj_name2id(model, mjOBJ_BODY, "Float"));
    CHECK(model->nq == 2 + 4 + 2 + 7 + 1);
    // Spherical cut s2 closes the loop with one connect.
    REQUIRE(model->neq == 1);
    CHECK(model->eq_type[0] == mjEQ_CONNECT);
}

TEST_CASE("MJCF: MuJoCo's compiled inertials equal mbx's mass, centre of mass and tensor") {
    for (const std::string& name : {std::string("six_axis_arm"), std::string("double_cardan")}) {
        CAPTURE(name);
        auto t = xtest::translate_builtin(name);
        const Mechanism& m = *t->mechanism;
        mbx_test::TempDir dir("mbx_mjcf_inertia");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        const mjModel* model = run.model.get();
        for (size_t b = 1; b < m.bodies.size(); ++b) {
            const RigidBody& rb = m.bodies[b];
            if (rb.kind != MBX_RIGID_BODY_DYNAMIC) continue;
            CAPTURE(rb.name);
            const int id = run.body_id(int(b));
            REQUIRE(id > 0);
            CHECK(std::fabs(model->body_mass[id] - rb.mass) < 1e-12 * rb.mass);
            const Vec3 ipos(model->body_ipos[3 * id], model->body_ipos[3 * id + 1], model->body_ipos[3 * id + 2]);
            CHECK((ipos - rb.com).norm() < 1e-12);
            // MuJoCo keeps principal moments and the principal axes as iquat.
            const mjtNum* iq = model->body_iquat + 4 * id;
            const Mat3 r = Eigen::Quaterniond(iq[0], iq[1], iq[2], iq[3]).normalized().toRotationMatrix();
            const Vec3 moments(model->body_inertia[3 * id], model->body_inertia[3 * id + 1],
                               model->body_inertia[3 * id + 2]);
            const Mat3 tensor = r * moments.asDiagonal() * r.transpose();
            CHECK((tensor - rb.inertia).norm() < 1e-9 * rb.inertia.norm());
        }
    }
}

TEST_CASE("MJCF: joint limits become ranges, names are sanitized, unique and escaped") {
    {
        auto t = xtest::translate_builtin("six_axis_arm");
        const Mechanism& m = *t->mechanism;
        mbx_test::TempDir dir("mbx_mjcf_limits");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        int limited = 0;
        for (size_t j = 0; j < m.joints.size(); ++j) {
            const Joint& joint = m.joints[j];
            const MjcfBody* owner = nullptr;
            const MjcfJoint* mj = find_joint(run.layout, int(j), &owner);
            REQUIRE(mj);
            CHECK(mj->name == sanitize_identifier(joint.name));  // no collisions in this model
            const int id = mj_name2id(run.model.get(), mjOBJ_JOINT, mj->name.c_str());
            REQUIRE(id >= 0);
            CHECK(bool(run.model->jnt_limited[id]) == joint.has_limits);
            if (!joint.has_limits) continue;
            ++limited;
            CHECK(run.model->jnt_range[2 * id] == joint.lower);
            CHECK(run.model->jnt_range[2 * id + 1] == joint.upper);
        }
        CHECK(limited > 0);
    }
    {
        auto t = xtest::translate(xtest::mjcf_assemblies::odd_names());
        mbx_test::TempDir dir("mbx_mjcf_names");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        const mjModel* model = run.model.get();
        std::vector<std::string> bodies, joints;
        for (int i = 1; i < model->nbody; ++i) bodies.push_back(mj_id2name(model, mjOBJ_BODY, i));
        for (int i = 0; i < model->njnt; ++i) joints.push_back(mj_id2name(model, mjOBJ_JOINT, i));
        CHECK(bodies == std::vector<std::string>{"Link_1", "link_1_2", "world_2", "body"});
        CHECK(joints == std::vector<std::string>{"hinge_1", "hinge_1_2", "Hinge_1_3", "_9_lives"});
        // Ground's geometry stays in MuJoCo's world; the CAD body named
        // "world" is a body of its own.
        ExportModel em = xtest::export_model(*t);
        CHECK(model->geom_bodyid[mj_name2id(model, mjOBJ_GEOM, em.mesh_stem(0).c_str())] == 0);
        CHECK(model->geom_bodyid[mj_name2id(model, mjOBJ_GEOM, "world")] == mj_name2id(model, mjOBJ_BODY, "world_2"));
    }
}

TEST_CASE("MJCF: every mesh geom sits on its own body, is visual only and leaves the inertials alone") {
    for (const std::string& name : mbx_stub::builtin_names()) {
        CAPTURE(name);
        auto t = xtest::translate_builtin(name);
        const Mechanism& m = *t->mechanism;
        mbx_test::TempDir dir("mbx_mjcf_geoms");
        xtest::MuJoCoRun run = xtest::load_mjcf(*t, dir);
        const mjModel* model = run.model.get();
        ExportModel em = xtest::export_model(*t);
        int meshes = 0;
        for (size_t b = 0; b < m.bodies.size(); ++b) {
            if (!em.has_mesh(int(b))) continue;
            ++meshes;
            const int mesh = mj_name2id(model, mjOBJ_MESH, em.mesh_stem(int(b)).c_str());
            REQUIRE(mesh >= 0);
            int geoms = 0;
            for (int g = 0; g < model->ngeom; ++g) {
                if (model->geom_dataid[g] != mesh) continue;
                ++geoms;
                CHECK(model->geom_type[g] == mjGEOM_MESH);
                CHECK(model->geom_bodyid[g] == run.body_id(int(b)));
                CHECK(model->geom_contype[g] == 0);
                CHECK(model->geom_conaffinity[g] == 0);
            }
            CHECK(geoms == 1);
        }
        CHECK(model->nmesh == meshes);
        CHECK(meshes > 0);
        // Geoms add no mass: each body weighs what mbx says.
        for (size_t b = 1; b < m.bodies.size(); ++b)
            if (m.bodies[b].kind == MBX_RIGID_BODY_DYNAMIC)
                CHECK(model->body_mass[run.body_id(int(b))] == mbx_test::relative(m.bodies[b].mass, 1e-12));
    }
}
}  // namespace MBX_UNITY_ID
