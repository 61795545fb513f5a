// mbx's simulation model next to MuJoCo's model of mbx's own MJCF export:
// the coordinate map between the two (hinges and slides equal, a ball's
// rates turned into the MuJoCo body's axes), and the stand-in masses the
// export gives leaf joint nodes copied into the simulation model, so both
// describe the same bodies.
#pragma once
#include <random>

#include "tests/export/mujoco_helpers.h"
#include "sim/build_model.h"
#include "sim/data.h"

namespace simtest {

struct Pair {
    mbx::sim::Model model;
    xtest::MuJoCoRun run;
    // Per sim joint: MuJoCo joint id (-1 for a fixed joint).
    std::vector<int> mj_joint;
    // Per sim joint with a ball: rotation from mbx joint axes to MuJoCo body axes.
    std::vector<mbx::Mat3> ball_axes;
    Eigen::MatrixXd T;  // v_mujoco = T v_mbx

    // MuJoCo's qpos for an mbx position (a helper slide keeps its qpos0).
    Eigen::VectorXd mujoco_qpos(const Eigen::VectorXd& q) const {
        const mjModel* mm = run.model.get();
        Eigen::VectorXd qpos = Eigen::Map<const Eigen::VectorXd>(mm->qpos0, mm->nq);
        for (size_t k = 0; k < model.joints.size(); ++k) {
            const auto& j = model.joints[k];
            if (mj_joint[k] < 0) continue;
            double* x = qpos.data() + mm->jnt_qposadr[mj_joint[k]];
            if (j.kind == mbx::sim::JointKind::Spherical) {
                const mbx::Mat3& y = ball_axes[k];
                const Eigen::Quaterniond r(q[j.q_index], q[j.q_index + 1], q[j.q_index + 2], q[j.q_index + 3]);
                const Eigen::Quaterniond ball(mbx::Mat3(y * r.normalized().toRotationMatrix() * y.transpose()));
                x[0] = ball.w(), x[1] = ball.x(), x[2] = ball.y(), x[3] = ball.z();
            } else {
                for (int i = 0; i < j.nq(); ++i) x[i] = q[j.q_index + i];
            }
        }
        return qpos;
    }

