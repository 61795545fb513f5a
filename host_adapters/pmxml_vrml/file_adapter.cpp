#include "file_adapter.h"

#include <algorithm>
#include <filesystem>

#include "host_adapters/common/mesh_file.h"
#include "pmxml_assembly.h"
#include "pmxml_reader.h"
#include "vrml_reader.h"

namespace mbx_files {

struct FileAdapter::Lazy {
    struct Source {
        std::string path, body_name;
        int line = 0;
        double unit_m = 0;  // the body's length unit, which a STEP mesh is given in
    };
    std::string xml_file;
    std::map<std::string, Source> files;  // by body id
    std::vector<mbx_memory::Diagnostic> late;
    mbx_memory::Host* host = nullptr;  // serves `late` too, so they become findings

    bool load(const mbx_memory::Body& body, std::vector<mbx_memory::Mesh>& out) {
        const auto it = files.find(body.id);
        if (it == files.end()) return true;
        mbx_memory::Mesh mesh;
        std::string error;
        if (load_mesh_file(it->second.path, mesh, error, it->second.unit_m)) {
            out.push_back(std::move(mesh));
            return true;
        }
        mbx_memory::Diagnostic d;
        d.code = "mesh_file_unreadable";
        d.subject_kind = MBX_SUBJECT_BODY;
        d.subject_id = body.id;
        d.subject_name = it->second.body_name;
        d.file = xml_file;
        d.line = it->second.line;
        d.message = "mesh file '" + it->second.path + "' of body '" + it->second.body_name +
                    "' could not be read: " + error + "; the body gets no mesh from it";
        if (host) host->add_diagnostic(d);
        late.push_back(std::move(d));
        return true;  // a broken mesh must not fail the translation
    }
};

namespace {

namespace fs = std::filesystem;

mbx_memory::Diagnostic body_diagnostic(const PmxmlModel& model, const PmxmlBody& body, const char* code,
                                       const std::string& message) {
    mbx_memory::Diagnostic d;
    d.severity = MBX_SEVERITY_WARNING;
    d.code = code;
    d.subject_kind = MBX_SUBJECT_BODY;
    d.subject_id = body.id;
    d.subject_name = body.name;
    d.file = model.file;
    d.line = body.geometry_line;
    d.message = message;
    return d;
}

std::string directory_list(const std::vector<std::string>& dirs) {
    std::string out;
    for (const std::string& d : dirs) out += (out.empty() ? "'" : ", '") + d + "'";
    return out;
}

bool excluded_from_matching(const PmxmlBody& b) { return (b.flags & (MBX_BODY_GROUND | MBX_BODY_HELPER)) != 0; }

VrmlScene read_scene(const std::string& path) {
    try {
        return read_vrml(path);
    } catch (const VrmlError& e) {
        // VrmlError's text already starts with "file:line: "; FileError adds it again.
        std::string message = e.what();
        const std::string prefix = e.file() + ":" + std::to_string(e.line()) + ": ";
        if (message.compare(0, prefix.size(), prefix) == 0) message.erase(0, prefix.size());
        throw FileError(e.file(), e.line(), message);
    } catch (const std::exception& e) {
        throw FileError(path, 0, std::string("cannot read the VRML scene: ") + e.what());
    }
}

}  // namespace

// Sub-directories of `root` breadth first, in name order (deterministic),
// at most `max_depth` levels and `max_count` directories; unreadable ones are skipped.
static void append_subdirectories(const std::string& root, int max_depth, size_t max_count, std::vector<std::string>& out) {
    std::vector<fs::path> level{fs::path(root)};
    size_t added = 0;
    for (int depth = 0; depth < max_depth && !level.empty() && added < max_count; ++depth) {
        std::vector<fs::path> next;
        for (const fs::path& dir : level) {
            std::error_code ec;
            std::vector<fs::path> children;
            for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
                if (it->is_directory(ec) && !it->is_symlink(ec)) children.push_back(it->path());
            std::sort(children.begin(), children.end());
            for (const fs::path& c : children) {
                if (added++ >= max_count) break;
                out.push_back(c.string());
                next.push_back(c);
            }
        }
        level = std::move(next);
    }
}

std::unique_ptr<FileAdapter> FileAdapter::open(const std::string& xml_path, const FileAdapterOptions& options) {
    std::unique_ptr<FileAdapter> self(new FileAdapter());
    self->model_ = read_pmxml(xml_path);
    const PmxmlModel& model = self->model_;
    mbx_memory::Assembly assembly = to_assembly(model);

    auto lazy = std::make_shared<Lazy>();
    lazy->xml_file = model.file;
    std::vector<std::string> dirs{fs::path(xml_path).parent_path().string()};
    if (dirs[0].empty()) dirs[0] = ".";
    dirs.insert(dirs.end(), options.mesh_dirs.begin(), options.mesh_dirs.end());
    // Exports are often reorganised into meshes/<exporter>/ beside the XML;
    // after the directories named above, look a few levels down.
    append_subdirectories(dirs[0], 3, 256, dirs);
    MeshFileFinder finder(dirs);
    for (const PmxmlBody& b : model.bodies) {
        if (b.geometry_file.empty()) continue;
        const std::string path = finder.find(b.geometry_file);
        std::string why;
        if (path.empty())
            assembly.diagnostics.push_back(body_diagnostic(model, b, "mesh_file_missing",
                                                           "mesh file '" + b.geometry_file + "' of body '" + b.name +
                                                               "' was not found (searched " + directory_list(dirs) +
                                                               ", ignoring case); the body gets no mesh from it"));
        else if (!probe_mesh_file(path, why))
            assembly.diagnostics.push_back(body_diagnostic(model, b, "mesh_file_unreadable",
                                                           "mesh file '" + path + "' of body '" + b.name +
                                                               "' cannot be read: " + why +
                                                               "; the body gets no mesh from it"));
        else {
            self->mesh_files_[b.id] = path;
            const double unit_m = b.cs1 >= 0 && size_t(b.cs1) < model.frames.size() ? model.frames[size_t(b.cs1)].length_to_m : 0;
            lazy->files[b.id] = {path, b.name, b.geometry_line, unit_m};
        }
    }

    if (!options.shapes_path.empty()) {
        const VrmlScene scene = read_scene(options.shapes_path);
        // Candidates are the real parts, in the model's length unit (the
        // first part's; every real file uses one length unit throughout).
        std::vector<BodyPose> poses;
        std::vector<int> body_of;  // candidate -> model body
        double model_unit = 0;
        for (size_t i = 0; i < model.bodies.size(); ++i) {
            const PmxmlBody& b = model.bodies[i];
            if (excluded_from_matching(b)) continue;
            const PmxmlFrame& cs1 = model.frames[size_t(b.cs1)];
            if (model_unit == 0) model_unit = cs1.length_to_m;
            BodyPose p;
            p.id = b.id;
            p.name = b.name;
            p.world = Eigen::Isometry3d::Identity();
            p.world.linear() = nearest_rotation(cs1.rotation);
            p.world.translation() = cs1.position * (cs1.length_to_m / model_unit);
            poses.push_back(std::move(p));
            body_of.push_back(int(i));
        }
        try {
            self->matching_ = match_shapes(scene, poses, options.match);
        } catch (const std::exception& e) {
            throw FileError(options.shapes_path, 0,
                            std::string("cannot match the VRML shapes to the bodies: ") + e.what());
        }
        for (MatchedMesh& m : self->matching_.meshes) {
            if (m.body < 0 || size_t(m.body) >= body_of.size()) continue;
            const PmxmlBody& b = model.bodies[size_t(body_of[size_t(m.body)])];
            if (self->mesh_files_.count(b.id)) {
                ++self->superseded_;
                continue;
            }
            // The host hands meshes over in the body's length unit.
            const double scale = model_unit / model.frames[size_t(b.cs1)].length_to_m;
            mbx_memory::Mesh mesh;
            mesh.name = m.name;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) mesh.pose.rotation[3 * r + c] = r == c ? 1.0 : 0.0;
            mesh.vertices = m.vertices;
            if (scale != 1.0)
                for (double& v : mesh.vertices) v *= scale;
            mesh.triangles = m.triangles;
            assembly.shapes[b.id].push_back(std::move(mesh));
        }
        for (const MatchIssue& issue : self->matching_.issues) {
            mbx_memory::Diagnostic d;
            d.severity = MBX_SEVERITY_WARNING;
            d.code = issue.kind == MatchIssue::ambiguous ? "vrml_ambiguous_shape" : "vrml_unmatched_shape";
            d.subject_kind = MBX_SUBJECT_FILE;
            d.file = options.shapes_path;
            if (issue.node >= 0 && size_t(issue.node) < scene.nodes.size()) {
                const VrmlNode& node = scene.nodes[size_t(issue.node)];
                d.subject_id = node.name.empty() ? "node#" + std::to_string(issue.node) : node.name;
                d.subject_name = node.part_name.empty() ? node.name : node.part_name;
                if (!node.file.empty()) d.file = node.file;
                d.line = node.line;
            }
            d.message = issue.message;
            assembly.diagnostics.push_back(std::move(d));
        }
        for (const std::string& w : scene.warnings) {
            mbx_memory::Diagnostic d;
            d.severity = MBX_SEVERITY_INFO;
            d.code = "vrml_reader_warning";
            d.subject_kind = MBX_SUBJECT_FILE;
            d.subject_id = options.shapes_path;
            d.file = options.shapes_path;
            d.message = w;
            assembly.diagnostics.push_back(std::move(d));
        }
    }

    self->lazy_ = lazy;
    mbx_memory::ShapeSource source = [lazy](const mbx_memory::Body& body, std::vector<mbx_memory::Mesh>& out,
                                            std::string&) { return lazy->load(body, out); };
    self->host_ = std::make_unique<mbx_memory::Host>(std::move(assembly), mbx_memory::Faults{}, std::move(source));
    lazy->host = self->host_.get();
    return self;
}

FileAdapter::~FileAdapter() = default;

const mbx_host* FileAdapter::table() const { return host_->table(); }
const mbx_memory::Assembly& FileAdapter::assembly() const { return host_->assembly(); }
const PmxmlModel& FileAdapter::model() const { return model_; }
const mbx_memory::Host& FileAdapter::host() const { return *host_; }
const std::map<std::string, std::string>& FileAdapter::mesh_files() const { return mesh_files_; }
const MatchResult& FileAdapter::matching() const { return matching_; }
size_t FileAdapter::superseded_vrml_meshes() const { return superseded_; }
std::vector<mbx_memory::Diagnostic> FileAdapter::late_diagnostics() const { return lazy_->late; }

}  // namespace mbx_files
