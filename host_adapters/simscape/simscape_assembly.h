// A Simscape import model as the assembly an mbx_host serves: one body per
// instance of a part (parts are shared; each instance is a CAD part of its
// own id), grounded instances fixed to the world, rigid sub-assemblies and
// rigid groups welded, and each typed joint a constraint whose primitives
// act along the joint frames' axes as Simscape's joint blocks do.
//
// Ids (what the description file, experiment files and reports name):
//   a body: the instance's path of uids from the root assembly, joined by
//           '/' (a top-level instance: its uid alone). Onshape's instance
//           uids and SolidWorks' component ids stay the same when the same
//           assembly is exported again, and a path tells apart the two
//           instances that older Link versions give one uid under different
//           sub-assemblies;
//   a joint: its name (a mate's name in the CAD system), prefixed by the
//           path of the sub-assembly instance when the joint belongs to a
//           sub-assembly.
#pragma once
#include <string>
#include <vector>

#include "host_adapters/memory/memory_host.h"
#include "simscape_model.h"

namespace mbx_files {

// A body's part, for the shapes the adapter loads when asked.
struct SimscapeBodyPart {
    std::string body_id, body_name;
    int part = -1;  // index into SimscapeModel::parts
};

struct SimscapeAssembly {
    mbx_memory::Assembly assembly;
    std::vector<SimscapeBodyPart> body_parts;
};

SimscapeAssembly to_assembly(const SimscapeModel& model);

}  // namespace mbx_files
