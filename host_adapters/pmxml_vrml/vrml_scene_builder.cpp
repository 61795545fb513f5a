#include "vrml_scene_builder.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "vrml_inline_paths.h"
#include "host_adapters/common/primitive_meshes.h"

namespace fs = std::filesystem;

namespace mbx_files::vrml {
namespace {

constexpr size_t max_warnings = 1000;

std::string canonical_path(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::path(path), ec);
    if (ec) p = fs::absolute(fs::path(path), ec).lexically_normal();
    return p.string();
}

// The whole file, or an error message. Reads at most max_bytes + 1 bytes,
// so files whose size the file system misreports (pipes, /proc) are bounded too.
bool read_file(const std::string& path, size_t max_bytes, std::string& text, std::string& error) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        error = fs::exists(path, ec) ? "not a regular file" : "no such file";
        return false;
    }
    const auto size = fs::file_size(path, ec);
    if (!ec && size > max_bytes) {
        error =
            "file is " + std::to_string(size) + " bytes, more than max_file_bytes (" + std::to_string(max_bytes) + ")";
        return false;
    }
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) {
        error = "cannot open file";
        return false;
    }
    text.clear();
    text.resize(std::min(ec ? size_t(1) << 16 : static_cast<size_t>(size) + 1, max_bytes + 1));
    size_t used = 0;
    for (;;) {
        if (used == text.size()) text.resize(std::min(text.size() * 2, max_bytes + 1));
        const size_t got = std::fread(&text[used], 1, text.size() - used, f);
        used += got;
        if (got == 0 || used > max_bytes) break;
    }
    const bool failed = std::ferror(f) != 0;
    std::fclose(f);
    if (failed) {
        error = "read error";
        return false;
    }
    if (used > max_bytes) {
        error = "file is larger than max_file_bytes (" + std::to_string(max_bytes) + ")";
        return false;
    }
    text.resize(used);
    return true;
}

std::string describe(const Value& v) {
    switch (v.kind) {
        case Value::Kind::none: return "an empty list";
        case Value::Kind::numbers: return std::to_string(v.numbers.size()) + " number(s)";
        case Value::Kind::strings: return std::to_string(v.strings.size()) + " string(s)";
        case Value::Kind::bools: return std::to_string(v.bools.size()) + " boolean(s)";
        case Value::Kind::nodes: return "node(s)";
        case Value::Kind::is: return "IS " + v.is_name;
    }
    return "?";
}

std::string normalized(std::string_view name) {
    std::string s;
    for (char c : name)
        if (c != '_' && c != '-') s += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool is_info_proto(const std::string& name) { return normalized(name).find("info") != std::string::npos; }

}  // namespace

SceneBuilder::SceneBuilder(const VrmlLimits& limits) : limits_(limits) {}

VrmlScene SceneBuilder::build_from_file(const std::string& path) {
    std::string text, error;
    if (!read_file(path, limits_.max_file_bytes, text, error)) throw VrmlError(path, 0, error);
    return build_from_text(text, path);
}

VrmlScene SceneBuilder::build_from_text(std::string_view text, const std::string& path) {
    const std::string canonical = canonical_path(path);
    auto parsed = parse_vrml(text, path, limits_, budget_, stack_);
    const ParsedFile& main = *parsed;
    files_[canonical] = std::move(parsed);
    return build(main, canonical);
}

VrmlScene SceneBuilder::build(const ParsedFile& main, const std::string& canonical) {
    add_file_warnings(main);
    inline_stack_.push_back(canonical);
    const Ctx top;
    for (const AstNode* n : main.roots) eval_child(n, top);
    inline_stack_.pop_back();

    for (size_t i = 0; i < scene_.nodes.size(); ++i) {
        VrmlNode& node = scene_.nodes[i];
        if (!own_names_[i].empty())
            node.part_name = own_names_[i];
        else
            node.part_name = node.parent >= 0 ? scene_.nodes[static_cast<size_t>(node.parent)].part_name : root_name_;
    }
    if (suppressed_warnings_ > 0)
        scene_.warnings.push_back(std::to_string(suppressed_warnings_) + " more warnings not shown");
    return std::move(scene_);
}

