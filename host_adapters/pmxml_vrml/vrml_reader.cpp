#include "vrml_reader.h"

#include "vrml_scene_builder.h"

namespace mbx_files {

VrmlScene read_vrml(const std::string& path, const VrmlLimits& limits) {
    return vrml::SceneBuilder(limits).build_from_file(path);
}

VrmlScene read_vrml_text(std::string_view text, const std::string& path, const VrmlLimits& limits) {
    return vrml::SceneBuilder(limits).build_from_text(text, path);
}

}  // namespace mbx_files
