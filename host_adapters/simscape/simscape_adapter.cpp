#include "simscape_adapter.h"

#include <filesystem>

#include "host_adapters/common/mesh_file.h"
#include "simscape_assembly.h"
#include "simscape_reader.h"

namespace mbx_files {

struct SimscapeAdapter::Lazy {
    struct Source {
        std::string path, part_name;
        int line = 0;
        bool tried = false, loaded = false;
        mbx_memory::Mesh mesh;  // the part's, shared by its instances
        std::string error;
    };
    std::string xml_file;
    double unit_m = 1;
    std::map<int, Source> parts;              // by part index
    std::map<std::string, int> part_of_body;  // body id -> part index
    mbx_memory::Host* host = nullptr;

    bool load(const mbx_memory::Body& body, std::vector<mbx_memory::Mesh>& out) {
        const auto b = part_of_body.find(body.id);
        if (b == part_of_body.end()) return true;
        const auto it = parts.find(b->second);
        if (it == parts.end()) return true;
        Source& s = it->second;
        if (!s.tried) {
            s.tried = true;
            s.loaded = load_mesh_file(s.path, s.mesh, s.error, unit_m);
            if (!s.loaded && host) {
                mbx_memory::Diagnostic d;
                d.code = "mesh_file_unreadable";
                d.subject_kind = MBX_SUBJECT_BODY;
                d.subject_id = body.id;
                d.subject_name = body.name;
                d.file = xml_file;
                d.line = s.line;
                d.message = "STEP file '" + s.path + "' of part '" + s.part_name + "' could not be read: " +
                            s.error + "; its instances get no shape from it";
                host->add_diagnostic(std::move(d));
            }
        }
        if (s.loaded) out.push_back(s.mesh);
        return true;  // a broken part file must not fail the translation
    }
};

namespace {

namespace fs = std::filesystem;

mbx_memory::Diagnostic part_diagnostic(const SimscapeModel& model, const SimscapePart& part, const char* code,
                                       const std::string& message) {
    mbx_memory::Diagnostic d;
    d.severity = MBX_SEVERITY_WARNING;
    d.code = code;
    d.subject_kind = MBX_SUBJECT_FILE;
    d.subject_id = part.uid;
    d.subject_name = part.name;
    d.file = model.file;
    d.line = part.geometry_line;
    d.message = message;
    return d;
}

}  // namespace

std::unique_ptr<SimscapeAdapter> SimscapeAdapter::open(const std::string& xml_path, const FileInputOptions& options) {
    std::unique_ptr<SimscapeAdapter> self(new SimscapeAdapter());
    self->model_ = read_simscape(xml_path);
    const SimscapeModel& model = self->model_;
    SimscapeAssembly built = to_assembly(model);

    auto lazy = std::make_shared<Lazy>();
    lazy->xml_file = model.file;
    lazy->unit_m = model.length_to_m;
    std::vector<std::string> dirs{fs::path(xml_path).parent_path().string()};
    if (dirs[0].empty()) dirs[0] = ".";
    dirs.insert(dirs.end(), options.mesh_dirs.begin(), options.mesh_dirs.end());
    MeshFileFinder finder(dirs);
    std::vector<bool> used(model.parts.size(), false);
    for (const SimscapeBodyPart& bp : built.body_parts) used[size_t(bp.part)] = true;
    for (size_t k = 0; k < model.parts.size(); ++k) {
        const SimscapePart& part = model.parts[k];
        if (!used[k] || part.geometry_file.empty()) continue;
        const std::string path = finder.find(part.geometry_file);
        std::string why;
        if (path.empty()) {
            built.assembly.diagnostics.push_back(part_diagnostic(
                model, part, "mesh_file_missing",
                "STEP file '" + part.geometry_file + "' of part '" + part.name + "' was not found (searched " +
                    std::to_string(dirs.size()) + " directories, ignoring case); its instances get no shape from it"));
        } else if (!probe_mesh_file(path, why)) {
            built.assembly.diagnostics.push_back(
                part_diagnostic(model, part, "mesh_file_unreadable",
                                "STEP file '" + path + "' of part '" + part.name + "' cannot be read: " + why +
                                    "; its instances get no shape from it"));
        } else {
            self->geometry_files_[part.uid] = path;
            Lazy::Source source;
            source.path = path;
            source.part_name = part.name;
            source.line = part.geometry_line;
            lazy->parts[int(k)] = std::move(source);
        }
    }
    for (const SimscapeBodyPart& bp : built.body_parts) lazy->part_of_body[bp.body_id] = bp.part;

    self->lazy_ = lazy;
    mbx_memory::ShapeSource source = [lazy](const mbx_memory::Body& body, std::vector<mbx_memory::Mesh>& out,
                                            std::string&) { return lazy->load(body, out); };
    self->host_ =
        std::make_unique<mbx_memory::Host>(std::move(built.assembly), mbx_memory::Faults{}, std::move(source));
    lazy->host = self->host_.get();
    return self;
}

SimscapeAdapter::~SimscapeAdapter() = default;

const mbx_host* SimscapeAdapter::table() const { return host_->table(); }
const mbx_memory::Assembly& SimscapeAdapter::assembly() const { return host_->assembly(); }
const SimscapeModel& SimscapeAdapter::model() const { return model_; }
const mbx_memory::Host& SimscapeAdapter::host() const { return *host_; }
const std::map<std::string, std::string>& SimscapeAdapter::geometry_files() const { return geometry_files_; }

}  // namespace mbx_files