const ParsedFile& SceneBuilder::load(const std::string& path, const std::string& canonical, const AstNode& from) {
    if (auto it = files_.find(canonical); it != files_.end()) return *it->second;
    std::string text, error;
    if (!read_file(path, limits_.max_file_bytes, text, error))
        fail(*from.file, from.line, {"cannot read Inline file '", path, "': ", error});
    auto parsed = parse_vrml(text, path, limits_, budget_, stack_);
    const ParsedFile& file = *parsed;
    files_[canonical] = std::move(parsed);
    add_file_warnings(file);
    return file;
}

// ---- messages and budgets ---------------------------------------------------

void SceneBuilder::add_file_warnings(const ParsedFile& file) {
    for (const std::string& w : file.warnings) {
        if (scene_.warnings.size() < max_warnings)
            scene_.warnings.push_back(w);
        else
            ++suppressed_warnings_;
    }
}

MBX_VRML_COLD void SceneBuilder::warn(const std::string& file, int line, std::initializer_list<Piece> message) {
    if (scene_.warnings.size() < max_warnings)
        scene_.warnings.push_back(file + ":" + std::to_string(line) + ": " + join(message));
    else
        ++suppressed_warnings_;
}

MBX_VRML_COLD void SceneBuilder::fail(const std::string& file, int line, std::initializer_list<Piece> message) const {
    throw VrmlError(file, line, join(message));
}

MBX_VRML_COLD void SceneBuilder::fail_type(const AstNode& n, const char* name, const Value& v,
                                           const char* expected) const {
    fail(*n.file, v.line, {n.type_name, ".", name, ": expected ", expected, ", found ", describe(v)});
}

MBX_VRML_COLD void SceneBuilder::fail_visit(const AstNode& n, size_t depth) const {
    if (budget_.visits > limits_.max_nodes)
        fail(*n.file, n.line,
             {"more than max_nodes (", limits_.max_nodes, ") node visits, counting USE and PROTO expansion"});
    if (depth >= limits_.max_depth)
        fail(*n.file, n.line,
             {"nodes nested deeper than max_depth (", limits_.max_depth, "), counting Inlines and PROTO expansion"});
    fail(*n.file, n.line, {"nodes nested too deeply for the stack left to the reader"});
}

void SceneBuilder::visit(const AstNode& n, size_t depth) {
    if (++budget_.visits > limits_.max_nodes || depth >= limits_.max_depth || stack_.exhausted()) fail_visit(n, depth);
}

void SceneBuilder::count_values(const AstNode& n, size_t count) {
    budget_.values += count;
    if (budget_.values > limits_.max_total_values)
        fail(*n.file, n.line,
             {"more than max_total_values (", limits_.max_total_values, ") values, counting the meshes built"});
}

MBX_VRML_COLD int SceneBuilder::emit(const AstNode& n, const std::string& kind, const std::string& file, int line,
                                     const Ctx& c, const Eigen::Affine3d& world) {
    if (scene_.nodes.size() >= limits_.max_nodes)
        fail(*n.file, n.line, {"more than max_nodes (", limits_.max_nodes, ") scene nodes"});
    if (!world.matrix().allFinite()) fail(*n.file, n.line, {"the accumulated transform is not finite"});
    VrmlNode& v = scene_.nodes.emplace_back();
    v.parent = c.parent;
    v.kind = kind;
    v.name = n.def_name;
    v.file = file;
    v.line = line;
    v.world = world;
    own_names_.emplace_back();
    return static_cast<int>(scene_.nodes.size() - 1);
}

// ---- part names -------------------------------------------------------------

void SceneBuilder::name_scope(int node, const std::string& name) {
    if (name.empty()) return;
    std::string& slot = node >= 0 ? own_names_[static_cast<size_t>(node)] : root_name_;
    if (slot.empty()) slot = name;
}

MBX_VRML_COLD void SceneBuilder::name_from_proto(const AstNode& instance, int node, const Ctx& c) {
    const std::string name = naming_value(instance, c.env);
    name_scope(node, name);
    if (is_info_proto(instance.type_name)) name_scope(c.parent, name);
}

