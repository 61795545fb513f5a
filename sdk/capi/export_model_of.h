// The ExportModel of a mechanism handle, as every consumer of its exports
// needs it: the attached description's drives, joint dynamics, contact and mounting,
// and meshes fetched from the host while the handle still has it.
#pragma once
#include "sdk/capi/handles.h"
#include "export/common/export_model.h"

inline mbx::ExportModel export_model_of(mbx_mechanism* mechanism, mbx::ExportSettings settings) {
    settings.drives = mechanism->drives;
    settings.joint_dynamics = mechanism->joint_dynamics;
    settings.contact = mechanism->contact;
    settings.mounting = mechanism->mounting;
    mbx::Mechanism& m = *mechanism->model;
    mbx::BodyShapes shapes;
    if (mechanism->has_host)
        shapes = [mechanism, &m](int body) -> const std::vector<mbx::Mesh>& { return mechanism->body_shapes(m, body); };
    return mbx::ExportModel(m, shapes, std::move(settings));
}
