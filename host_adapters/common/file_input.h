// An input file opened by one of the file adapters, whatever its format: what
// the command-line tool, the file host's C face (libmbx_files) and the Python
// package hold while the SDK translates from its mbx_host table. Each format
// opens its files through its entry in host_adapters/inputs/input_formats.h.
#pragma once
#include <string>
#include <vector>

#include "host_adapters/common/shape_matching.h"
#include "mbx/mbx.h"

namespace mbx_files {

// Options every file format takes; a format ignores those it has no use for
// (a format whose parts carry their own geometry has no scene to match).
struct FileInputOptions {
    std::string shapes_path;  // a scene (VRML97) holding the parts' shapes; "" = none
    // Searched for the mesh files a model names after the input's own folder.
    std::vector<std::string> mesh_dirs;
    MatchOptions match;  // pose matching of scene shapes to bodies
    // ROS package name -> its folder, for `package://name/...` paths (URDF);
    // searched before ROS_PACKAGE_PATH.
    std::vector<std::pair<std::string, std::string>> package_paths;
    // A URDF's root link free in space instead of fixed to the world.
    bool floating_base = false;
};

class FileInput {
public:
    virtual ~FileInput() = default;
    // The host table; valid as long as this object. A mechanism translated
    // from it must be destroyed, or must release the host, before this.
    virtual const mbx_host* table() const = 0;
    // What the file says beyond the assembly (a URDF's joint dynamics and
    // collision shapes) as the text of a description file
    // (docs/mechatronics.md), keyed by the same ids; "" when nothing. Loaded
    // before the user's description file, which refines it.
    virtual std::string description() const { return {}; }
};

}  // namespace mbx_files
