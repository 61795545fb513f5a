// The URDF adapter: a robot description (ROS packages, onshape-to-robot,
// the SolidWorks and Fusion exporters) served through the mbx_host table.
//
//   auto adapter = mbx_files::UrdfAdapter::open("panda.urdf", options);   // throws FileError
//   mbx_translate(ctx, adapter->table(), &translate_options, &mechanism);
//   adapter->description();   // the joint dynamics and collision shapes, as a description file
//
// Links are bodies and joints are joints, named as in the file (those names
// are this format's CAD ids). Each link's visual geometry is its shape (its
// collision geometry where it has no visual): boxes, cylinders and spheres
// meshed here, mesh files (STL, OBJ, DAE through assimp; STEP through mbx's
// reader) found relative to the URDF, as absolute paths, or as
// `package://name/...` through FileInputOptions::package_paths and then
// ROS_PACKAGE_PATH, loaded when the SDK first asks for a link's shapes. A
// mesh file that is not found is a finding, never a failure.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host_adapters/common/file_error.h"
#include "host_adapters/common/file_input.h"
#include "host_adapters/memory/memory_host.h"
#include "urdf_model.h"

namespace mbx_files {

class UrdfAdapter final : public FileInput {
public:
    static std::unique_ptr<UrdfAdapter> open(const std::string& path, const FileInputOptions& options = {});
    ~UrdfAdapter() override;
    UrdfAdapter(const UrdfAdapter&) = delete;
    UrdfAdapter& operator=(const UrdfAdapter&) = delete;

    const mbx_host* table() const override;
    // <joint> dynamics (damping; friction as Coulomb friction) and a
    // <collision> per collision element (box, cylinder, sphere; a mesh as
    // its link's hull) in the description file's form.
    std::string description() const override;

    const UrdfModel& model() const;
    const mbx_memory::Assembly& assembly() const;
    // Mesh filename as written -> the file it was found as (missing ones left out).
    const std::map<std::string, std::string>& mesh_files() const;

    struct Lazy;  // the links' mesh files, shared with the host's shape source

private:
    UrdfAdapter() = default;

    UrdfModel model_;
    std::map<std::string, std::string> mesh_files_;
    std::string description_;
    std::shared_ptr<Lazy> lazy_;
    std::unique_ptr<mbx_memory::Host> host_;  // last: destroyed before what its shape source uses
};

// Where a URDF mesh filename points: `package://name/rest` with the longest
// `name` (one or more path segments) given in `packages`, else the
// ROS_PACKAGE_PATH folders (`ros_package_path`, colon-separated: a folder
// named like the package, or one holding it); `file://` and absolute paths
// as they are; anything else relative to `urdf_dir`. "" when a package is
// found nowhere; `tried` then lists where it was looked for.
std::string resolve_urdf_path(const std::string& filename, const std::string& urdf_dir,
                              const std::vector<std::pair<std::string, std::string>>& packages,
                              const std::string& ros_package_path, std::string* tried = nullptr);

}  // namespace mbx_files
