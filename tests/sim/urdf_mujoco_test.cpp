// URDF as an input, against MuJoCo reading the same URDF itself: the mass
// matrix and inverse dynamics of mbx's model of a real robot description
// (the Franka Panda, Solo12) equal MuJoCo's at random states. MuJoCo fuses
// links joined by fixed joints and may order its coordinates otherwise, so
// coordinates are matched by joint name. mj_rne holds neither passive forces
// nor constraints (URDF damping, friction loss, limits, mimic), as mbx's
// model is compared without its description file.
#include <mujoco/mujoco.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "host_adapters/urdf/urdf_adapter.h"
#include "host_adapters/urdf/urdf_assembly.h"
#include "sim/build_model.h"
#include "sim/dynamics.h"
#include "tests/export/export_fixture.h"
#include "sim_mujoco_support.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"
#include "tests/common/temp_dir.h"
#include "tests/common/file_text.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

struct ModelFree {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataFree {
    void operator()(mjData* d) const { mj_deleteData(d); }
};

// MuJoCo's model of the URDF: without its visual and collision elements,
// whose package:// meshes MuJoCo cannot find and which carry no mass here.
std::unique_ptr<mjModel, ModelFree> mujoco_model(const std::string& urdf, const mbx_test::TempDir& dir,
                                                 const std::string& added = "") {
    std::string text = mbx_test::read_file(urdf);
    text = std::regex_replace(text, std::regex("<visual[\\s\\S]*?</visual>"), "");
    text = std::regex_replace(text, std::regex("<collision[\\s\\S]*?</collision>"), "");
    // MuJoCo wants Gazebo's implied "world" link declared.
    if (text.find("link=\"world\"") != std::string::npos && text.find("<link name=\"world\"") == std::string::npos)
        text = std::regex_replace(text, std::regex("(<robot[^>]*>)"), "$1<link name=\"world\"/>");
    // Elements the caller adds after <robot>'s opening tag (a floating base for MuJoCo).
    if (!added.empty()) text = std::regex_replace(text, std::regex("(<robot[^>]*>)"), "$1" + added);
    const std::string copy = dir.file("mujoco.urdf");
    std::ofstream(copy, std::ios::binary) << text;
    char error[1000] = "";
    std::unique_ptr<mjModel, ModelFree> m(mj_loadXML(copy.c_str(), nullptr, error, sizeof error));
    REQUIRE_MESSAGE(m, error);
    return m;
}

// mbx's and MuJoCo's mass matrix and inverse dynamics (mj_fullM, mj_rne) at
// random states, coordinates matched by joint name.
void compare_with_mujoco(const std::string& urdf, const mbx_files::FileInputOptions& options, int expected_nv) {
    mbx_test::TempDir dir("mbx_urdf_mujoco");
    const auto mj = mujoco_model(urdf, dir);
    std::unique_ptr<mjData, DataFree> d(mj_makeData(mj.get()));
    REQUIRE(mj->nv == expected_nv);

    std::shared_ptr<mbx_files::UrdfAdapter> adapter = mbx_files::UrdfAdapter::open(urdf, options);
    const auto t = xtest::translate_table(adapter->table(), adapter);
    sim::Model model = sim::build_model(*t->mechanism);
    REQUIRE(model.nv == mj->nv);
    REQUIRE(model.nq == mj->nq);

    // Each rigid body (links welded by fixed joints made one, as MuJoCo fuses
    // them) has the inertial MuJoCo compiled from the same file, in the same
    // frame: mass and centre of mass to rounding, the inertia to MuJoCo's
    // iterative diagonalisation (within 1e-6 of its largest entry: the
    // Panda's first link, whose two principal moments are 0.5 % apart, is off
    // by 6e-7, all else by less than 1e-7). The dynamics below run on MuJoCo's compiled
    // numbers, so that they test the kinematics and the algorithms to 1e-9.
    int checked = 0;
    for (size_t b = 1; b < model.bodies.size(); ++b) {
        sim::BodyT<double>& body = model.bodies[b];
        CAPTURE(body.id);
        const int id = mj_name2id(mj.get(), mjOBJ_BODY, body.id.c_str());
        REQUIRE(id > 0);
        const sim::Inertia<double> theirs = simtest::mujoco_inertia(mj.get(), id);
        const sim::Inertia<double>& mine = body.inertia;
        CHECK(mine.mass == mbx_test::relative(theirs.mass, 1e-12));
        CHECK((mine.h - theirs.h).norm() <= 1e-12 * std::max(1.0, theirs.h.norm()));
        CHECK((mine.I - theirs.I).cwiseAbs().maxCoeff() <= 1e-6 * theirs.I.cwiseAbs().maxCoeff());
        body.inertia = theirs;
        ++checked;
    }
    CHECK(checked == int(model.bodies.size()) - 1);

    // mbx coordinate -> MuJoCo's (hinges and slides only: one of each per joint).
    std::vector<int> dof(size_t(model.nv), -1), qpos(size_t(model.nq), -1);
    for (const auto& j : model.joints) {
        if (j.nv() == 0) continue;
        CAPTURE(j.constraint_id);
        REQUIRE(j.nv() == 1);
        const int id = mj_name2id(mj.get(), mjOBJ_JOINT, j.constraint_id.c_str());
        REQUIRE(id >= 0);
        dof[size_t(j.v_index)] = mj->jnt_dofadr[id];
        qpos[size_t(j.q_index)] = mj->jnt_qposadr[id];
    }

    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    const int n = mj->nv;
    sim::Data data(model);
    std::vector<mjtNum> dense(size_t(n) * size_t(n)), rne(static_cast<size_t>(n));
    for (int sample = 0; sample < 5; ++sample) {
        Eigen::VectorXd q(model.nq), v(model.nv), a(model.nv);
        for (int k = 0; k < model.nq; ++k) q[k] = 0.3 * u(rng);
        for (int k = 0; k < model.nv; ++k) v[k] = u(rng), a[k] = u(rng);
        for (int k = 0; k < model.nq; ++k) d->qpos[qpos[size_t(k)]] = q[k];
        for (int k = 0; k < model.nv; ++k) d->qvel[dof[size_t(k)]] = v[k];
        mj_forward(mj.get(), d.get());
        mj_fullM(mj.get(), dense.data(), d->qM);
        for (int k = 0; k < model.nv; ++k) d->qacc[dof[size_t(k)]] = a[k];
        mj_rne(mj.get(), d.get(), 1, rne.data());

        data.q = q;
        data.v = v;
        sim::update_kinematics(model, data);
        sim::mass_matrix(model, data);
        Eigen::VectorXd tau;
        sim::inverse_dynamics(model, data, a, tau);
        double scale = 0, tau_scale = 0;
        for (double x : dense) scale = std::max(scale, std::abs(x));
        for (double x : rne) tau_scale = std::max(tau_scale, std::abs(x));
        for (int r = 0; r < n; ++r) {
            CAPTURE(r);
            for (int c = 0; c < n; ++c)
                CHECK(data.M(r, c) ==
                      mbx_test::within(dense[size_t(dof[size_t(r)] * n + dof[size_t(c)])], 1e-9 * scale, "MuJoCo's"));
            CHECK(tau[r] == mbx_test::within(rne[size_t(dof[size_t(r)])], 1e-9 * tau_scale, "MuJoCo's"));
        }
    }
}

}  // namespace

