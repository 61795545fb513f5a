#include "pmxml_assembly.h"

#include <algorithm>

namespace mbx_files {

mbx_pose to_pose(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& position) {
    mbx_pose pose{};
    for (int i = 0; i < 3; ++i) {
        pose.position[i] = position[i];
        for (int j = 0; j < 3; ++j) pose.rotation[3 * i + j] = rotation(i, j);
    }
    return pose;
}

mbx_memory::Assembly to_assembly(const PmxmlModel& model) {
    mbx_memory::Assembly a;
    a.name = model.name;
    a.source = model.file;
    a.bodies.reserve(model.bodies.size());
    for (const PmxmlBody& b : model.bodies) {
        const PmxmlFrame& cs1 = model.frames[size_t(b.cs1)];
        mbx_memory::Body body;
        body.id = b.id;
        body.name = b.name;
        body.flags = b.flags;
        body.units = {cs1.length_to_m, b.mass_to_kg, b.inertia_to_kg_m2};
        body.mass = b.mass;
        // The host table wants the volume in the cube of the body's length unit.
        body.volume = b.volume * b.volume_to_m3 / (cs1.length_to_m * cs1.length_to_m * cs1.length_to_m);
        for (int i = 0; i < 3; ++i) body.com[i] = b.com[i];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) body.inertia[3 * i + j] = b.inertia(i, j);
        // As printed (rounded): the SDK re-orthonormalizes and reports what it repaired.
        body.pose = to_pose(cs1.rotation, cs1.position);
        a.bodies.push_back(std::move(body));
    }
    a.frames.reserve(size_t(std::count_if(model.frames.begin(), model.frames.end(),
                                          [](const PmxmlFrame& f) { return f.to_host; })));
    for (const PmxmlFrame& f : model.frames) {
        if (!f.to_host) continue;
        mbx_memory::Frame frame;
        frame.id = f.id;
        frame.name = f.display_name.empty() ? f.name : f.name + " (" + f.display_name + ")";
        frame.body_id = model.bodies[size_t(f.body)].id;
        frame.reference = MBX_FRAME_IN_WORLD;
        frame.units = {f.length_to_m, 1, 0};
        frame.pose = to_pose(f.rotation, f.position);
        a.frames.push_back(std::move(frame));
    }
    a.constraints.reserve(model.joints.size());
    for (const PmxmlJoint& j : model.joints) {
        mbx_memory::Constraint c;
        c.id = j.id;
        c.name = j.name;
        c.base_frame_id = model.frames[size_t(j.base_frame)].id;
        c.follower_frame_id = model.frames[size_t(j.follower_frame)].id;
        c.host_status = j.status;
        for (const PmxmlPrimitive& p : j.primitives) {
            mbx_memory::Primitive prim;
            prim.type = p.type;
            prim.axis_reference = MBX_AXIS_IN_WORLD;
            for (int i = 0; i < 3; ++i) prim.axis[i] = p.axis[i];
            c.chain.push_back(prim);
        }
        a.constraints.push_back(std::move(c));
    }
    a.diagnostics = model.diagnostics;
    return a;
}

}  // namespace mbx_files
