// The Simscape Multibody import-file adapter: a second-generation XML file
// and the STEP file of each part, served through the mbx_host table.
//
//   auto adapter = mbx_files::SimscapeAdapter::open("arm.xml", {});   // throws FileError
//   mbx_translate(ctx, adapter->table(), &options, &mechanism);
//
// Each part's STEP file is read by mbx's own STEP reader (host_adapters/step)
// when the SDK first asks for a body's shapes, once per part however many
// instances share it; whether it exists and starts as a STEP file is checked
// at open, so a missing or broken file is a host diagnostic in the report
// and the XML's mass properties still make the model.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "host_adapters/common/file_error.h"
#include "host_adapters/common/file_input.h"
#include "host_adapters/memory/memory_host.h"
#include "simscape_model.h"

namespace mbx_files {

class SimscapeAdapter final : public FileInput {
public:
    static std::unique_ptr<SimscapeAdapter> open(const std::string& xml_path, const FileInputOptions& options = {});
    ~SimscapeAdapter() override;
    SimscapeAdapter(const SimscapeAdapter&) = delete;
    SimscapeAdapter& operator=(const SimscapeAdapter&) = delete;

    const mbx_host* table() const override;
    const mbx_memory::Assembly& assembly() const;
    const SimscapeModel& model() const;
    const mbx_memory::Host& host() const;
    // Part uid -> the STEP file found for it (missing or unreadable ones excluded).
    const std::map<std::string, std::string>& geometry_files() const;

    struct Lazy;  // the parts' meshes, shared with the host's shape source

private:
    SimscapeAdapter() = default;

    SimscapeModel model_;
    std::map<std::string, std::string> geometry_files_;
    std::shared_ptr<Lazy> lazy_;
    std::unique_ptr<mbx_memory::Host> host_;  // last: destroyed before what its shape source uses
};

}  // namespace mbx_files
