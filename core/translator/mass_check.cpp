// CAD mass data against the part's own geometry: the volume centroid of a
// closed mesh must sit on the CAD centre of mass (uniform density assumed).
// A column/row-major mix-up, a mirrored part or a wrong unit moves it by
// centimetres, far above what rounding or a non-uniform material explains.
#include <cstdio>
#include <map>

#include "core/assembly/shape_loader.h"
#include "core/geometry/mesh_properties.h"
#include "core/translator/translate.h"

namespace mbx {

void check_mass_with_shapes(Mechanism& m, const ShapeFetcher& shapes, double centroid_tolerance, Progress& progress) {
    const Assembly& a = m.assembly;
    m.shape_checks.assign(a.parts.size(), ShapeCheck{});
    std::map<std::string, int> part_index;  // only parts of the body at hand
    progress.stage("check mass with shapes", m.bodies.size());
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        progress.tick();
        const RigidBody& body = m.bodies[b];
        if (body.parts.empty()) continue;
        const std::vector<Mesh>& meshes = shapes(m, int(b));
        if (meshes.empty()) continue;
        part_index.clear();
        for (int p : body.parts) part_index.emplace(a.parts[size_t(p)].id, p);
        const Pose body_inv = body.pose.inverse();

        std::map<int, std::vector<const Mesh*>> by_part;
        for (const Mesh& mesh : meshes) {
            auto it = part_index.find(mesh.part_id);
            if (it != part_index.end()) by_part[it->second].push_back(&mesh);
        }
        for (const auto& [p, list] : by_part) {
            const Part& part = a.parts[size_t(p)];
            if (part.mass <= 0 || part.is_helper()) continue;
            SolidAccumulator solid;
            Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
            bool closed = true;
            for (const Mesh* mesh : list) {
                const MeshClosure c = check_closure(mesh->triangles);
                if (!c.closed) {
                    closed = false;
                    m.add(MBX_SEVERITY_INFO, MBX_FINDING_SHAPE_NOT_CLOSED, Subject::body(part.id, part.name),
                          "mesh '" + mesh->name + "' of part '" + part.name + "' is not a closed surface (" +
                              std::to_string(c.boundary_edges) + " open and " + std::to_string(c.nonmanifold_edges) +
                              " non-manifold edges); its mass data cannot be checked against it");
                    break;
                }
                solid.add(mesh->vertices, mesh->triangles);
                for (const Vec3& v : mesh->vertices) {
                    lo = lo.cwiseMin(v);
                    hi = hi.cwiseMax(v);
                }
            }
            if (!closed) continue;
            const SolidProperties sp = solid.result();
            if (!(sp.volume > 0)) continue;
            const Vec3 cad_com = (body_inv * part.pose).apply(part.com);
            ShapeCheck& check = m.shape_checks[size_t(p)];
            check.checked = true;
            check.volume = sp.volume;
            check.centroid_mismatch = (sp.centroid - cad_com).norm();
            check.density = part.mass / sp.volume;
            check.tolerance = centroid_tolerance > 0 ? centroid_tolerance : std::max(1e-3, 0.02 * (hi - lo).norm());
            if (check.centroid_mismatch > check.tolerance) {
                char text[160];
                std::snprintf(text, sizeof text, "%.3f mm from the mesh centroid (tolerance %.3f mm)",
                              check.centroid_mismatch * 1e3, check.tolerance * 1e3);
                m.add(MBX_SEVERITY_WARNING, MBX_FINDING_MASS_MISMATCH, Subject::body(part.id, part.name),
                      "the CAD centre of mass of part '" + part.name + "' is " + text +
                          "; suspect a mirrored part, a wrong orientation layout or wrong units");
            }
        }
    }
    progress.finish();
}

}  // namespace mbx
