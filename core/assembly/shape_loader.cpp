#include "core/assembly/shape_loader.h"

#include <cmath>
#include <cstring>

#include "core/assembly/host_reader.h"

namespace mbx {
namespace {

struct SinkState {
    const Part* part;
    Pose body_from_part;
    std::vector<Mesh>* out;
    std::string error;
};

int add_mesh(void* data, const mbx_mesh_desc* d) {
    auto* s = static_cast<SinkState*>(data);
    const std::string who = "mesh of part '" + s->part->id + "'";
    if (!d || d->struct_size < offsetof(mbx_mesh_desc, triangle_count) + sizeof(d->triangle_count)) {
        s->error = who + " was delivered with a missing or too small descriptor";
        return 1;
    }
    if ((d->vertex_count && !d->vertices) || (d->triangle_count && !d->triangles)) {
        s->error = who + " has counts but no arrays";
        return 1;
    }
    const double len = d->units.length_to_m == 0 ? 1.0 : d->units.length_to_m;
    Mat3 r = from_row_major(d->pose.rotation);
    Mat3 fixed;
    if (!std::isfinite(len) || len <= 0 || !nearest_rotation(r, fixed) || orthonormality_error(r) > 0.05) {
        s->error = who + " has an invalid unit factor or pose rotation";
        return 1;
    }
    Pose mesh_pose{fixed, Vec3(d->pose.position[0], d->pose.position[1], d->pose.position[2]) * len};
    if (!mesh_pose.position.allFinite()) {
        s->error = who + " has a non-finite pose";
        return 1;
    }
    const Pose to_body = s->body_from_part * mesh_pose;
    Mesh mesh;
    mesh.name = d->name ? d->name : "";
    mesh.part_id = s->part->id;
    mesh.vertices.reserve(d->vertex_count);
    for (uint32_t i = 0; i < d->vertex_count; ++i) {
        Vec3 v(d->vertices[3 * i], d->vertices[3 * i + 1], d->vertices[3 * i + 2]);
        if (!v.allFinite()) {
            s->error = who + " has a non-finite vertex #" + std::to_string(i);
            return 1;
        }
        mesh.vertices.push_back(to_body.apply(v * len));
    }
    mesh.triangles.assign(d->triangles, d->triangles + 3 * size_t(d->triangle_count));
    for (uint32_t idx : mesh.triangles)
        if (idx >= d->vertex_count) {
            s->error = who + " refers to vertex " + std::to_string(idx) + " of " + std::to_string(d->vertex_count);
            return 1;
        }
    if (MBX_FIELD_FITS(d, mbx_mesh_desc, color)) {
        for (int k = 0; k < 4; ++k)
            if (!(d->color[k] >= 0 && d->color[k] <= 1)) {
                s->error = who + " has a colour component that is not a number in 0..1 (component " +
                           std::to_string(k) + ")";
                return 1;
            }
        for (int k = 0; k < 4; ++k) mesh.color[size_t(k)] = d->color[k];
    }
    s->out->push_back(std::move(mesh));
    return 0;
}

// `record`: where the host's late diagnostics go (m itself), or null.
std::vector<Mesh> load(const mbx_host& host, const Mechanism& m, int body, Mechanism* record) {
    std::vector<Mesh> out;
    if (!host.get_shapes) return out;
    const RigidBody& b = m.bodies[size_t(body)];
    const Pose body_inv = b.pose.inverse();
    for (int p : b.parts) {
        const Part& part = m.assembly.parts[size_t(p)];
        SinkState state{&part, body_inv * part.pose, &out, {}};
        mbx_shape_sink sink{sizeof(mbx_shape_sink), &state, add_mesh};
        char message[512] = {0};
        const int failed = host.get_shapes(host.user_data, part.id.c_str(), &sink, message, sizeof message);
        // Older hosts pulled theirs once and may rewrite the list; only
        // version 4 promises that it only grows.
        if (record && host.abi_version >= 4)
            record->assembly.host_diagnostics_read =
                pull_host_diagnostics(host, record->assembly.host_diagnostics_read, record->findings);
        if (failed != 0 || !state.error.empty()) {
            std::string text = state.error.empty() ? "host failed to deliver the shapes of part '" + part.id + "'"
                                                   : state.error;
            if (message[0]) text += ": " + std::string(message, strnlen(message, sizeof message));
            throw Error(state.error.empty() ? MBX_ERROR_HOST_CALLBACK : MBX_ERROR_INVALID_INPUT,
                        Subject::body(part.id, part.name), text);
        }
    }
    return out;
}

}  // namespace

std::vector<Mesh> load_body_shapes(const mbx_host& host, Mechanism& m, int body) { return load(host, m, body, &m); }

std::vector<Mesh> load_body_shapes(const mbx_host& host, const Mechanism& m, int body) {
    return load(host, m, body, nullptr);
}

}  // namespace mbx