std::string SceneBuilder::naming_value(const AstNode& instance, const Env* outer) const {
    const ProtoDecl& p = *instance.proto;
    std::vector<std::string_view> keys = {"partname", "modelname", "name"};
    if (is_info_proto(p.name)) keys.push_back("title");
    for (std::string_view key : keys) {
        for (const InterfaceField& f : p.interface) {
            if ((f.type != "SFString" && f.type != "MFString") || normalized(f.name) != key) continue;
            const Bound b = field(instance, f.name, outer);
            const Value* v = b.value ? b.value : (p.external ? nullptr : &f.default_value);
            if (v && v->kind == Value::Kind::strings && !v->strings.empty() && !v->strings.front().empty())
                return v->strings.front();
        }
    }
    return {};
}

// ---- field access -----------------------------------------------------------

SceneBuilder::Bound SceneBuilder::field(const AstNode& n, std::string_view name, const Env* env) const {
    const Field* f = n.find(name);
    return f ? resolve(f->value, env) : Bound{};
}

SceneBuilder::Bound SceneBuilder::resolve(const Value& value, const Env* env) const {
    Bound b{&value, env};
    // Interface values are never IS themselves, so one step resolves; the
    // bound only guards against a malformed tree.
    for (int step = 0; step < 8 && b.value && b.value->kind == Value::Kind::is; ++step) {
        if (!b.env || !b.env->proto) return {};
        const int i = b.env->proto->find(b.value->is_name);
        if (i < 0 || static_cast<size_t>(i) >= b.env->values.size()) return {};
        b = b.env->values[static_cast<size_t>(i)];
    }
    if (b.value && b.value->kind == Value::Kind::is) return {};
    return b;
}

SceneBuilder::Env SceneBuilder::make_env(const AstNode& instance, const Env* outer) const {
    Env e;
    e.proto = instance.proto;
    const auto& iface = instance.proto->interface;
    e.values.resize(iface.size());
    for (size_t i = 0; i < iface.size(); ++i)
        if (iface[i].kind == InterfaceField::Kind::field || iface[i].kind == InterfaceField::Kind::exposed_field)
            e.values[i] = {&iface[i].default_value, outer};
    for (const Field& f : instance.fields) {
        const int i = instance.proto->find(f.name);
        if (i < 0) continue;
        const Bound b = resolve(f.value, outer);
        if (b.value) e.values[static_cast<size_t>(i)] = b;
    }
    return e;
}

Eigen::Vector3d SceneBuilder::vec3(const AstNode& n, const char* name, const Env* env,
                                   const Eigen::Vector3d& fallback) const {
    const Bound b = field(n, name, env);
    if (!b.value) return fallback;
    const Value& v = *b.value;
    if (v.kind != Value::Kind::numbers || v.numbers.size() != 3) fail_type(n, name, v, "3 numbers");
    return {v.numbers[0], v.numbers[1], v.numbers[2]};
}

Eigen::AngleAxisd SceneBuilder::rotation(const AstNode& n, const char* name, const Env* env) {
    const Bound b = field(n, name, env);
    if (!b.value) return Eigen::AngleAxisd(0, Eigen::Vector3d::UnitZ());
    const Value& v = *b.value;
    if (v.kind != Value::Kind::numbers || v.numbers.size() != 4) fail_type(n, name, v, "4 numbers (axis, angle)");
    const Eigen::Vector3d axis(v.numbers[0], v.numbers[1], v.numbers[2]);
    const double norm = axis.norm();
    if (!(norm > 0) || !std::isfinite(norm)) {
        if (v.numbers[3] != 0) warn(*n.file, v.line, {n.type_name, ".", name, " has a zero axis; read as no rotation"});
        return Eigen::AngleAxisd(0, Eigen::Vector3d::UnitZ());
    }
    return Eigen::AngleAxisd(v.numbers[3], axis / norm);
}

double SceneBuilder::number(const AstNode& n, const char* name, const Env* env, double fallback) const {
    const Bound b = field(n, name, env);
    if (!b.value) return fallback;
    const Value& v = *b.value;
    if (v.kind != Value::Kind::numbers || v.numbers.size() != 1) fail_type(n, name, v, "1 number");
    return v.numbers[0];
}

