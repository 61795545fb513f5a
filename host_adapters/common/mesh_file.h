// Mesh files named by a PMXML body (geometryFileName): found beside the XML
// or in extra directories, case-insensitively (Creo writes upper-case names,
// repositories hold lower-case files), and read with assimp as they are: no
// scaling, no frame change, only triangulation and welding of identical
// vertices so the SDK can tell closed surfaces.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "host_adapters/memory/memory_host.h"

namespace mbx_files {

class MeshFileFinder {
public:
    // Directories searched in order.
    explicit MeshFileFinder(std::vector<std::string> directories);

    // Path of the file `name` refers to, or "" if no directory holds it.
    // `name` may carry a relative or absolute path ('\' or '/'); its last
    // component is matched case-insensitively (an exact match first), the
    // directories before it literally. Listings are read once and cached.
    std::string find(const std::string& name);

    const std::vector<std::string>& directories() const { return directories_; }

private:
    const std::map<std::string, std::string>* listing(const std::string& directory);

    std::vector<std::string> directories_;
    // directory -> (lower-case file name -> file name); nullopt if unreadable
    std::map<std::string, std::optional<std::map<std::string, std::string>>> listings_;
};

// Cheap check at open time (the mesh itself loads lazily): the file can be
// opened and, for STL, its header and size are those of an ASCII or binary
// STL. Returns false and says why otherwise.
bool probe_mesh_file(const std::string& path, std::string& why);

// Reads every triangle of the file into one mesh, in the file's own
// coordinates (node transforms of multi-node formats applied). Mesh formats
// carry no unit and come in the file's own numbers; a STEP file (.step,
// .stp) knows its unit and is meshed (host_adapters/step, at its default
// tolerance) in `unit_m` metres per unit (1 when 0). Returns false and says
// why when the file cannot be read or has no triangles.
bool load_mesh_file(const std::string& path, mbx_memory::Mesh& out, std::string& error, double unit_m = 0);

// Whether the file is STEP by its name (.step, .stp, any case).
bool is_step_file(const std::string& path);

}  // namespace mbx_files
