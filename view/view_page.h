// The page `mbx view` writes: one HTML file with three.js, the scene (glTF
// binary, base64) and the posed trajectory inlined, so it opens offline from
// a file:// URL. It renders the assembly at its CAD pose, plays the
// trajectory in a loop when there is one, and reports in an element with id
// "mbx-status" what it drew (for headless checks).
#pragma once
#include <string>
#include <vector>

#include "export/common/export_model.h"
#include "view/trajectory_poses.h"

namespace mbx {

// The page for scene.glb bytes `glb`; `motion` may be null (a still view).
// `collision_nodes` names the scene's collision shape nodes: the page hides
// them and shows a "collision shapes" checkbox (id mbx-collision) that shows
// them. Throws mbx::Error when three.js (Debian's libjs-three) is not installed.
std::string view_page(const std::string& title, const std::string& glb, const PosedTrajectory* motion,
                      const std::vector<std::string>& collision_nodes = {});

// view.html for `model` (its scene exported in memory, with the collision
// shapes of its description when it has any), with the trajectory of
// `trajectory_csv` when that is not empty.
OutputFiles view_files(ExportModel& model, const std::string& trajectory_csv);

}  // namespace mbx
