// The ContactNets cube tosses (../shared/data/measured/contactnets_cube, 570
// real tosses of a 0.1048 m, 0.37 kg wooden cube onto a board, tracked at
// 148 Hz) as the contact tests use them: the cube as an mbx model, the
// authors' nominal contact, and MuJoCo's rollout of a toss in the same run.
#pragma once
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>

#include "core/assembly/host_reader.h"
#include "calibration/simulation/contact_fit.h"
#include "contact_scenes.h"
#include "core/progress.h"
#include "host_adapters/memory/memory_host.h"
#include "sim/build_model.h"
#include "core/translator/translate.h"
#include "tests/common/shared_data.h"

namespace mbx_test {

constexpr double kCubeEdge = 0.1048, kCubeMass = 0.37, kCubeInertia = kCubeMass * kCubeEdge * kCubeEdge / 6;

inline std::string cube_tosses_path() { return mbx_test::shared_data("measured/contactnets_cube/cube_tosses.csv"); }

// The cube as a free body of a translated assembly (mbx's own pipeline;
// no doctest here, bench_contact uses it too).
struct CubeScene {
    mbx::sim::Model model;
    mbx::calibration::ContactScene scene;
    CubeScene() {
        mbx_memory::Host host(free_parts("cube", {{kCubeMass, kCubeInertia * mbx::Mat3::Identity(), mbx::Vec3::Zero()}}));
        mbx::Progress progress(nullptr, nullptr);
        mbx::Findings findings;
        mbx::Assembly assembly = mbx::read_host(host.table(), mbx::HostReadOptions{}, progress, findings);
        auto mechanism = mbx::translate_assembly(std::move(assembly), std::move(findings), mbx::TranslateOptions{}, progress);
        model = mbx::sim::build_model(*mechanism);
        scene.model = &model, scene.body = 1, scene.length_scale = kCubeEdge;
        scene.shapes = {ground_plane(), box_shape(1, kCubeEdge)};
        // Every tenth toss scores within 0.1 %-point of its 0.1 ms rollout
        // at 0.25 ms (0.5 ms drifts by 1.3, 1 ms by 50): the step the
        // stiff Hunt-Crossley contact needs, and no smaller.
        scene.integrator = mbx::calibration::ContactScene::euler(2.5e-4);
    }
    CubeScene(const CubeScene&) = delete;
};

// The authors' nominal contact: Hunt-Crossley with their restitution 0.125
// for a corner's share of the mass, their friction 0.18, a friction spring.
inline mbx::sim::contact::ContactSettings nominal_cube_contact() {
    using namespace mbx::sim::contact;
    ContactSettings cs;
    cs.normal.model = NormalModel::HuntCrossley, cs.normal.stiffness = 1e6, cs.normal.exponent = 1.5;
    cs.normal.damping = damping_for_restitution(cs.normal, kCubeMass / 4, 1.0, 0.125);
    cs.friction.mu_static = cs.friction.mu_kinetic = 0.18;
    cs.friction.stiffness = 2e4;
    cs.friction.damping = 0.5 * 2 * std::sqrt(cs.friction.stiffness * kCubeMass / 4);
    return cs;
}

struct MjDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
    void operator()(mjData* d) const { mj_deleteData(d); }
};
using MjModelPtr = std::unique_ptr<mjModel, MjDeleter>;

// The cube on a plane in MuJoCo, `contact` the geoms' contact attributes.
inline MjModelPtr mujoco_cube(const std::string& contact) {
    const double h = kCubeEdge / 2;
    std::ostringstream x;
    x << "<mujoco><option timestep=\"0.0005\"/><worldbody><geom type=\"plane\" size=\"0 0 1\" " << contact << "/>"
      << "<body><freejoint/><geom type=\"box\" size=\"" << h << " " << h << " " << h << "\" " << contact
      << "/><inertial pos=\"0 0 0\" mass=\"" << kCubeMass << "\" diaginertia=\"" << kCubeInertia << " " << kCubeInertia
      << " " << kCubeInertia << "\"/></body></worldbody></mujoco>";
    const std::string text = x.str();
    mjVFS vfs;
    mj_defaultVFS(&vfs);
    mj_makeEmptyFileVFS(&vfs, "cube.xml", int(text.size()));
    std::memcpy(vfs.filedata[vfs.nfile - 1], text.data(), text.size());
    char error[500] = "";
    mjModel* m = mj_loadXML("cube.xml", &vfs, error, sizeof error);
    mj_deleteVFS(&vfs);
    if (!m) throw std::runtime_error(error);
    return MjModelPtr(m);
}

// MuJoCo's rollout of a toss from its first measured state, scored like
// calibration::roll_out (position in % of the edge, rotation in degrees).
inline mbx::calibration::PoseError mujoco_toss_error(const mjModel* m, const mbx::calibration::PoseRecord& toss) {
    std::unique_ptr<mjData, MjDeleter> d(mj_makeData(m));
    const auto& s0 = toss.samples.front();
    for (int k = 0; k < 3; ++k) d->qpos[k] = s0.p[k], d->qvel[k] = s0.v[k], d->qvel[3 + k] = s0.w[k];
    d->qpos[3] = s0.q.w(), d->qpos[4] = s0.q.x(), d->qpos[5] = s0.q.y(), d->qpos[6] = s0.q.z();
    d->time = s0.t;
    mbx::calibration::PoseError e;
    for (const auto& s : toss.samples) {
        while (d->time < s.t - 1e-9) mj_step(m, d.get());
        const Eigen::Vector3d p(d->qpos[0], d->qpos[1], d->qpos[2]);
        const Eigen::Quaterniond q(d->qpos[3], d->qpos[4], d->qpos[5], d->qpos[6]);
        e.position += (p - s.p).norm() / kCubeEdge * 100;
        e.rotation += 2 * std::acos(std::min(1.0, std::abs(q.normalized().dot(s.q)))) * 180 / M_PI;
        ++e.samples;
    }
    e.position /= double(e.samples), e.rotation /= double(e.samples);
    return e;
}

// Mean over tosses, every sample weighing the same (as calibration::pose_error).
inline mbx::calibration::PoseError mujoco_error(const mjModel* m, const std::vector<mbx::calibration::PoseRecord>& tosses) {
    mbx::calibration::PoseError sum;
    for (const auto& t : tosses) {
        const auto e = mujoco_toss_error(m, t);
        sum.position += e.position * double(e.samples), sum.rotation += e.rotation * double(e.samples);
        sum.samples += e.samples;
    }
    sum.position /= double(sum.samples), sum.rotation /= double(sum.samples);
    return sum;
}

}  // namespace mbx_test
