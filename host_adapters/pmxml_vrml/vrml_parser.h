// VRML97 classic-encoding parser: header check, then statements (nodes,
// DEF/USE, PROTO, EXTERNPROTO, ROUTE) into a ParsedFile. Recursive descent;
// every nesting level is checked against VrmlLimits::max_depth and against
// the stack left (StackGuard), so hostile nesting ends in a VrmlError.
#pragma once
#include <memory>
#include <string>
#include <string_view>

#include "vrml_ast.h"
#include "host_adapters/common/vrml_scene.h"
#include "vrml_stack_guard.h"

namespace mbx_files::vrml {

// Totals over all files of one read, checked against VrmlLimits.
struct ReadBudget {
    size_t values = 0;  // numbers and strings parsed, plus mesh values emitted
    size_t parsed_nodes = 0;
    size_t visits = 0;  // nodes visited while building the scene (USE/PROTO expansion included)
};

// Parses `text` (the whole file, header included). `path` names the file in
// messages and is what AstNode::file points to.
std::unique_ptr<ParsedFile> parse_vrml(std::string_view text, const std::string& path, const VrmlLimits& limits,
                                       ReadBudget& budget, const StackGuard& stack);

}  // namespace mbx_files::vrml