bool SceneBuilder::boolean(const AstNode& n, const char* name, const Env* env, bool fallback) const {
    const Bound b = field(n, name, env);
    if (!b.value) return fallback;
    const Value& v = *b.value;
    if (v.kind != Value::Kind::bools || v.bools.size() != 1) fail_type(n, name, v, "TRUE or FALSE");
    return v.bools[0] != 0;
}

std::vector<std::string> SceneBuilder::strings(const AstNode& n, const char* name, const Env* env) const {
    const Bound b = field(n, name, env);
    if (!b.value || b.value->kind == Value::Kind::none) return {};
    if (b.value->kind != Value::Kind::strings) fail_type(n, name, *b.value, "strings");
    return b.value->strings;
}

const std::vector<const AstNode*>* SceneBuilder::nodes(const AstNode& n, const char* name, const Bound& b) const {
    if (!b.value || b.value->kind == Value::Kind::none) return nullptr;
    if (b.value->kind != Value::Kind::nodes) fail_type(n, name, *b.value, "nodes");
    return &b.value->nodes;
}

// ---- child nodes --------------------------------------------------------------
// These recurse once per nesting level: each case lives in its own function
// so the recursive path only carries the frames it needs.

void SceneBuilder::eval_child(const AstNode* n, const Ctx& c) {
    if (!n) return;
    visit(*n, c.depth);
    switch (n->type) {
        case NodeType::transform: return eval_transform(*n, c);
        case NodeType::group:
        case NodeType::anchor:
        case NodeType::billboard:
        case NodeType::collision: return eval_group(*n, c);
        case NodeType::switch_node:
        case NodeType::lod: return eval_switch_or_lod(*n, c);
        case NodeType::inline_node: return eval_inline(*n, c);
        case NodeType::shape: return eval_shape(*n, c);
        case NodeType::world_info: return eval_world_info(*n, c);
        case NodeType::proto_instance: return eval_proto_child(*n, c);
        case NodeType::externproto_instance: return eval_externproto_child(*n, c);
        case NodeType::indexed_face_set:
        case NodeType::box:
        case NodeType::sphere:
        case NodeType::cylinder:
        case NodeType::cone:
            return warn(*n->file, n->line, {"geometry node '", n->type_name, "' outside a Shape ignored"});
        default: return;  // lights, viewpoints, sensors, ... and unknown types (warned by the parser)
    }
}

void SceneBuilder::eval_transform(const AstNode& n, const Ctx& c) {
    const Eigen::Affine3d world = c.world * local_transform(n, c.env);
    const int idx = emit(n, n.type_name, *n.file, n.line, c, world);
    eval_children(n, "children", Ctx{idx, world, c.env, c.depth + 1});
}

// Out of line: the field reads and Eigen temporaries stay off the recursive path.
MBX_VRML_COLD Eigen::Affine3d SceneBuilder::local_transform(const AstNode& n, const Env* env) {
    const Eigen::Vector3d t = vec3(n, "translation", env, Eigen::Vector3d::Zero());
    const Eigen::Vector3d s = vec3(n, "scale", env, Eigen::Vector3d::Ones());
    const Eigen::Vector3d center = vec3(n, "center", env, Eigen::Vector3d::Zero());
    const Eigen::AngleAxisd r = rotation(n, "rotation", env);
    const Eigen::AngleAxisd sr = rotation(n, "scaleOrientation", env);
    // A zero scale folds everything below onto a plane, a line or a point:
    // masses and contact shapes from such meshes are nothing, so say so.
    if (s.x() == 0 || s.y() == 0 || s.z() == 0)
        warn(*n.file, n.line, {n.type_name, ".scale (", s.x(), " ", s.y(), " ", s.z(),
                               ") has a zero component: the geometry below it collapses to ",
                               (s.array() == 0).count() == 1 ? "a plane" : (s.array() == 0).count() == 2 ? "a line" : "a point"});
    // T * C * R * SR * S * -SR * -C, clause 6.52.
    Eigen::Affine3d local = Eigen::Affine3d::Identity();
    local.translate(t + center);
    local.rotate(r);
    local.rotate(sr);
    local.scale(s);
    local.rotate(sr.inverse());
    local.translate(-center);
    return local;
}

