#include "vrml_node_types.h"

#include <algorithm>
#include <initializer_list>
#include <string_view>

namespace mbx_files::vrml {
namespace {

struct Entry {
    std::string_view name;
    NodeType type;
};

// All 54 node types of ISO/IEC 14772-1 clause 6.
constexpr Entry standard_nodes[] = {
    {"Anchor", NodeType::anchor},
    {"Appearance", NodeType::other_standard},
    {"AudioClip", NodeType::other_standard},
    {"Background", NodeType::other_standard},
    {"Billboard", NodeType::billboard},
    {"Box", NodeType::box},
    {"Collision", NodeType::collision},
    {"Color", NodeType::other_standard},
    {"ColorInterpolator", NodeType::other_standard},
    {"Cone", NodeType::cone},
    {"Coordinate", NodeType::coordinate},
    {"CoordinateInterpolator", NodeType::other_standard},
    {"Cylinder", NodeType::cylinder},
    {"CylinderSensor", NodeType::other_standard},
    {"DirectionalLight", NodeType::other_standard},
    {"ElevationGrid", NodeType::other_standard},
    {"Extrusion", NodeType::other_standard},
    {"Fog", NodeType::other_standard},
    {"FontStyle", NodeType::other_standard},
    {"Group", NodeType::group},
    {"ImageTexture", NodeType::other_standard},
    {"IndexedFaceSet", NodeType::indexed_face_set},
    {"IndexedLineSet", NodeType::other_standard},
    {"Inline", NodeType::inline_node},
    {"LOD", NodeType::lod},
    {"Material", NodeType::other_standard},
    {"MovieTexture", NodeType::other_standard},
    {"NavigationInfo", NodeType::other_standard},
    {"Normal", NodeType::other_standard},
    {"NormalInterpolator", NodeType::other_standard},
    {"OrientationInterpolator", NodeType::other_standard},
    {"PixelTexture", NodeType::other_standard},
    {"PlaneSensor", NodeType::other_standard},
    {"PointLight", NodeType::other_standard},
    {"PointSet", NodeType::other_standard},
    {"PositionInterpolator", NodeType::other_standard},
    {"ProximitySensor", NodeType::other_standard},
    {"ScalarInterpolator", NodeType::other_standard},
    {"Script", NodeType::other_standard},
    {"Shape", NodeType::shape},
    {"Sound", NodeType::other_standard},
    {"Sphere", NodeType::sphere},
    {"SphereSensor", NodeType::other_standard},
    {"SpotLight", NodeType::other_standard},
    {"Switch", NodeType::switch_node},
    {"Text", NodeType::other_standard},
    {"TextureCoordinate", NodeType::other_standard},
    {"TextureTransform", NodeType::other_standard},
    {"TimeSensor", NodeType::other_standard},
    {"TouchSensor", NodeType::other_standard},
    {"Transform", NodeType::transform},
    {"Viewpoint", NodeType::other_standard},
    {"VisibilitySensor", NodeType::other_standard},
    {"WorldInfo", NodeType::world_info},
};

bool among(std::string_view field, std::initializer_list<std::string_view> names) {
    return std::find(names.begin(), names.end(), field) != names.end();
}

}  // namespace

NodeType standard_node_type(std::string_view name) {
    for (const Entry& e : standard_nodes)
        if (e.name == name) return e.type;
    return NodeType::unknown;
}

bool is_known_field(NodeType type, std::string_view f) {
    // Switch and LOD also take X3D's "children", which some exporters write.
    switch (type) {
        case NodeType::transform:
            return among(f, {"children", "translation", "rotation", "scale", "scaleOrientation", "center", "bboxCenter",
                             "bboxSize", "addChildren", "removeChildren"});
        case NodeType::group: return among(f, {"children", "bboxCenter", "bboxSize", "addChildren", "removeChildren"});
        case NodeType::anchor:
            return among(f, {"children", "description", "parameter", "url", "bboxCenter", "bboxSize", "addChildren",
                             "removeChildren"});
        case NodeType::billboard:
            return among(f, {"children", "axisOfRotation", "bboxCenter", "bboxSize", "addChildren", "removeChildren"});
        case NodeType::collision:
            return among(f,
                         {"children", "collide", "proxy", "bboxCenter", "bboxSize", "addChildren", "removeChildren"});
        case NodeType::switch_node: return among(f, {"choice", "whichChoice", "children"});
        case NodeType::lod: return among(f, {"level", "center", "range", "children"});
        case NodeType::inline_node: return among(f, {"url", "bboxCenter", "bboxSize"});
        case NodeType::shape: return among(f, {"appearance", "geometry"});
        case NodeType::indexed_face_set:
            return among(f, {"color", "coord", "normal", "texCoord", "ccw", "colorIndex", "colorPerVertex", "convex",
                             "coordIndex", "creaseAngle", "normalIndex", "normalPerVertex", "solid", "texCoordIndex",
                             "set_colorIndex", "set_coordIndex", "set_normalIndex", "set_texCoordIndex"});
        case NodeType::coordinate: return among(f, {"point"});
        case NodeType::box: return among(f, {"size"});
        case NodeType::sphere: return among(f, {"radius"});
        case NodeType::cylinder: return among(f, {"bottom", "height", "radius", "side", "top"});
        case NodeType::cone: return among(f, {"bottomRadius", "height", "side", "bottom"});
        case NodeType::world_info: return among(f, {"title", "info"});
        default: return true;
    }
}

}  // namespace mbx_files::vrml
