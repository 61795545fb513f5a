// Shared by the exporter tests: translate an in-memory assembly with the SDK's
// own pipeline (white box, so tests can compare against mbx's forward
// kinematics), export it, and write the files to a temporary directory.
#pragma once
#include <memory>
#include <string>

#include <doctest/doctest.h>

#include "core/assembly/host_reader.h"
#include "core/assembly/shape_loader.h"
#include "export/common/export_model.h"
#include "export/export_files.h"
#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "core/kinematics/forward_kinematics.h"
#include "host_adapters/memory/memory_host.h"
#include "apps/stub_host/assemblies/stub_assembly.h"
#include "temp_dir.h"
#include "core/translator/translate.h"

namespace xtest {

// A translated model that keeps its host, so meshes can still be fetched.
struct Translated {
    std::shared_ptr<void> owner;    // what keeps `table` alive (a memory Host, a FileAdapter)
    const mbx_host* table = nullptr;
    std::unique_ptr<mbx::Mechanism> mechanism;
    std::vector<std::unique_ptr<std::vector<mbx::Mesh>>> shapes;

    const std::vector<mbx::Mesh>& body_shapes(int body) {
        if (shapes.size() < mechanism->bodies.size()) shapes.resize(mechanism->bodies.size());
        auto& s = shapes[size_t(body)];
        if (!s) s = std::make_unique<std::vector<mbx::Mesh>>(mbx::load_body_shapes(*table, *mechanism, body));
        return *s;
    }
};

// Translates whatever `table` serves; `owner` keeps the table alive.
inline std::unique_ptr<Translated> translate_table(const mbx_host* table, std::shared_ptr<void> owner) {
    auto t = std::make_unique<Translated>();
    t->owner = std::move(owner);
    t->table = table;
    mbx::Progress progress(nullptr, nullptr);
    mbx::Findings findings;
    mbx::Assembly a = mbx::read_host(table, mbx::HostReadOptions{}, progress, findings);
    t->mechanism = mbx::translate_assembly(std::move(a), std::move(findings), mbx::TranslateOptions{}, progress);
    return t;
}

inline std::unique_ptr<Translated> translate(mbx_memory::Assembly assembly, mbx_memory::ShapeSource source = {}) {
    auto host = std::make_shared<mbx_memory::Host>(std::move(assembly), mbx_memory::Faults{}, std::move(source));
    return translate_table(host->table(), host);
}

// A PMXML file (with optional VRML shapes and mesh folders) through the file adapter.
inline std::unique_ptr<Translated> translate_file(const std::string& xml, mbx_files::FileAdapterOptions options = {}) {
    std::shared_ptr<mbx_files::FileAdapter> adapter = mbx_files::FileAdapter::open(xml, options);
    return translate_table(adapter->table(), adapter);
}

inline std::unique_ptr<Translated> translate_builtin(const std::string& name) {
    mbx_memory::Assembly a;
    REQUIRE(mbx_stub::builtin_assembly(name, a));
    return translate(std::move(a));
}

// Export model over a translation (geometry from its host).
inline mbx::ExportModel export_model(Translated& t, mbx::ExportSettings settings = {}) {
    Translated* tp = &t;
    return mbx::ExportModel(*t.mechanism, [tp](int body) -> const std::vector<mbx::Mesh>& { return tp->body_shapes(body); },
                            std::move(settings));
}

// Runs the exporters for `formats` and writes the files below `dir`.
inline mbx::OutputFiles export_to(Translated& t, const mbx_test::TempDir& dir, uint32_t formats,
                                  mbx::ExportSettings settings = {}) {
    mbx::ExportModel model = export_model(t, std::move(settings));
    mbx::OutputFiles files = mbx::export_files(model, formats);
    mbx::write_output_files(dir.path.string(), files);
    return files;
}

inline const mbx::OutputFile* find_file(const mbx::OutputFiles& files, const std::string& path) {
    for (const auto& f : files)
        if (f.path == path) return &f;
    return nullptr;
}

}  // namespace xtest
