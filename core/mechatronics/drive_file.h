// The mechatronic description file (`mbx translate --drives`): which library
// objects drive which joints, with controller, amplifier and motion, and the
// joints' own dynamics (damping, friction, spring, limits, armature), keyed by
// the CAD constraint ids so it survives re-exports of the CAD model. Format:
// docs/mechatronics.md.
#pragma once
#include <string>
#include <vector>

#include "core/mechatronics/drive.h"

namespace mbx {

// Appends the file's drives to `spec.drives`, its <joint> entries to
// `spec.joint_dynamics`, and loads the libraries it
// names (<library file="..."/>, relative to the file) into `spec.library`.
// Every problem of the file goes to `errors` with its line; a drive with a
// problem (or a <joint> with one) is not added. Library problems stay in spec.library.errors().
void load_drive_file(const std::string& path, MechatronicSpec& spec, std::vector<DriveError>& errors);

// The same from text; `file` names it in errors, `base_dir` resolves library
// paths ("" = the current directory).
void load_drive_text(const std::string& text, const std::string& file, const std::string& base_dir,
                     MechatronicSpec& spec, std::vector<DriveError>& errors);

// "measured", "difference", "filtered_difference".
bool parse_velocity_estimate(const std::string& word, VelocityEstimate& out);
const char* velocity_estimate_name(VelocityEstimate v);

}  // namespace mbx
