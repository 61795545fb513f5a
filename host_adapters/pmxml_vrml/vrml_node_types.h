// The VRML97 node types the reader tells apart. Everything the scene needs
// (grouping, Inline, Shape and its geometry, WorldInfo) has its own value;
// the other standard nodes are parsed and dropped without a warning, and
// node types that are neither standard nor declared by a PROTO are dropped
// with one.
#pragma once
#include <string_view>

namespace mbx_files::vrml {

enum class NodeType {
    transform,
    group,
    anchor,
    billboard,
    collision,
    switch_node,
    lod,
    inline_node,
    shape,
    indexed_face_set,
    coordinate,
    box,
    sphere,
    cylinder,
    cone,
    world_info,
    other_standard,        // a VRML97 node that carries nothing the scene needs
    unknown,               // neither standard nor declared
    proto_instance,        // of a PROTO in scope
    externproto_instance,  // of an EXTERNPROTO (never loaded)
};

// Standard node types by name; NodeType::unknown if `name` is not one.
NodeType standard_node_type(std::string_view name);

// Whether `field` is a field of the standard node `type`, for the types the
// scene builder reads (others: always true). Catches misspelt fields, which
// would otherwise silently keep their defaults.
bool is_known_field(NodeType type, std::string_view field);

// Grouping nodes whose children become VrmlNodes of their own.
inline bool is_grouping(NodeType t) {
    return t == NodeType::transform || t == NodeType::group || t == NodeType::anchor || t == NodeType::billboard ||
           t == NodeType::collision || t == NodeType::switch_node || t == NodeType::lod;
}

}  // namespace mbx_files::vrml