void SceneBuilder::eval_group(const AstNode& n, const Ctx& c) {
    const int idx = emit(n, n.type_name, *n.file, n.line, c, c.world);
    eval_children(n, "children", Ctx{idx, c.world, c.env, c.depth + 1});
}

void SceneBuilder::eval_children(const AstNode& n, const char* name, const Ctx& c) {
    const Bound b = field(n, name, c.env);
    const std::vector<const AstNode*>* list = nodes(n, name, b);
    if (!list) return;
    Ctx cc = c;
    cc.env = b.env;  // nodes given to a PROTO instance keep the instance site's IS scope
    for (const AstNode* child : *list) eval_child(child, cc);
}

void SceneBuilder::eval_switch_or_lod(const AstNode& n, const Ctx& c) {
    const bool is_switch = n.type == NodeType::switch_node;
    const int idx = emit(n, n.type_name, *n.file, n.line, c, c.world);
    const char* list_name = is_switch ? "choice" : "level";
    if (!n.find(list_name)) list_name = "children";  // X3D spelling, seen in exports
    const Bound b = field(n, list_name, c.env);
    const std::vector<const AstNode*>* list = nodes(n, list_name, b);
    if (!list) return;
    size_t chosen = 0;  // LOD: the first (most detailed) level
    if (is_switch) {
        const double which = number(n, "whichChoice", c.env, -1);
        if (which != std::floor(which)) fail(*n.file, n.line, {"Switch.whichChoice ", which, " is not an integer"});
        if (which < 0) return;
        if (which >= static_cast<double>(list->size()))
            return warn(*n.file, n.line,
                        {"Switch.whichChoice ", which, " is out of range (", list->size(), " choices): nothing shown"});
        chosen = static_cast<size_t>(which);
    }
    if (chosen < list->size()) eval_child((*list)[chosen], Ctx{idx, c.world, b.env, c.depth + 1});
}

void SceneBuilder::eval_proto_child(const AstNode& n, const Ctx& c) {
    const int idx = emit(n, n.type_name, *n.file, n.line, c, c.world);
    const Env env = make_env(n, c.env);
    name_from_proto(n, idx, c);
    if (!n.proto->body.empty()) eval_child(n.proto->body.front(), Ctx{idx, c.world, &env, c.depth + 1});
}

void SceneBuilder::eval_externproto_child(const AstNode& n, const Ctx& c) {
    const int idx = emit(n, n.type_name, *n.file, n.line, c, c.world);
    name_from_proto(n, idx, c);
}

void SceneBuilder::eval_world_info(const AstNode& n, const Ctx& c) {
    const std::vector<std::string> title = strings(n, "title", c.env);
    if (c.parent < 0) {
        if (!title_set_) {
            title_set_ = true;
            scene_.title = title.empty() ? std::string() : title.front();
            scene_.info = strings(n, "info", c.env);
        }
        return;
    }
    if (!title.empty()) name_scope(c.parent, title.front());
}