TEST_CASE("urdf input: the Franka Panda's URDF gives MuJoCo's mass matrix and inverse dynamics") {
    const std::string robots = mbx_test::shared_data("urdf");
    mbx_files::FileInputOptions o;
    o.package_paths.push_back({"example-robot-data/robots", robots});
    // Seven revolute joints and the two finger slides (the second mimics the first in the file).
    compare_with_mujoco(robots + "/panda_description/urdf/panda.urdf", o, 9);
}

TEST_CASE("urdf input: Solo12's URDF, its base fixed, gives MuJoCo's mass matrix and inverse dynamics") {
    const std::string robots = mbx_test::shared_data("urdf");
    mbx_files::FileInputOptions o;
    o.package_paths.push_back({"example-robot-data/robots", robots});
    compare_with_mujoco(robots + "/solo_description/robots/solo12.urdf", o, 12);
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("urdf input: the DFKI acrobot's identified URDF (world implied, a fixed joint's zero axis) gives MuJoCo's dynamics") {
    const std::string urdf = mbx_test::shared_data("measured/dfki_double_pendulum_c0/identified_model_3.1_acrobot.urdf");
    compare_with_mujoco(urdf, {}, 2);
}

}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("urdf input: Solo12 with a floating base gives MuJoCo's dynamics with a free joint on its base") {
    const std::string robots = mbx_test::shared_data("urdf");
    const std::string urdf = robots + "/solo_description/robots/solo12.urdf";
    mbx_test::TempDir dir("mbx_urdf_floating");
    // MuJoCo's copy hangs the base on a floating joint from "world", which
    // MuJoCo's URDF import makes its free joint (its root is fixed otherwise).
    auto mj = mujoco_model(urdf, dir, "<link name=\"world\"/><joint name=\"floating_base\" type=\"floating\">"
                                      "<parent link=\"world\"/><child link=\"base_link\"/></joint>");
    std::unique_ptr<mjData, DataFree> d(mj_makeData(mj.get()));
    REQUIRE(mj->nv == 18);

    mbx_files::FileInputOptions o;
    o.package_paths.push_back({"example-robot-data/robots", robots});
    o.floating_base = true;
    std::shared_ptr<mbx_files::UrdfAdapter> adapter = mbx_files::UrdfAdapter::open(urdf, o);
    const auto t = xtest::translate_table(adapter->table(), adapter);
    sim::Model model = sim::build_model(*t->mechanism);
    REQUIRE(model.nv == 18);
    REQUIRE(model.nq == 19);
    // MuJoCo's compiled inertials, as above (the slides' massless nodes have no MuJoCo body).
    for (size_t b = 1; b < model.bodies.size(); ++b) {
        sim::BodyT<double>& rb = model.bodies[b];
        const int id = mj_name2id(mj.get(), mjOBJ_BODY, rb.id.c_str());
        if (id <= 0) continue;
        const sim::Inertia<double> theirs = simtest::mujoco_inertia(mj.get(), id);
        CHECK(rb.inertia.mass == mbx_test::relative(theirs.mass, 1e-12));
        rb.inertia = theirs;
    }

    // mbx's three slides along the world's axes and its ball are MuJoCo's free
    // joint: the base's position and its turn (the base starts at the world's
    // origin and axes), linear rates in the world, angular in the base.
    const int free = mj_name2id(mj.get(), mjOBJ_JOINT, "floating_base");
    REQUIRE(free >= 0);
    std::vector<int> dof(size_t(model.nv), -1), qpos(size_t(model.nq), -1);
    int slides = 0;
    for (const auto& j : model.joints) {
        if (j.nv() == 0) continue;
        if (j.constraint_id == mbx_files::kUrdfFloatingBaseId) {
            if (j.kind == sim::JointKind::Prismatic) {
                dof[size_t(j.v_index)] = mj->jnt_dofadr[free] + slides;
                qpos[size_t(j.q_index)] = mj->jnt_qposadr[free] + slides;
                ++slides;
            } else {
                REQUIRE(j.kind == sim::JointKind::Spherical);
                for (int k = 0; k < 3; ++k) dof[size_t(j.v_index + k)] = mj->jnt_dofadr[free] + 3 + k;
                for (int k = 0; k < 4; ++k) qpos[size_t(j.q_index + k)] = mj->jnt_qposadr[free] + 3 + k;
            }
            continue;
        }
        const int id = mj_name2id(mj.get(), mjOBJ_JOINT, j.constraint_id.c_str());
        REQUIRE(id >= 0);
        dof[size_t(j.v_index)] = mj->jnt_dofadr[id];
        qpos[size_t(j.q_index)] = mj->jnt_qposadr[id];
    }
    REQUIRE(slides == 3);

    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    const int n = mj->nv;
    sim::Data data(model);
    std::vector<mjtNum> dense(size_t(n) * size_t(n)), rne(static_cast<size_t>(n));
    for (int sample = 0; sample < 5; ++sample) {
        Eigen::VectorXd q = model.q_reference, v(model.nv), a(model.nv);
        for (const auto& j : model.joints) {
            if (j.kind == sim::JointKind::Revolute || j.kind == sim::JointKind::Prismatic) q[j.q_index] = 0.4 * u(rng);
            if (j.kind == sim::JointKind::Spherical) {
                const Eigen::Quaterniond r(Eigen::AngleAxisd(u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()));
                q[j.q_index] = r.w(), q[j.q_index + 1] = r.x(), q[j.q_index + 2] = r.y(), q[j.q_index + 3] = r.z();
            }
        }
        for (int k = 0; k < model.nv; ++k) v[k] = u(rng), a[k] = u(rng);
        for (int k = 0; k < model.nq; ++k) d->qpos[qpos[size_t(k)]] = q[k];
        for (int k = 0; k < model.nv; ++k) d->qvel[dof[size_t(k)]] = v[k];
        mj_forward(mj.get(), d.get());
        mj_fullM(mj.get(), dense.data(), d->qM);
        for (int k = 0; k < model.nv; ++k) d->qacc[dof[size_t(k)]] = a[k];
        mj_rne(mj.get(), d.get(), 1, rne.data());
        data.q = q;
        data.v = v;
        sim::update_kinematics(model, data);
        sim::mass_matrix(model, data);
        Eigen::VectorXd tau;
        sim::inverse_dynamics(model, data, a, tau);
        double scale = 0, tau_scale = 0;
        for (double x : dense) scale = std::max(scale, std::abs(x));
        for (double x : rne) tau_scale = std::max(tau_scale, std::abs(x));
        for (int r = 0; r < n; ++r) {
            CAPTURE(r);
            for (int c = 0; c < n; ++c)
                CHECK(data.M(r, c) ==
                      mbx_test::within(dense[size_t(dof[size_t(r)] * n + dof[size_t(c)])], 1e-9 * scale, "MuJoCo's"));
            CHECK(tau[r] == mbx_test::within(rne[size_t(dof[size_t(r)])], 1e-9 * tau_scale, "MuJoCo's"));
        }
    }
}

}  // namespace MBX_UNITY_ID
