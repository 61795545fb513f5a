// The PMXML + VRML file adapter: a SimMechanics first-generation XML file,
// the mesh files its bodies name, and optionally a VRML97 scene whose shapes
// are matched to the bodies by pose, served through the mbx_host table.
//
//   auto adapter = mbx_files::FileAdapter::open("robot.xml", {});   // throws FileError
//   mbx_translate(ctx, adapter->table(), &options, &mechanism);
//
// Meshes named by a body (geometryFileName) attach to it directly; only
// bodies without one take shapes from the VRML scene. Mesh files load lazily,
// when the SDK first asks for a body's shapes; whether they exist and look
// readable is checked at open, so a missing or broken file is a host
// diagnostic in the report rather than a failure.
//
// The adapter must outlive every mechanism translated from its table (or the
// mechanism must release the host first), as for any mbx_host.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "host_adapters/common/file_error.h"
#include "host_adapters/common/file_input.h"
#include "host_adapters/memory/memory_host.h"
#include "pmxml_model.h"
#include "host_adapters/common/shape_matching.h"

namespace mbx_files {

// shapes_path: a VRML97 scene; mesh_dirs: searched for geometryFileName
// after the XML's own directory.
using FileAdapterOptions = FileInputOptions;

class FileAdapter final : public FileInput {
public:
    // Reads everything but the mesh files. Throws FileError (file, line,
    // message) for an unusable XML or VRML file.
    static std::unique_ptr<FileAdapter> open(const std::string& xml_path, const FileAdapterOptions& options = {});
    ~FileAdapter() override;
    FileAdapter(const FileAdapter&) = delete;
    FileAdapter& operator=(const FileAdapter&) = delete;

    const mbx_host* table() const override;
    // What the host serves (VRML shapes included; mesh files are not, they load on demand).
    const mbx_memory::Assembly& assembly() const;
    const PmxmlModel& model() const;
    // Call counts and shape requests of the host, to see what loaded when.
    const mbx_memory::Host& host() const;
    // Body id -> mesh file found for it (missing or unreadable ones excluded).
    const std::map<std::string, std::string>& mesh_files() const;
    // The VRML matching, empty without shapes_path.
    const MatchResult& matching() const;
    // VRML meshes matched to a body that already has its own mesh file, and dropped.
    size_t superseded_vrml_meshes() const;
    // Mesh files that passed the open-time check but failed to load when the
    // SDK asked for them (the body simply has no shape). The host serves them
    // as diagnostics appended while it served the shapes, so they are also
    // findings of the mechanism from then on.
    std::vector<mbx_memory::Diagnostic> late_diagnostics() const;

    struct Lazy;  // mesh files, shared with the host's shape source

private:
    FileAdapter() = default;

    PmxmlModel model_;
    std::map<std::string, std::string> mesh_files_;
    MatchResult matching_;
    size_t superseded_ = 0;
    std::shared_ptr<Lazy> lazy_;
    std::unique_ptr<mbx_memory::Host> host_;  // last: destroyed before what its shape source uses
};

}  // namespace mbx_files
