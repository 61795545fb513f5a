// Reads a VRML97 scene (a CAD export: an assembly file Inlining part files)
// into a VrmlScene for match_shapes. Only what places and shapes geometry is
// kept; everything else is parsed and dropped.
//
// Nodes. One VrmlNode per grouping node, depth first, parents first:
//  - Transform, Group, Anchor, Billboard, Collision, Switch, LOD: kind is the
//    type name;
//  - Inline: kind "Inline", file the inlined file, line 1 (the Inline
//    statement's own place is in messages about it);
//  - PROTO instance used as a child node: kind is the PROTO name;
//  - EXTERNPROTO instance (never loaded; a warning): kind is its name, no content.
// Switch keeps only its whichChoice child (-1 or out of range: none), LOD
// only its first level. `world` is the product of the enclosing Transforms,
// each T*C*R*SR*S*-SR*-C (clause 6.52). Shapes add a mesh to the nearest
// enclosing VrmlNode, in that node's coordinates; Shapes at the top level of
// the main file go to one implicit "Group" node created for them.
//
// Geometry. IndexedFaceSet (coord, coordIndex, ccw; faces fan-triangulated,
// which assumes convex faces; faces with fewer than 3 vertices skipped with
// a warning), Box (exact), Sphere, Cylinder and Cone (24 facets around; see
// primitive_meshes.h). Other geometry (ElevationGrid, Extrusion, Text, ...)
// is skipped with a warning. DEF/USE works for any node, including
// Coordinate and geometry nodes; a PROTO instance works anywhere its first
// body node would (child, geometry or coord), with IS fields taking the
// instance's value or the interface default.
//
// Inline. The first of its urls (at most 16 are tried) that names an
// existing local file is read, relative to the including file ("file:"
// URLs, %XX escapes, backslashes and case-insensitive matching accepted);
// remote urls and urls that cannot be found are skipped with a warning. Each
// file is parsed once however often it is inlined.
//
// Part names (VrmlNode::part_name), the rule implemented:
//  1. A "naming field" is a PROTO or EXTERNPROTO interface field of type
//     SFString or MFString whose name, lower-cased with '_' and '-' removed,
//     is "partname", "modelname" or "name"; for an info PROTO (one whose
//     name, compared the same way, contains "info", e.g. Model_Info) also
//     "title". Its value is the instance's, else the interface default (an
//     EXTERNPROTO has none); the first non-empty one in that order counts.
//  2. A PROTO instance with a naming value names itself. An info PROTO
//     instance also names the enclosing VrmlNode (the grouping node, PROTO
//     instance or Inline it sits in), siblings before it included.
//  3. A WorldInfo with a non-empty title names the enclosing VrmlNode, except
//     at the top level of the main file, where title and info become
//     VrmlScene::title/info (the first such WorldInfo only).
//  4. An info PROTO at the top level of the main file names all top-level
//     nodes, as if the file were the enclosing node.
//  5. The first name found for a node wins (its own naming field before any
//     info node or WorldInfo inside it). A node without one inherits its
//     parent's part_name.
// So `DEF PART Group { children [ Model_Info { name "PRT0001" } Shape {...} ] }`,
// or an inlined part file with `WorldInfo { title "PRT0001" }` at its top,
// gives the Group (or the Inline) and everything below it "PRT0001".
//
// Limits (VrmlLimits): max_depth counts nested nodes and PROTO bodies while
// parsing, and nested nodes, PROTO expansions and Inlines while building.
// Both recurse once per level, so each level also checks the stack the
// thread has left (vrml_stack_guard.h): a max_depth too large for the stack
// ends in a VrmlError too. max_total_values counts the numbers and strings
// parsed plus the mesh values emitted (so USE of a big mesh many times is
// bounded too). max_nodes bounds the nodes parsed, the node visits while
// building (USE and PROTO expansion included) and the VrmlNodes emitted.
// Inline cycles are found by canonical path on the stack of open Inlines.
//
// Errors: VrmlError with the file and line: syntax errors, truncated files,
// junk bytes, NaN/inf or out-of-range numbers, unterminated strings, USE of
// an undefined DEF, recursive PROTOs, coordIndex naming a vertex that does
// not exist, fields of the wrong type, limits exceeded, Inline cycles,
// unreadable files, VRML 1.0 / X3D / gzip-compressed files.
#pragma once
#include <string>
#include <string_view>

#include "host_adapters/common/vrml_scene.h"

namespace mbx_files {

VrmlScene read_vrml(const std::string& path, const VrmlLimits& limits = {});

// The same from text in memory; `path` names it in messages and is where
// relative Inline urls are resolved from (the file need not exist).
VrmlScene read_vrml_text(std::string_view text, const std::string& path, const VrmlLimits& limits = {});

}  // namespace mbx_files