void SceneBuilder::eval_inline(const AstNode& n, const Ctx& c) {
    const Bound url_field = field(n, "url", c.env);
    static const std::vector<std::string> no_urls;
    const Value* url_value = url_field.value && url_field.value->kind != Value::Kind::none ? url_field.value : nullptr;
    if (url_value && url_value->kind != Value::Kind::strings) fail_type(n, "url", *url_value, "strings");
    const std::vector<std::string>& urls = url_value ? url_value->strings : no_urls;
    InlineUrl target;
    std::string tried;
    // Alternatives beyond the first few are not tried: each costs file
    // system calls, and a hostile list could hold millions.
    constexpr size_t max_urls = 16;
    if (urls.size() > max_urls)
        warn(*n.file, n.line, {"Inline has ", urls.size(), " urls; only the first ", max_urls, " are tried"});
    for (size_t u_index = 0; u_index < urls.size() && u_index < max_urls; ++u_index) {
        const std::string& url = urls[u_index];
        const InlineUrl u = resolver_.resolve(url, *n.file);
        if (u.status == InlineUrl::Status::found) {
            target = u;
            break;
        }
        if (u.status == InlineUrl::Status::remote) warn(*n.file, n.line, {"Inline url '", url, "' is remote; skipped"});
        tried += (tried.empty() ? "" : ", ") + (u.path.empty() ? url : u.path);
    }
    if (target.status != InlineUrl::Status::found) {
        if (urls.empty()) return warn(*n.file, n.line, {"Inline without url skipped"});
        return warn(*n.file, n.line, {"Inline skipped: no readable local file among ", tried});
    }
    auto [known, fresh] = canonical_paths_.try_emplace(target.path);
    if (fresh) known->second = canonical_path(target.path);
    const std::string canonical = known->second;
    if (std::find(inline_stack_.begin(), inline_stack_.end(), canonical) != inline_stack_.end()) {
        std::string chain;
        for (const std::string& s : inline_stack_) chain += fs::path(s).filename().string() + " -> ";
        fail(*n.file, n.line, {"Inline cycle: ", chain, fs::path(canonical).filename().string()});
    }
    if (inline_stack_.size() > limits_.max_inline_depth)
        fail(*n.file, n.line, {"Inlines nested deeper than max_inline_depth (", limits_.max_inline_depth, ")"});
    const ParsedFile& file = load(target.path, canonical, n);
    const int idx = emit(n, "Inline", file.path, 1, c, c.world);
    inline_stack_.push_back(canonical);
    const Ctx inner{idx, c.world, nullptr, c.depth + 1};
    for (const AstNode* root : file.roots) eval_child(root, inner);
    inline_stack_.pop_back();
}

// ---- geometry -----------------------------------------------------------------

const AstNode* SceneBuilder::unwrap(const AstNode* n, const Env*& env, size_t& depth, std::deque<Env>& envs) {
    while (n && n->type == NodeType::proto_instance) {
        ++depth;
        visit(*n, depth);
        envs.push_back(make_env(*n, env));
        env = &envs.back();
        n = n->proto->body.empty() ? nullptr : n->proto->body.front();
    }
    return n;
}

void SceneBuilder::eval_shape(const AstNode& n, const Ctx& c) {
    const Bound gb = field(n, "geometry", c.env);
    const std::vector<const AstNode*>* list = nodes(n, "geometry", gb);
    if (!list || list->empty()) return;
    if (list->size() != 1) fail_type(n, "geometry", *gb.value, "one node");
    const AstNode* g = list->front();
    if (!g) return;
    VrmlMesh mesh;
    if (!build_geometry(g, gb.env, c.depth + 1, mesh) || mesh.triangles.empty()) return;
    mesh.name = !n.def_name.empty() ? n.def_name : g->def_name;
    count_values(n, mesh.vertices.size() + mesh.triangles.size());
    int target = c.parent;
    if (target < 0) {
        if (implicit_root_ < 0) implicit_root_ = emit(n, "Group", *n.file, n.line, c, c.world);
        target = implicit_root_;
    }
    scene_.nodes[static_cast<size_t>(target)].meshes.push_back(std::move(mesh));
}

bool SceneBuilder::build_geometry(const AstNode* g, const Env* env, size_t depth, VrmlMesh& mesh) {
    std::deque<Env> envs;
    visit(*g, depth);
    g = unwrap(g, env, depth, envs);
    if (!g) return false;
    auto positive = [&](double v, const char* what) {
        if (v > 0) return true;
        warn(*g->file, g->line, {g->type_name, ".", what, " is ", v, ", not positive; skipped"});
        return false;
    };
    switch (g->type) {
        case NodeType::indexed_face_set: build_indexed_face_set(*g, env, depth, mesh); return true;
        case NodeType::box: {
            const Eigen::Vector3d s = vec3(*g, "size", env, Eigen::Vector3d::Constant(2));
            if (!positive(s.minCoeff(), "size")) return false;
            mesh = box_mesh(s.x(), s.y(), s.z());
            return true;
        }
        case NodeType::sphere: {
            const double r = number(*g, "radius", env, 1);
            if (!positive(r, "radius")) return false;
            mesh = sphere_mesh(r);
            return true;
        }
        case NodeType::cylinder: {
            const double r = number(*g, "radius", env, 1), h = number(*g, "height", env, 2);
            if (!positive(r, "radius") || !positive(h, "height")) return false;
            mesh = cylinder_mesh(r, h, boolean(*g, "side", env, true), boolean(*g, "top", env, true),
                                 boolean(*g, "bottom", env, true));
            return true;
        }
        case NodeType::cone: {
            const double r = number(*g, "bottomRadius", env, 1), h = number(*g, "height", env, 2);
            if (!positive(r, "bottomRadius") || !positive(h, "height")) return false;
            mesh = cone_mesh(r, h, boolean(*g, "side", env, true), boolean(*g, "bottom", env, true));
            return true;
        }
        case NodeType::externproto_instance: return false;  // warned at its declaration
        default:
            if (warned_geometry_.insert(g->type_name).second) {
                warn(*g->file, g->line, {"geometry node '", g->type_name, "' is not supported; skipped"});
            }
            return false;
    }
}

