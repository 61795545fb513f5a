// Lazy geometry: asks the host for the meshes of a rigid body's parts and
// brings them into the body frame in metres. Nothing calls this during
// translation; consumers that need geometry (exporters, collision) do.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "mbx/mbx.h"
#include "translator/mechanism.h"

namespace mbx {

struct Mesh {
    std::string name;
    std::string part_id;
    std::vector<Vec3> vertices;       // body frame, metres
    std::vector<uint32_t> triangles;  // 3 per triangle
};

// Loads the meshes of every part of rigid body `body`. Throws Error naming the
// part (and the host's message) when the host fails or sends bad data.
std::vector<Mesh> load_body_shapes(const mbx_host& host, const Mechanism& m, int body);

}  // namespace mbx
