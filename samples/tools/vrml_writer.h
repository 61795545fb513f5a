// VRML97 the way CAD exporters lay out an assembly: an assembly file with a
// WorldInfo, a Model_Info PROTO carrying CAD part names, and per part a
// Transform at the part frame (CS1) that Inlines the part's geometry file;
// part files hold closed IndexedFaceSets in the part frame.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "solid_mesh.h"

namespace mbx_samples {

struct VrmlShape {
    std::string name;  // DEF name of the Shape
    Solid solid;       // part frame, model length unit
    Eigen::Vector3d color = Eigen::Vector3d::Constant(0.7);
};

struct VrmlGeometryFile {
    std::string file_name;  // relative to the assembly file
    std::string part_name;  // for the file's comment
    std::vector<VrmlShape> shapes;
};

// One Transform of the assembly file.
struct VrmlPlacement {
    std::string name;           // DEF name (sanitized) and Model_Info name
    std::string type = "part";  // Model_Info type: "part" or "assembly"
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // in the enclosing placement, model unit
    std::string url;            // Inline of a geometry file, "" for none
    std::vector<VrmlShape> shapes;  // geometry written in place
    std::vector<VrmlPlacement> children;
};

struct VrmlAssembly {
    std::string file_name;  // e.g. "fourbar_a.wrl"
    std::string title;
    std::vector<std::string> info;
    double unit_in_model = 1;  // one VRML length unit in model units (1000: VRML in m, model in mm)
    std::vector<VrmlPlacement> placements;
    std::vector<VrmlGeometryFile> geometry;
};

// Writes the assembly file and every geometry file into `directory`.
void write_vrml(const std::string& directory, const VrmlAssembly& assembly);

// A VRML identifier for a CAD name ("Obj-1" -> "Obj_1").
std::string vrml_identifier(const std::string& name);

}  // namespace mbx_samples
