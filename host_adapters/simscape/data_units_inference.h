// The units of a Simscape file that does not say them. Older Link versions
// write no <DataUnits>, and their <ModelUnits> cannot be trusted for the
// numbers (a Creo export says inch and lbm while its translations are
// millimetres). The part's STEP files can: a STEP file states its length
// unit, so a solid's radius of gyration in metres against the one the file's
// mass properties give (sqrt(trace I / m), in file lengths whatever the mass
// unit) is the file's metres per length unit; with that, the mass over the
// solid's volume is a density, and the mass unit is the one that makes it an
// engineering material's.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mbx_files {

// One part with mass properties and a solid read from its STEP file.
struct UnitEvidence {
    std::string part_name;
    double mass = 0;                                        // as written
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();      // as written
    double volume = 0;                                      // m^3, of the STEP solid
    Eigen::Matrix3d inertia_per_density = Eigen::Matrix3d::Zero();  // m^5, about its centroid
};

struct InferredUnits {
    double length_to_m = 1, mass_to_kg = 1;
    std::string length_name = "metres", mass_name = "kilograms";
    bool from_geometry = false;  // false: no usable evidence, metres and kilograms assumed
    std::string reason;          // one sentence for the finding
};

// `model_length`/`model_mass` are the ModelUnits strings ("" when absent),
// only named in the reason.
InferredUnits infer_data_units(const std::vector<UnitEvidence>& evidence, const std::string& model_length,
                               const std::string& model_mass);

}  // namespace mbx_files
