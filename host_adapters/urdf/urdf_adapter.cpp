#include "urdf_adapter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "host_adapters/common/mesh_file.h"
#include "host_adapters/common/primitive_meshes.h"
#include "urdf_assembly.h"
#include "urdf_reader.h"

namespace mbx_files {

namespace fs = std::filesystem;

namespace {

// The visual's material colour, for the view and the glTF scene (alpha 0
// would mean "none" to the SDK: a transparent material is drawn faintly).
void set_colour(mbx_memory::Mesh& m, const UrdfColour& c) {
    if (!c.given) return;
    for (int k = 0; k < 4; ++k) m.color[k] = std::clamp(c.rgba[k], 0.0, 1.0);
    m.color[3] = std::max(m.color[3], 0.05);
}

}  // namespace

// One mesh file of a link: where it is, how it is scaled and placed.
struct UrdfAdapter::Lazy {
    struct File {
        std::string path, written;
        Eigen::Vector3d scale = Eigen::Vector3d::Ones();
        Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // in the link frame
        int line = 0;
        UrdfColour colour;
    };
    struct Loaded {
        bool tried = false, ok = false;
        mbx_memory::Mesh mesh;  // in the file's numbers, unscaled
        std::string error;
    };
    std::string urdf_file;
    std::map<std::string, std::vector<File>> by_link;
    std::map<std::string, Loaded> loaded;  // by path: a file shared by links loads once
    mbx_memory::Host* host = nullptr;

    bool load(const mbx_memory::Body& body, std::vector<mbx_memory::Mesh>& out) {
        const auto files = by_link.find(body.id);
        if (files == by_link.end()) return true;
        for (const File& f : files->second) {
            Loaded& l = loaded[f.path];
            if (!l.tried) {
                l.tried = true;
                l.ok = load_mesh_file(f.path, l.mesh, l.error, 1.0);
                if (!l.ok && host) {
                    mbx_memory::Diagnostic d;
                    d.code = "mesh_file_unreadable";
                    d.subject_kind = MBX_SUBJECT_BODY;
                    d.subject_id = d.subject_name = body.id;
                    d.file = urdf_file;
                    d.line = f.line;
                    d.message = "mesh file '" + f.path + "' of link '" + body.id + "' could not be read: " + l.error +
                                "; the link gets no shape from it";
                    host->add_diagnostic(std::move(d));
                }
            }
            if (!l.ok) continue;
            mbx_memory::Mesh m = l.mesh;
            m.name = body.id + ":" + fs::path(f.path).filename().string();
            for (size_t v = 0; v < m.vertices.size(); ++v) m.vertices[v] *= f.scale[long(v % 3)];
            if (f.scale.prod() < 0)  // a mirroring scale turns the triangles inside out
                for (size_t t = 0; t + 2 < m.triangles.size(); t += 3) std::swap(m.triangles[t + 1], m.triangles[t + 2]);
            set_colour(m, f.colour);
            // The file's own node transforms are already in its vertices; the origin places the file.
            for (int i = 0; i < 3; ++i) {
                m.pose.position[i] = f.origin.translation()[i];
                for (int j = 0; j < 3; ++j) m.pose.rotation[3 * i + j] = f.origin.linear()(i, j);
            }
            out.push_back(std::move(m));
        }
        return true;
    }
};

namespace {

std::string number(double x) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", x);
    return buffer;
}

std::string attribute_text(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '&') out += "&amp;";
        else if (c == '<') out += "&lt;";
        else if (c == '"') out += "&quot;";
        else out += c;
    }
    return out;
}

// A primitive's mesh in the link frame. VRML's cylinder stands along y, URDF's along z.
mbx_memory::Mesh primitive_mesh(const std::string& link, const UrdfShape& s) {
    VrmlMesh v;
    Eigen::Isometry3d at = s.origin.pose();
    const UrdfGeometry& g = s.geometry;
    if (g.kind == UrdfGeometry::Kind::box) {
        v = vrml::box_mesh(g.size.x(), g.size.y(), g.size.z());
    } else if (g.kind == UrdfGeometry::Kind::sphere) {
        v = vrml::sphere_mesh(g.radius);
    } else {
        v = vrml::cylinder_mesh(g.radius, g.length, true, true, true);
        at = at * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX());
    }
    mbx_memory::Mesh m;
    m.name = link + ":" + (s.name.empty() ? std::string(g.kind == UrdfGeometry::Kind::box      ? "box"
                                                          : g.kind == UrdfGeometry::Kind::sphere ? "sphere"
                                                                                                 : "cylinder")
                                          : s.name);
    m.pose = urdf_pose(at);
    m.vertices = std::move(v.vertices);
    m.triangles = std::move(v.triangles);
    set_colour(m, s.colour);
    return m;
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

