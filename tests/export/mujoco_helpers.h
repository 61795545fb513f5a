// MuJoCo as the consumer of the MJCF tests: load an exported model from its
// written file, look bodies and joints up by the layout's names, and put
// mbx joint coordinates into qpos.
#pragma once
#include <mujoco/mujoco.h>

#include <Eigen/Geometry>
#include <memory>
#include <string>

#include "export/common/names.h"
#include "export_fixture.h"
#include "export/mjcf/mjcf_layout.h"

namespace xtest {

struct MjModelDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
    void operator()(mjData* d) const { mj_deleteData(d); }
};

// An exported model as MuJoCo reads it, with the layout it was written from.
struct MuJoCoRun {
    std::unique_ptr<mjModel, MjModelDeleter> model;
    std::unique_ptr<mjData, MjDataDeleter> data;
    std::string load_message;  // MuJoCo's warning text when it loaded with one
    mbx::MjcfLayout layout;
    mbx::OutputFiles files;
    std::string xml;  // the MJCF text

    int body_id(int rigid_body) const {
        if (rigid_body == 0) return 0;
        const int k = layout.of_body[size_t(rigid_body)];
        if (k < 0) return -1;
        return mj_name2id(model.get(), mjOBJ_BODY, layout.bodies[size_t(k)].name.c_str());
    }
    mbx::Pose pose(int mj_body) const {
        mbx::Pose p;
        for (int r = 0; r < 3; ++r) {
            p.position[r] = data->xpos[3 * mj_body + r];
            for (int c = 0; c < 3; ++c) p.rotation(r, c) = data->xmat[9 * mj_body + 3 * r + c];
        }
        return p;
    }
};

// Exports MJCF (and the meshes it refers to) into `dir`, loads the written
// file and makes its data. REQUIREs that MuJoCo accepts the model.
inline MuJoCoRun load_mjcf(Translated& t, const mbx_test::TempDir& dir, mbx::ExportSettings settings = {}) {
    MuJoCoRun run;
    {
        mbx::ExportModel layout_model = export_model(t, settings);
        run.layout = mbx::build_mjcf_layout(layout_model);
    }
    run.files = export_to(t, dir, MBX_EXPORT_MJCF, settings);
    const std::string name = mbx::sanitize_identifier(settings.model_name, "model");
    const mbx::OutputFile* f = find_file(run.files, "mjcf/" + name + ".xml");
    REQUIRE(f);
    run.xml = f->contents;
    char error[1024] = "";
    run.model.reset(mj_loadXML(dir.file("mjcf/" + name + ".xml").c_str(), nullptr, error, sizeof error));
    REQUIRE_MESSAGE(run.model, error);
    run.load_message = error;
    run.data.reset(mj_makeData(run.model.get()));
    REQUIRE(run.data);
    return run;
}

// Rotation angle between two rotation matrices.
inline double rotation_error(const mbx::Mat3& a, const mbx::Mat3& b) {
    return Eigen::AngleAxisd(a.transpose() * b).angle();
}

// Number of MuJoCo runtime warnings raised so far.
inline int warning_count(const mjData* d) {
    int n = 0;
    for (int i = 0; i < mjNWARNING; ++i) n += d->warning[i].number;
    return n;
}

}  // namespace xtest
