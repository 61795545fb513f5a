// Walks parsed VRML files into a VrmlScene: transforms, Inline loading,
// PROTO expansion, Shape geometry to meshes and part names (the rules are
// documented in vrml_reader.h).
#pragma once
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "vrml_ast.h"
#include "vrml_inline_paths.h"
#include "vrml_message.h"
#include "vrml_parser.h"
#include "host_adapters/common/vrml_scene.h"

namespace mbx_files::vrml {

class SceneBuilder {
public:
    explicit SceneBuilder(const VrmlLimits& limits);

    VrmlScene build_from_file(const std::string& path);
    VrmlScene build_from_text(std::string_view text, const std::string& path);

private:
    struct Env;
    // A field value and the PROTO instance scope its own IS bindings refer to.
    struct Bound {
        const Value* value = nullptr;
        const Env* env = nullptr;
    };
    // The interface values of one PROTO instance.
    struct Env {
        const ProtoDecl* proto = nullptr;
        std::vector<Bound> values;
    };
    struct Ctx {
        int parent = -1;  // VrmlNode that receives content; -1: top level of the main file
        Eigen::Affine3d world = Eigen::Affine3d::Identity();
        const Env* env = nullptr;
        size_t depth = 0;
    };

    VrmlScene build(const ParsedFile& main, const std::string& canonical);
    const ParsedFile& load(const std::string& path, const std::string& canonical, const AstNode& from);
    void add_file_warnings(const ParsedFile& file);

    // Child context: what a node in a children list turns into.
    void eval_child(const AstNode* n, const Ctx& c);
    void eval_transform(const AstNode& n, const Ctx& c);
    Eigen::Affine3d local_transform(const AstNode& n, const Env* env);
    void eval_group(const AstNode& n, const Ctx& c);
    void eval_switch_or_lod(const AstNode& n, const Ctx& c);
    void eval_children(const AstNode& n, const char* field, const Ctx& c);
    void eval_inline(const AstNode& n, const Ctx& c);
    void eval_shape(const AstNode& n, const Ctx& c);
    void eval_world_info(const AstNode& n, const Ctx& c);
    void eval_proto_child(const AstNode& n, const Ctx& c);
    void eval_externproto_child(const AstNode& n, const Ctx& c);

    bool build_geometry(const AstNode* g, const Env* env, size_t depth, VrmlMesh& mesh);
    void build_indexed_face_set(const AstNode& g, const Env* env, size_t depth, VrmlMesh& mesh);

    // The first body node of PROTO instance chains, with its instance scope
    // (kept alive in `envs`), so instances work in geometry and coord fields.
    const AstNode* unwrap(const AstNode* n, const Env*& env, size_t& depth, std::deque<Env>& envs);
    Env make_env(const AstNode& instance, const Env* outer) const;
    Bound field(const AstNode& n, std::string_view name, const Env* env) const;
    Bound resolve(const Value& value, const Env* env) const;  // follows IS into the instance scope

    Eigen::Vector3d vec3(const AstNode& n, const char* name, const Env* env, const Eigen::Vector3d& fallback) const;
    Eigen::AngleAxisd rotation(const AstNode& n, const char* name, const Env* env);
    double number(const AstNode& n, const char* name, const Env* env, double fallback) const;
    bool boolean(const AstNode& n, const char* name, const Env* env, bool fallback) const;
    std::vector<std::string> strings(const AstNode& n, const char* name, const Env* env) const;
    const std::vector<const AstNode*>* nodes(const AstNode& n, const char* name, const Bound& b) const;
    std::string naming_value(const AstNode& instance, const Env* outer) const;

    int emit(const AstNode& n, const std::string& kind, const std::string& file, int line, const Ctx& c,
             const Eigen::Affine3d& world);
    void name_scope(int node, const std::string& name);
    void name_from_proto(const AstNode& instance, int node, const Ctx& c);
    void visit(const AstNode& n, size_t depth);
    void count_values(const AstNode& n, size_t count);
    void warn(const std::string& file, int line, std::initializer_list<Piece> message);
    [[noreturn]] void fail(const std::string& file, int line, std::initializer_list<Piece> message) const;
    [[noreturn]] void fail_type(const AstNode& n, const char* field, const Value& v, const char* expected) const;
    [[noreturn]] void fail_visit(const AstNode& n, size_t depth) const;

    const VrmlLimits& limits_;
    StackGuard stack_;
    ReadBudget budget_;
    std::unordered_map<std::string, std::unique_ptr<ParsedFile>> files_;  // by canonical path
    std::vector<std::string> inline_stack_;                               // canonical paths being read
    InlineResolver resolver_;
    std::unordered_map<std::string, std::string> canonical_paths_;  // resolved Inline path -> canonical
    VrmlScene scene_;
    std::vector<std::string> own_names_;  // part name given to each node itself
    std::string root_name_;               // part name given at the main file's top level
    int implicit_root_ = -1;
    bool title_set_ = false;
    size_t suppressed_warnings_ = 0;
    std::unordered_set<std::string> warned_geometry_;  // unsupported geometry types already reported
};

}  // namespace mbx_files::vrml
