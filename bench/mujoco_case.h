// The benchmarks' shared MuJoCo peer: a translated stub assembly with mbx's
// simulation model beside MuJoCo's load of mbx's MJCF export of the same
// translation, and the map between their coordinates (bench_sim,
// bench_excitation).
#pragma once
#include <mujoco/mujoco.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/stub_host/assemblies/builder.h"
#include "apps/stub_host/assemblies/stub_assembly.h"
#include "core/assembly/host_reader.h"
#include "core/assembly/shape_loader.h"
#include "core/translator/translate.h"
#include "export/common/export_model.h"
#include "export/export_files.h"
#include "export/mjcf/mjcf_layout.h"
#include "sim/build_model.h"

namespace mbx_bench {

using namespace mbx_stub::build;


// n links of 0.1 m along x; joint k turns about z, y, x in turn.
inline mbx_stub::Assembly chain(int n) {
    mbx_stub::Assembly a;
    a.name = "chain" + std::to_string(n);
    const mbx_units si{1, 1, 1};
    Builder b(a, a.name, si, si);
    const Mat3 I = Mat3::Identity();
    b.body("ground", "Ground", MBX_BODY_GROUND, 1.0, I, Vec3::Zero(), Vec3::Zero(), box_inertia(1.0, 0.1, 0.1, 0.1));
    const Vec3 axes[3] = {Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitX()};
    std::string prev = "ground";
    for (int k = 0; k < n; ++k) {
        const std::string name = "l" + std::to_string(k);
        const Vec3 at(0.1 * k, 0, 1);
        b.body(name, "Link " + std::to_string(k), 0, 1.0, I, at, at + Vec3(0.05, 0.01, 0), box_inertia(1.0, 0.1, 0.03, 0.02));
        b.joint("j" + std::to_string(k), prev, name, at, I, {revolute(axes[k % 3])}, MBX_FRAME_IN_WORLD,
                MBX_FRAME_IN_WORLD);
        prev = name;
    }
    return a;
}

struct MjDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
    void operator()(mjData* d) const { mj_deleteData(d); }
};

// Both engines' models of one translated assembly, and the map from mbx's
// velocity coordinates to MuJoCo's (hinges and slides; other kinds stay at rest).
struct Case {
    std::string label;
    mbx::sim::Model model;
    std::unique_ptr<mjModel, MjDeleter> mm;
    std::unique_ptr<mjData, MjDeleter> md;
    std::vector<int> qpos_of_q, dof_of_v;  // -1: no counterpart
};

inline std::string read_text(const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

// MuJoCo 2.2's XML parser stops at 100 nested elements, fewer than a chain
// of 100 bodies needs; an <include> is parsed as a document of its own and
// then copied in, so the inner half of the chain goes to a second file.
// `cut` is the body (1-based, in nesting order) whose content moves.
inline void split_nesting(const std::filesystem::path& dir, const std::string& file, int cut, int bodies) {
    const std::string xml = read_text(dir / file);
    size_t open = 0;
    for (int k = 0; k < cut; ++k) open = xml.find("<body", open) + 1;
    const size_t begin = xml.find('>', open) + 1;
    size_t close = 0;
    for (int k = 0; k < bodies + 1 - cut; ++k) close = xml.find("</body>", close) + 1;
    const size_t end = close - 1;
    if (open == 0 || close == 0 || end < begin) throw std::runtime_error("cannot split " + file);
    std::ofstream(dir / ("inner_" + file)) << "<mujoco>" << xml.substr(begin, end - begin) << "</mujoco>\n";
    std::ofstream(dir / file) << xml.substr(0, begin) << "<include file=\"inner_" << file << "\"/>" << xml.substr(end);
}

inline Case make_case(const std::string& label, mbx_stub::Assembly assembly, const std::filesystem::path& dir) {
    Case c;
    c.label = label;
    mbx_stub::Host host(std::move(assembly));
    mbx::Progress progress(nullptr, nullptr);
    mbx::Findings findings;
    mbx::Assembly a = mbx::read_host(host.table(), mbx::HostReadOptions{}, progress, findings);
    auto m = mbx::translate_assembly(std::move(a), std::move(findings), mbx::TranslateOptions{}, progress);
    c.model = mbx::sim::build_model(*m);
    std::vector<std::vector<mbx::Mesh>> shapes(m->bodies.size());
    for (size_t b = 0; b < m->bodies.size(); ++b) shapes[b] = mbx::load_body_shapes(*host.table(), *m, int(b));
    const mbx::BodyShapes fetch = [&shapes](int b) -> const std::vector<mbx::Mesh>& { return shapes[size_t(b)]; };
    mbx::ExportSettings settings;
    settings.model_name = "bench";
    mbx::ExportModel em(*m, fetch, settings);
    const mbx::MjcfLayout layout = mbx::build_mjcf_layout(em);
    const std::filesystem::path out = dir / label;
    mbx::write_output_files(out.string(), mbx::export_files(em, MBX_EXPORT_MJCF));
    const int bodies = int(m->bodies.size()) - 1;
    if (bodies > 90) split_nesting(out / "mjcf", "bench.xml", bodies / 2, bodies);
    char error[1024] = "";
    c.mm.reset(mj_loadXML((out / "mjcf/bench.xml").c_str(), nullptr, error, sizeof error));
    if (!c.mm) throw std::runtime_error(label + ": MuJoCo refused the export: " + error);
    c.md.reset(mj_makeData(c.mm.get()));
    c.qpos_of_q.assign(size_t(c.model.nq), -1);
    c.dof_of_v.assign(size_t(c.model.nv), -1);
    for (const auto& j : c.model.joints) {
        if (j.source < 0 || j.nv() != 1) continue;
        for (const mbx::MjcfBody& b : layout.bodies)
            for (const mbx::MjcfJoint& mj : b.joints)
                if (mj.joint == j.source) {
                    const int id = mj_name2id(c.mm.get(), mjOBJ_JOINT, mj.name.c_str());
                    if (id < 0) continue;
                    c.qpos_of_q[size_t(j.q_index)] = c.mm->jnt_qposadr[id];
                    c.dof_of_v[size_t(j.v_index)] = c.mm->jnt_dofadr[id];
                }
    }
    // Same gravity on both, tilted so that planar loops lying flat move too.
    const Eigen::Vector3d g = 9.81 * Eigen::Vector3d(0.3, -0.5, -0.8).normalized();
    c.model.gravity = g;
    for (int k = 0; k < 3; ++k) c.mm->opt.gravity[k] = g[k];
    c.mm->opt.timestep = 1e-3;
    c.mm->opt.disableflags |= mjDSBL_CONTACT;
    return c;
}

inline void to_mujoco(Case& c, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    mj_resetData(c.mm.get(), c.md.get());
    for (size_t k = 0; k < c.qpos_of_q.size(); ++k)
        if (c.qpos_of_q[k] >= 0) c.md->qpos[c.qpos_of_q[k]] = q[Eigen::Index(k)];
    for (size_t k = 0; k < c.dof_of_v.size(); ++k)
        if (c.dof_of_v[k] >= 0) c.md->qvel[c.dof_of_v[k]] = v[Eigen::Index(k)];
}

}  // namespace mbx_bench