void SceneBuilder::build_indexed_face_set(const AstNode& g, const Env* env, size_t depth, VrmlMesh& mesh) {
    const Bound cb = field(g, "coord", env);
    const std::vector<const AstNode*>* coords = nodes(g, "coord", cb);
    if (!coords || coords->empty()) return;
    if (coords->size() != 1) fail_type(g, "coord", *cb.value, "one node");
    const AstNode* coord = coords->front();
    if (!coord) return;
    const Env* coord_env = cb.env;
    std::deque<Env> envs;
    ++depth;
    visit(*coord, depth);
    coord = unwrap(coord, coord_env, depth, envs);
    if (!coord) return;
    if (coord->type != NodeType::coordinate)
        fail(*coord->file, coord->line,
             {"IndexedFaceSet.coord must be a Coordinate node, found '", coord->type_name, "'"});

    const Bound pb = field(*coord, "point", coord_env);
    if (pb.value && pb.value->kind != Value::Kind::none) {
        const Value& p = *pb.value;
        if (p.kind != Value::Kind::numbers) fail_type(*coord, "point", p, "numbers");
        if (p.numbers.size() % 3 != 0)
            fail(*coord->file, p.line, {"Coordinate.point: ", p.numbers.size(), " numbers are not whole 3D points"});
        mesh.vertices = p.numbers;
    }
    const size_t points = mesh.vertices.size() / 3;

    const Bound ib = field(g, "coordIndex", env);
    if (!ib.value || ib.value->kind == Value::Kind::none) return;
    const Value& index = *ib.value;
    if (index.kind != Value::Kind::numbers) fail_type(g, "coordIndex", index, "integers");
    const bool ccw = boolean(g, "ccw", env, true);

    mesh.triangles.reserve(index.numbers.size() * 3 / 2);
    std::vector<uint32_t> face;
    size_t skipped = 0;
    int first_skipped_line = 0;
    auto flush = [&](size_t at) {
        if (face.size() >= 3) {
            // Fan from the first vertex: exact for convex faces, which CAD
            // tessellators write (Pro/E exports triangles in practice).
            for (size_t k = 1; k + 1 < face.size(); ++k) {
                const uint32_t b = face[k], c = face[k + 1];
                mesh.triangles.insert(mesh.triangles.end(), {face[0], ccw ? b : c, ccw ? c : b});
            }
        } else if (!face.empty()) {
            if (skipped++ == 0) first_skipped_line = index.line_of_number(at);
        }
        face.clear();
    };
    const auto& idx = index.numbers;
    for (size_t i = 0; i < idx.size(); ++i) {
        const double d = idx[i];
        if (d == -1) {
            flush(i);
            continue;
        }
        if (d != std::floor(d)) fail(*g.file, index.line_of_number(i), {"coordIndex ", d, " is not an integer"});
        if (d < 0)
            fail(*g.file, index.line_of_number(i),
                 {"coordIndex ", d, " is not a vertex index (only -1, ending a face, may be negative)"});
        if (d >= static_cast<double>(points))
            fail(
                *g.file, index.line_of_number(i),
                {"coordIndex ", d, " refers to a vertex that does not exist (the Coordinate has ", points, " points)"});
        face.push_back(static_cast<uint32_t>(d));
    }
    flush(idx.empty() ? 0 : idx.size() - 1);
    if (skipped)
        warn(*g.file, first_skipped_line, {skipped, " face(s) with fewer than 3 vertices skipped in IndexedFaceSet"});
}

}  // namespace mbx_files::vrml