    // MuJoCo's qpos/qvel from an mbx state.
    void to_mujoco(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
        mjModel* mm = run.model.get();
        mjData* md = run.data.get();
        const Eigen::VectorXd qpos = mujoco_qpos(q);
        for (int i = 0; i < mm->nq; ++i) md->qpos[i] = qpos[i];
        const Eigen::VectorXd vm = T * v;
        for (int i = 0; i < mm->nv; ++i) md->qvel[i] = vm[i];
    }
};

// A MuJoCo body's compiled inertial in its body frame.
inline mbx::sim::Inertia<double> mujoco_inertia(const mjModel* mm, int id) {
    REQUIRE(id >= 0);
    const Eigen::Quaterniond iq(mm->body_iquat[4 * id], mm->body_iquat[4 * id + 1], mm->body_iquat[4 * id + 2],
                                mm->body_iquat[4 * id + 3]);
    const mbx::Mat3 R = iq.normalized().toRotationMatrix();
    const mbx::Vec3 principal(mm->body_inertia[3 * id], mm->body_inertia[3 * id + 1], mm->body_inertia[3 * id + 2]);
    const mbx::Vec3 com(mm->body_ipos[3 * id], mm->body_ipos[3 * id + 1], mm->body_ipos[3 * id + 2]);
    return mbx::sim::Inertia<double>::from_com(mm->body_mass[id], com, R * principal.asDiagonal() * R.transpose());
}

// Builds both models of the translated mechanism.
inline Pair make_pair(xtest::Translated& t, const mbx_test::TempDir& dir, mbx::ExportSettings settings = {},
                      mbx::sim::BuildOptions options = {}) {
    Pair p{mbx::sim::build_model(*t.mechanism, options), xtest::load_mjcf(t, dir, settings), {}, {}, {}};
    const mbx::Mechanism& m = *t.mechanism;
    mjModel* mm = p.run.model.get();
    // Same bodies: MuJoCo's compiled inertials (the export's stand-in masses
    // of leaf nodes included, and what balanceinertia made of CAD inertias
    // that break the triangle inequality), so that both engines' algorithms
    // see the same numbers. sim_inertials_test checks build_model's own.
    for (const mbx::MjcfBody& b : p.run.layout.bodies) {
        if (b.body < 0) continue;
        const int sb = p.model.body_of_source[size_t(b.body)];
        REQUIRE(sb > 0);
        p.model.bodies[size_t(sb)].inertia = mujoco_inertia(mm, mj_name2id(mm, mjOBJ_BODY, b.name.c_str()));
    }
    // A prismatic cut's helper slider (layout body -1) hangs on the cut's
    // parent side; with its own slide at rest it rides rigidly on that body,
    // so its inertial belongs there (after the loop above set the parent's).
    for (const mbx::MjcfBody& b : p.run.layout.bodies) {
        if (b.body >= 0 || b.parent < 0) continue;
        const mbx::MjcfBody& parent = p.run.layout.bodies[size_t(b.parent)];
        REQUIRE(parent.body >= 0);
        const int sb = p.model.body_of_source[size_t(parent.body)];
        REQUIRE(sb > 0);
        const mbx::sim::Transform<double> local{b.local.rotation, b.local.position};
        p.model.bodies[size_t(sb)].inertia +=
            mujoco_inertia(mm, mj_name2id(mm, mjOBJ_BODY, b.name.c_str())).to_parent(local);
    }
    for (int k = 0; k < 3; ++k) mm->opt.gravity[k] = p.model.gravity[k];
    p.mj_joint.assign(p.model.joints.size(), -1);
    p.ball_axes.assign(p.model.joints.size(), mbx::Mat3::Identity());
    p.T = Eigen::MatrixXd::Zero(mm->nv, p.model.nv);
    for (size_t k = 0; k < p.model.joints.size(); ++k) {
        const auto& j = p.model.joints[k];
        if (j.kind == mbx::sim::JointKind::Fixed) continue;
        std::string name;
        const mbx::MjcfBody* owner = nullptr;
        for (const mbx::MjcfBody& b : p.run.layout.bodies) {
            if (j.kind == mbx::sim::JointKind::Free && b.free && b.body == p.model.bodies[size_t(j.body)].source) {
                name = b.free_name;
                owner = &b;
            }
            for (const mbx::MjcfJoint& mj : b.joints)
                if (mj.joint == j.source && j.source >= 0) name = mj.name, owner = &b;
        }
        REQUIRE_MESSAGE(!name.empty(), "no MuJoCo joint for " << j.name);
        const int id = mj_name2id(mm, mjOBJ_JOINT, name.c_str());
        REQUIRE(id >= 0);
        p.mj_joint[k] = id;
        const int dof = mm->jnt_dofadr[id];
        if (j.kind == mbx::sim::JointKind::Spherical) {
            const mbx::Joint& mjt = m.joints[size_t(j.source)];
            p.ball_axes[k] = m.bodies[size_t(owner->body)].pose.rotation.transpose() * m.bodies[size_t(mjt.parent)].pose.rotation;
            p.T.block(dof, j.v_index, 3, 3) = p.ball_axes[k];
        } else {
            p.T.block(dof, j.v_index, j.nv(), j.nv()).setIdentity();
        }
    }
    return p;
}

// A random state: angles within +-1.2 rad, slides within +-5 cm, random
// quaternions, rates within +-2.
inline void random_state(const mbx::sim::Model& m, std::mt19937& rng, Eigen::VectorXd& q, Eigen::VectorXd& v) {
    std::uniform_real_distribution<double> angle(-1.2, 1.2), shift(-0.05, 0.05), unit(-1, 1), rate(-2, 2);
    q = m.q_reference;
    v.resize(m.nv);
    for (int i = 0; i < m.nv; ++i) v[i] = rate(rng);
    for (const auto& j : m.joints) {
        double* x = q.data() + j.q_index;
        switch (j.kind) {
        case mbx::sim::JointKind::Revolute: x[0] = angle(rng); break;
        case mbx::sim::JointKind::Prismatic: x[0] = shift(rng); break;
        case mbx::sim::JointKind::Spherical:
        case mbx::sim::JointKind::Free: {
            const int o = j.kind == mbx::sim::JointKind::Free ? 3 : 0;
            if (o) for (int i = 0; i < 3; ++i) x[i] += shift(rng);
            const Eigen::Quaterniond r(Eigen::AngleAxisd(angle(rng), mbx::Vec3(unit(rng), unit(rng), unit(rng)).normalized()));
            const Eigen::Quaterniond base(x[o], x[o + 1], x[o + 2], x[o + 3]);
            const Eigen::Quaterniond n = base * r;
            x[o] = n.w(), x[o + 1] = n.x(), x[o + 2] = n.y(), x[o + 3] = n.z();
            break;
        }
        case mbx::sim::JointKind::Fixed: break;
        }
    }
}

}  // namespace simtest
