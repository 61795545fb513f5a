// `mbx geometry <file.step>`: what mbx makes of a STEP file's geometry
// (host_adapters/step): every placed solid with its volume, centroid,
// inertia, triangle count and closure, and with -o its meshes written as
// files. Geometry is not yet an input the C API takes on its own (a STEP file
// comes in as a part's mesh), so this reads it through the adapter directly.
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.h"
#include "core/finding.h"
#include "core/geometry/mesh_properties.h"
#include "core/report/atomic_file.h"
#include "export/common/names.h"
#include "export/mesh/mesh_export.h"
#include "host_adapters/step/assembly.h"
#include "host_adapters/step/tessellate.h"

namespace mbx_cli {
namespace {

const char* kGeometryUsage =
    "usage: mbx geometry <file.step> [-o <dir>] [--format stl|obj|glb]\n"
    "                    [--chord <m> | --relative-chord <fraction>] [--angle <degrees>]\n"
    "\n"
    "  Reads a STEP file (AP203, AP214, AP242) and prints each placed solid: its product and occurrence,\n"
    "  volume, centroid, inertia about the centroid per unit density, triangle count and whether its mesh\n"
    "  is closed. Findings (a face not meshed, an entity not read) go to stderr with the file's line.\n"
    "\n"
    "  -o <dir>            write one mesh file per placed solid there, in the file's frame, in metres\n"
    "  --format <f>        stl (binary, the default), obj or glb (binary glTF 2.0)\n"
    "  --chord <m>         chord tolerance in metres (default: a fraction of each solid's size)\n"
    "  --relative-chord <f>  chord as a fraction of each solid's bounding-box diagonal (default 1e-5)\n"
    "  --angle <degrees>   largest turn of an edge segment (default 1)\n";


}  // namespace

int run_geometry(const std::vector<std::string>& args) {
    std::string input, out_dir, format_name = "stl";
    mbx_step::Tolerance tolerance;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const bool has_value = i + 1 < args.size();
        double value = 0;
        if (a == "-h" || a == "--help") {
            std::fputs(kGeometryUsage, stdout);
            return 0;
        } else if ((a == "-o" || a == "--output") && has_value) {
            out_dir = args[++i];
        } else if (a == "--format" && has_value) {
            format_name = args[++i];
        } else if ((a == "--chord" || a == "--relative-chord" || a == "--angle") && has_value) {
            if (!parse_number(args[++i], value) || !(value > 0) || (a == "--relative-chord" && value >= 0.1) ||
                (a == "--angle" && value > 90)) {
                std::fprintf(stderr, "mbx geometry: %s takes a positive number%s, not '%s'\n", a.c_str(),
                             a == "--angle" ? " of degrees up to 90" : a == "--relative-chord" ? " below 0.1" : "",
                             args[i].c_str());
                return 2;
            }
            if (a == "--chord") tolerance.chord = value;
            if (a == "--relative-chord") tolerance.relative_chord = value, tolerance.chord = 0;
            if (a == "--angle") tolerance.angle = value * M_PI / 180;
        } else if (!a.empty() && a[0] != '-' && input.empty()) {
            input = a;
        } else {
            std::fprintf(stderr, "mbx geometry: unexpected argument '%s'\n\n%s", a.c_str(), kGeometryUsage);
            return 2;
        }
    }
    if (input.empty()) {
        std::fputs(kGeometryUsage, stderr);
        return 2;
    }
    mbx_mesh_format format;
    std::string extension;
    if (format_name == "stl") {
        format = MBX_MESH_STL, extension = ".stl";
    } else if (format_name == "obj") {
        format = MBX_MESH_OBJ, extension = ".obj";
    } else if (format_name == "glb" || format_name == "gltf") {
        format = MBX_MESH_GLTF, extension = ".glb";
    } else {
        std::fprintf(stderr, "mbx geometry: --format is stl, obj or glb, not '%s'\n", format_name.c_str());
        return 2;
    }
    try {
        const mbx_step::File file = mbx_step::read_part21_file(input);
        const mbx_step::Brep brep = mbx_step::read_breps(file);
        const mbx_step::Assembly placed = mbx_step::place_solids(file, brep);
        const std::vector<mbx_step::SolidMesh> meshes = mbx_step::tessellate(brep, tolerance);
        auto finding = [&](const mbx_step::Problem& p) {
            std::fprintf(stderr, "%s:%d: #%llu: %s\n", input.c_str(), p.line, static_cast<unsigned long long>(p.entity),
                         p.message.c_str());
        };
        for (const mbx_step::Problem& p : brep.problems) finding(p);
        for (const mbx_step::Problem& p : placed.problems) finding(p);
        for (const mbx_step::SolidMesh& m : meshes)
            for (const mbx_step::Problem& p : m.problems) finding(p);
        if (placed.solids.empty()) {
            std::fprintf(stderr, "mbx geometry: %s holds no solid mbx reads (no B-rep)\n", input.c_str());
            return 1;
        }
        std::printf("%s: %zu solids, %zu placed\n", input.c_str(), brep.solids.size(), placed.solids.size());
        mbx::NameTable names;
        size_t open = 0;
        for (const mbx_step::PlacedSolid& p : placed.solids) {
            const mbx_step::SolidMesh& m = meshes[p.solid];
            std::vector<uint32_t> flat;
            flat.reserve(m.mesh.triangles.size() * 3);
            for (const auto& t : m.mesh.triangles) flat.insert(flat.end(), t.begin(), t.end());
            const mbx::MeshClosure closure = mbx::check_closure(flat);
            mbx::SolidAccumulator acc;
            acc.add(m.mesh.points, flat);
            const mbx::SolidProperties props = acc.result();
            const Eigen::Matrix3d R = p.pose.linear();
            const Eigen::Vector3d c = p.pose * props.centroid;
            const Eigen::Matrix3d I = R * props.inertia_per_density * R.transpose();
            std::string name = p.product.empty() ? m.name : p.product;
            if (!p.occurrence.empty()) name += " (" + p.occurrence + ")";
            if (name.empty()) name = "solid " + std::to_string(p.solid + 1);
            open += closure.closed ? 0 : 1;
            std::printf("%s\n  volume %.9g m^3, centroid %.9g %.9g %.9g m\n"
                        "  inertia tensor about the centroid per density: xx %.6g yy %.6g zz %.6g xy %.6g xz %.6g yz %.6g m^5\n"
                        "  %zu triangles at a chord of %.3g m, %s\n",
                        name.c_str(), props.volume, c.x(), c.y(), c.z(), I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2),
                        I(1, 2), m.mesh.triangles.size(), m.chord,
                        closure.closed ? "closed" : ("not closed: " + std::to_string(closure.boundary_edges) +
                                                     " open and " + std::to_string(closure.nonmanifold_edges) +
                                                     " non-manifold edges").c_str());
            if (out_dir.empty()) continue;
            mbx::Mesh placed_mesh;
            placed_mesh.name = name;
            for (const Eigen::Vector3d& v : m.mesh.points) placed_mesh.vertices.push_back(p.pose * v);
            placed_mesh.triangles = flat;
            const std::string stem = names.claim(mbx::sanitize_identifier(name, "solid"));
            const std::string path = (std::filesystem::path(out_dir) / (stem + extension)).string();
            mbx::write_file_atomically(path, mbx::encode_mesh({placed_mesh}, stem, format));
        }
        if (!out_dir.empty()) std::printf("meshes written to %s\n", out_dir.c_str());
        if (open) std::fprintf(stderr, "mbx geometry: %zu of %zu solids are not closed\n", open, placed.solids.size());
        return 0;
    } catch (const mbx_step::ReadError& e) {
        std::fprintf(stderr, "mbx geometry: %s\n", e.what());
        return 1;
    } catch (const mbx::Error& e) {
        std::fprintf(stderr, "mbx geometry: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "mbx geometry: %s needs more memory than is available to mesh\n", input.c_str());
        return 1;
    }
}

}  // namespace mbx_cli
