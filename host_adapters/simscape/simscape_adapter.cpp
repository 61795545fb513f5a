#include "simscape_adapter.h"

#include <algorithm>
#include <filesystem>

#include "core/geometry/mesh_properties.h"
#include "data_units_inference.h"
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
        double colour[4] = {0, 0, 0, 0};  // the part's VisualProperties colour; alpha 0: none
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
        if (s.loaded) {
            out.push_back(s.mesh);
            for (int k = 0; k < 4; ++k) out.back().color[k] = s.colour[k];
        }
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

// A file without <DataUnits>: its units told by up to three parts' STEP
// solids (the smallest files, to keep the cost of opening low). The meshes
// read for it are kept, in the file's length unit, for the shapes.
void infer_units(SimscapeModel& model, const std::vector<std::string>& step_paths, std::map<int, mbx_memory::Mesh>& meshes) {
    std::vector<std::pair<uintmax_t, int>> candidates;
    for (size_t k = 0; k < model.parts.size(); ++k) {
        const SimscapePart& part = model.parts[k];
        std::error_code ec;
        if (!part.has_mass_properties || !(part.mass > 0) || step_paths[k].empty()) continue;
        const uintmax_t size = fs::file_size(step_paths[k], ec);
        if (!ec) candidates.push_back({size, int(k)});
    }
    std::sort(candidates.begin(), candidates.end());
    std::vector<UnitEvidence> evidence;
    std::vector<int> evidence_parts;
    for (const auto& [size, k] : candidates) {
        if (evidence.size() == 3) break;
        mbx_memory::Mesh mesh;
        std::string error;
        if (!load_mesh_file(step_paths[size_t(k)], mesh, error, 1.0)) continue;
        std::vector<mbx::Vec3> points(mesh.vertices.size() / 3);
        for (size_t v = 0; v < points.size(); ++v)
            points[v] = mbx::Vec3(mesh.vertices[3 * v], mesh.vertices[3 * v + 1], mesh.vertices[3 * v + 2]);
        mbx::SolidAccumulator solid;
        solid.add(points, mesh.triangles);
        const mbx::SolidProperties p = solid.result();
        const SimscapePart& part = model.parts[size_t(k)];
        evidence.push_back({part.name, part.mass, part.inertia, p.volume, p.inertia_per_density});
        evidence_parts.push_back(k);
        meshes[k] = std::move(mesh);
    }
    const InferredUnits units = infer_data_units(evidence, model.model_length_unit, model.model_mass_unit);
    model.length_to_m = units.length_to_m;
    model.mass_to_kg = units.mass_to_kg;
    for (mbx_memory::Diagnostic& d : model.diagnostics)
        if (d.code == "simscape_no_data_units") d.message = units.reason;
    for (auto& [k, mesh] : meshes)
        for (double& x : mesh.vertices) x /= units.length_to_m;
}

}  // namespace

std::unique_ptr<SimscapeAdapter> SimscapeAdapter::open(const std::string& xml_path, const FileInputOptions& options) {
    std::unique_ptr<SimscapeAdapter> self(new SimscapeAdapter());
    self->model_ = read_simscape(xml_path);
    SimscapeModel& model = self->model_;

    // Each part's STEP file: found and starting as STEP, or why not.
    std::vector<std::string> dirs{fs::path(xml_path).parent_path().string()};
    if (dirs[0].empty()) dirs[0] = ".";
    dirs.insert(dirs.end(), options.mesh_dirs.begin(), options.mesh_dirs.end());
    MeshFileFinder finder(dirs);
    std::vector<std::string> step_paths(model.parts.size()), problems(model.parts.size());
    std::vector<const char*> problem_codes(model.parts.size(), nullptr);
    for (size_t k = 0; k < model.parts.size(); ++k) {
        const SimscapePart& part = model.parts[k];
        if (part.geometry_file.empty()) continue;
        const std::string path = finder.find(part.geometry_file);
        std::string why;
        if (path.empty()) {
            problem_codes[k] = "mesh_file_missing";
            problems[k] = "STEP file '" + part.geometry_file + "' of part '" + part.name + "' was not found (searched " +
                          std::to_string(dirs.size()) + " directories, ignoring case); its instances get no shape from it";
        } else if (!probe_mesh_file(path, why)) {
            problem_codes[k] = "mesh_file_unreadable";
            problems[k] = "STEP file '" + path + "' of part '" + part.name + "' cannot be read: " + why +
                          "; its instances get no shape from it";
        } else {
            step_paths[k] = path;
        }
    }
    std::map<int, mbx_memory::Mesh> preloaded;
    if (!model.data_units_written) infer_units(model, step_paths, preloaded);

    SimscapeAssembly built = to_assembly(model);
    auto lazy = std::make_shared<Lazy>();
    lazy->xml_file = model.file;
    lazy->unit_m = model.length_to_m;
    std::vector<bool> used(model.parts.size(), false);
    for (const SimscapeBodyPart& bp : built.body_parts) used[size_t(bp.part)] = true;
    for (size_t k = 0; k < model.parts.size(); ++k) {
        if (!used[k]) continue;
        if (problem_codes[k]) {
            built.assembly.diagnostics.push_back(part_diagnostic(model, model.parts[k], problem_codes[k], problems[k]));
        } else if (!step_paths[k].empty()) {
            self->geometry_files_[model.parts[k].uid] = step_paths[k];
            Lazy::Source source;
            source.path = step_paths[k];
            source.part_name = model.parts[k].name;
            source.line = model.parts[k].geometry_line;
            if (model.parts[k].has_colour)
                for (int c = 0; c < 4; ++c) source.colour[c] = std::clamp(model.parts[k].colour[c], c == 3 ? 0.05 : 0.0, 1.0);
            const auto kept = preloaded.find(int(k));
            if (kept != preloaded.end()) {
                source.tried = source.loaded = true;
                source.mesh = std::move(kept->second);
            }
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