bool exists(const std::string& path) {
    std::error_code ec;
    return fs::is_regular_file(path, ec);
}

}  // namespace

std::string resolve_urdf_path(const std::string& filename, const std::string& urdf_dir,
                              const std::vector<std::pair<std::string, std::string>>& packages,
                              const std::string& ros_package_path, std::string* tried) {
    if (starts_with(filename, "file://")) return filename.substr(7);
    if (!starts_with(filename, "package://"))
        return fs::path(filename).is_absolute() ? filename : (fs::path(urdf_dir) / filename).string();
    const std::string rest = filename.substr(10);
    std::vector<std::string> places;
    // The longest given package name that is a whole-segment prefix of the path.
    const std::pair<std::string, std::string>* best = nullptr;
    for (const auto& p : packages) {
        std::string name = p.first;
        while (!name.empty() && name.back() == '/') name.pop_back();
        if (name.empty() || !starts_with(rest, name) || (rest.size() > name.size() && rest[name.size()] != '/')) continue;
        if (!best || name.size() > best->first.size()) best = &p;
    }
    if (best) {
        std::string name = best->first;
        while (!name.empty() && name.back() == '/') name.pop_back();
        const std::string candidate = (fs::path(best->second) / rest.substr(std::min(rest.size(), name.size() + 1))).string();
        if (exists(candidate)) return candidate;
        places.push_back(candidate);
    }
    const size_t slash = rest.find('/');
    const std::string package = rest.substr(0, slash);
    const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
    size_t start = 0;
    while (start <= ros_package_path.size()) {
        const size_t colon = std::min(ros_package_path.find(':', start), ros_package_path.size());
        const std::string dir = ros_package_path.substr(start, colon - start);
        start = colon + 1;
        if (dir.empty()) continue;
        for (const fs::path& candidate :
             {fs::path(dir).filename() == package ? fs::path(dir) / inside : fs::path(dir) / package / inside}) {
            if (exists(candidate.string())) return candidate.string();
            places.push_back(candidate.string());
        }
    }
    if (tried) {
        *tried = places.empty() ? "no --package-path names package '" + package + "' and ROS_PACKAGE_PATH is empty"
                                : "looked for it as";
        for (size_t k = 0; k < places.size() && k < 4; ++k) *tried += (k ? ", " : " ") + places[k];
    }
    return "";
}

