// Lazy geometry: asks the host for the meshes of a rigid body's parts and
// brings them into the body frame in metres. Nothing calls this during
// translation; consumers that need geometry (exporters, collision) do.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include <array>

#include "mbx/mbx.h"
#include "core/translator/mechanism.h"

namespace mbx {

struct Mesh {
    std::string name;
    std::string part_id;
    std::vector<Vec3> vertices;       // body frame, metres
    std::vector<uint32_t> triangles;  // 3 per triangle
    // The host's colour (red, green, blue, alpha in 0..1); alpha 0: none given.
    std::array<double, 4> color{};
    bool has_color() const { return color[3] > 0; }
};

// Loads the meshes of every part of rigid body `body`. Throws Error naming the
// part (and the host's message) when the host fails or sends bad data.
// Diagnostics a version-4 host appended while serving the shapes (a mesh file
// that passed its open-time check but failed to load) join m.findings, also
// when the host then failed.
std::vector<Mesh> load_body_shapes(const mbx_host& host, Mechanism& m, int body);
// The same for a mechanism that cannot take findings: the host's new
// diagnostics stay unread, and the next load through the overload above
// pulls them.
std::vector<Mesh> load_body_shapes(const mbx_host& host, const Mechanism& m, int body);

}  // namespace mbx
