// Reads a URDF file into a UrdfModel with pugixml (in place, on its own copy
// of the text), keeping every element's line. A file that cannot describe a
// robot (not XML, no <robot>, a link or joint without a name or repeated, a
// joint without parent, child or a known type, a number that is not a finite
// number, a negative mass, a zero axis) is a FileError naming the line;
// extension elements (gazebo, transmission, ros2_control, ...) are stepped
// over as every URDF consumer does. read_urdf also reads the cut joints that
// close a looped mechanism's loops from <stem>.cut_joints.json beside the
// file, when there is one (what mbx's URDF export writes).
#pragma once
#include <string>
#include <string_view>

#include "host_adapters/common/file_error.h"
#include "urdf_model.h"

namespace mbx_files {

inline constexpr const char* kUrdfRootElement = "robot";

UrdfModel read_urdf(const std::string& path);
// The cut joints of `file` (mbx-urdf-cut-joints version 1, what mbx's URDF
// export writes beside a looped mechanism's URDF); FileError naming `file`
// and the line otherwise.
std::vector<UrdfCutJoint> parse_cut_joints(std::string_view text, const std::string& file);
UrdfModel parse_urdf(std::string_view text, const std::string& file);

}  // namespace mbx_files