std::unique_ptr<UrdfAdapter> UrdfAdapter::open(const std::string& path, const FileInputOptions& options) {
    std::unique_ptr<UrdfAdapter> self(new UrdfAdapter());
    self->model_ = read_urdf(path);
    const UrdfModel& model = self->model_;
    UrdfAssemblyOptions assembly_options;
    assembly_options.floating_base = options.floating_base;
    UrdfAssembly built = to_assembly(model, assembly_options);
    mbx_memory::Assembly& a = built.assembly;

    auto lazy = std::make_shared<Lazy>();
    lazy->urdf_file = model.file;
    std::string urdf_dir = fs::path(path).parent_path().string();
    if (urdf_dir.empty()) urdf_dir = ".";
    const char* ros = std::getenv("ROS_PACKAGE_PATH");
    const std::string ros_package_path = ros ? ros : "";
    // A link's shapes: its visuals, or its collisions where it has none.
    for (const UrdfLink& link : model.links) {
        const std::vector<UrdfShape>& shapes = link.visuals.empty() ? link.collisions : link.visuals;
        for (const UrdfShape& s : shapes) {
            if (!s.has_geometry) continue;
            if (s.geometry.kind != UrdfGeometry::Kind::mesh) {
                a.shapes[link.name].push_back(primitive_mesh(link.name, s));
                continue;
            }
            std::string tried;
            const std::string file = resolve_urdf_path(s.geometry.filename, urdf_dir, options.package_paths,
                                                       ros_package_path, &tried);
            std::string why;
            if (file.empty() || !exists(file) || !probe_mesh_file(file, why)) {
                mbx_memory::Diagnostic d;
                d.code = file.empty() || !exists(file) ? "mesh_file_missing" : "mesh_file_unreadable";
                d.subject_kind = MBX_SUBJECT_BODY;
                d.subject_id = d.subject_name = link.name;
                d.file = model.file;
                d.line = s.line;
                d.message = "mesh file '" + s.geometry.filename + "' of link '" + link.name + "' " +
                            (file.empty() ? "was not found (" + tried + ")"
                             : !exists(file) ? "was not found (as " + file + ")"
                                             : "cannot be read: " + why) +
                            "; the link gets no shape from it";
                a.diagnostics.push_back(std::move(d));
                continue;
            }
            self->mesh_files_[s.geometry.filename] = file;
            lazy->by_link[link.name].push_back({file, s.geometry.filename, s.geometry.scale, s.origin.pose(), s.line, s.colour});
        }
    }

    // The file's own description: joint dynamics and collision shapes.
    std::string text;
    for (const UrdfJoint& j : model.joints) {
        if (!j.has_dynamics || (j.damping == 0 && j.friction == 0)) continue;
        if (j.type != "revolute" && j.type != "continuous" && j.type != "prismatic") continue;
        text += "  <joint constraint=\"" + attribute_text(j.name) + "\" damping=\"" + number(j.damping) +
                "\" coulomb=\"" + number(j.friction) + "\"/>\n";
    }
    for (const UrdfLink& link : model.links) {
        for (const UrdfShape& s : link.collisions) {
            if (!s.has_geometry) continue;
            const UrdfGeometry& g = s.geometry;
            std::string shape = "  <collision body=\"" + attribute_text(link.name) + "\"";
            if (!s.name.empty()) shape += " name=\"" + attribute_text(s.name) + "\"";
            if (g.kind == UrdfGeometry::Kind::mesh) {
                // One hull per link: a link's several collision meshes are one shape.
                if (text.find("<collision body=\"" + attribute_text(link.name) + "\" shape=\"hull\"") != std::string::npos)
                    continue;
                text += "  <collision body=\"" + attribute_text(link.name) + "\" shape=\"hull\"/>\n";
                continue;
            }
            if (g.kind == UrdfGeometry::Kind::box)
                shape += " shape=\"box\" size=\"" + number(g.size.x()) + " " + number(g.size.y()) + " " + number(g.size.z()) + "\"";
            else if (g.kind == UrdfGeometry::Kind::sphere)
                shape += " shape=\"sphere\" radius=\"" + number(g.radius) + "\"";
            else
                shape += " shape=\"cylinder\" radius=\"" + number(g.radius) + "\" length=\"" + number(g.length) + "\"";
            shape += " xyz=\"" + number(s.origin.xyz.x()) + " " + number(s.origin.xyz.y()) + " " + number(s.origin.xyz.z()) +
                     "\" rpy=\"" + number(s.origin.rpy.x()) + " " + number(s.origin.rpy.y()) + " " +
                     number(s.origin.rpy.z()) + "\"/>\n";
            text += shape;
        }
    }
    if (!text.empty())
        self->description_ = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- from " + attribute_text(model.file) +
                             " -->\n<mechatronics version=\"1\">\n" + text + "</mechatronics>\n";

    self->lazy_ = lazy;
    mbx_memory::ShapeSource source = [lazy](const mbx_memory::Body& body, std::vector<mbx_memory::Mesh>& out,
                                            std::string&) { return lazy->load(body, out); };
    self->host_ = std::make_unique<mbx_memory::Host>(std::move(a), mbx_memory::Faults{}, std::move(source));
    lazy->host = self->host_.get();
    return self;
}

UrdfAdapter::~UrdfAdapter() = default;

const mbx_host* UrdfAdapter::table() const { return host_->table(); }
std::string UrdfAdapter::description() const { return description_; }
const UrdfModel& UrdfAdapter::model() const { return model_; }
const mbx_memory::Assembly& UrdfAdapter::assembly() const { return host_->assembly(); }
const std::map<std::string, std::string>& UrdfAdapter::mesh_files() const { return mesh_files_; }

}  // namespace mbx_files
