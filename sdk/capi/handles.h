// What the opaque C handles hold. Only capi/ sees these.
#pragma once
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/assembly/shape_loader.h"
#include "core/finding.h"
#include "core/mechatronics/drive.h"
#include "core/mechatronics/joint_dynamics.h"
#include "mbx/mbx.h"
#include "core/translator/mechanism.h"

struct mbx_context {
    mbx_progress_fn progress = nullptr;
    void* progress_user = nullptr;

    // Last failure; strings are returned to the caller by pointer.
    mbx_status status = MBX_OK;
    std::string message;
    mbx::Subject subject;
    std::string file;
    int line = 0;

    void clear() {
        status = MBX_OK;
        message.clear();
        subject = {};
        file.clear();
        line = 0;
    }
    mbx_status fail(mbx_status s, std::string text, mbx::Subject subj = {}, std::string in_file = {}, int at = 0) {
        status = s;
        message = std::move(text);
        subject = std::move(subj);
        file = std::move(in_file);
        line = at;
        return s;
    }
};

struct mbx_mechanism {
    std::unique_ptr<mbx::Mechanism> model;
    mbx_host host{};  // copy of the host's table (zero past its struct_size)
    bool has_host = false;
    std::vector<std::unique_ptr<std::vector<mbx::Mesh>>> shapes;  // per rigid body, loaded on demand
    mutable std::unordered_map<std::string, int> part_index;       // built on the first lookup
    std::vector<mbx::Drive> drives;  // resolved by mbx_mechanism_set_mechatronics
    std::vector<mbx::ResolvedJointDynamics> joint_dynamics;  // idem
    // Body mass corrections of the attached description, applied to `model`
    // from the CAD inertia kept here (taken when the first is applied).
    std::vector<mbx::ResolvedBodyMass> body_masses;
    std::unique_ptr<mbx::CadInertia> cad_inertia;
    // Collision shapes and contact materials of the attached description,
    // resolved to body frames (hulls wait for the simulator to load meshes).
    mbx::ResolvedContact contact;
    // The attached description's <mounting>: the simulator's and the
    // calibration's gravity turned by it.
    mbx::MountingSpec mounting;

    // Meshes of rigid body `body`, asked from the host once, then cached.
    // `m` is passed because during translation `model` is not set yet.
    const std::vector<mbx::Mesh>& body_shapes(mbx::Mechanism& m, int body) {
        if (shapes.size() < m.bodies.size()) shapes.resize(m.bodies.size());
        auto& cache = shapes[size_t(body)];
        if (!cache) cache = std::make_unique<std::vector<mbx::Mesh>>(mbx::load_body_shapes(host, m, body));
        return *cache;
    }
};

struct mbx_mechatronics {
    mbx::MechatronicSpec spec;
};
