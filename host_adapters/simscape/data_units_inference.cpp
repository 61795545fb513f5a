#include "data_units_inference.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mbx_files {
namespace {

struct Unit {
    const char* name;
    double si;
};

// The length units CAD systems model in.
constexpr Unit kLengths[] = {{"metres", 1}, {"millimetres", 1e-3}, {"centimetres", 1e-2}, {"inches", 0.0254}, {"feet", 0.3048}};
constexpr Unit kMasses[] = {{"kilograms", 1}, {"grams", 1e-3}, {"pounds", 0.45359237}, {"tonnes", 1e3}};
// Densities of the materials parts are made of (kg/m^3): plastics, aluminium,
// titanium, steel, brass and copper. A mass unit off by 2.2 (pound against
// kilogram) or 1000 lands far from every one of them.
constexpr double kMaterials[] = {1200, 2700, 4430, 7850, 8700};
// A radius of gyration that matches a unit within this ratio names it (the
// units above are at least 2.5 apart; mass properties printed to six digits
// and a mesh at the default chord agree to far better than this).
constexpr double kLengthMatch = 1.05;

std::string format(const char* pattern, double x) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, pattern, x);
    return buffer;
}

}  // namespace

InferredUnits infer_data_units(const std::vector<UnitEvidence>& evidence, const std::string& model_length,
                               const std::string& model_mass) {
    InferredUnits out;
    const std::string model_units =
        model_length.empty() && model_mass.empty()
            ? std::string()
            : " (the file's ModelUnits, which only say what a Simulink import displays, are '" + model_length + "' and '" +
                  model_mass + "')";
    // Metres per file length from each part: sqrt of (solid's trace J / V) over (file's trace I / m).
    std::vector<double> scales;
    for (const UnitEvidence& e : evidence) {
        const double file = e.inertia.trace() / e.mass, solid = e.inertia_per_density.trace() / e.volume;
        if (e.mass > 0 && e.volume > 0 && file > 0 && solid > 0 && std::isfinite(file) && std::isfinite(solid))
            scales.push_back(std::sqrt(solid / file));
    }
    if (scales.empty()) {
        out.reason = "no <DataUnits> and no part with mass properties and a readable STEP file to tell the units by: "
                     "the numbers are taken as metres and kilograms" + model_units;
        return out;
    }
    std::sort(scales.begin(), scales.end());
    const double scale = scales[scales.size() / 2];
    const Unit* length = nullptr;
    for (const Unit& u : kLengths)
        if (std::abs(std::log(scale / u.si)) < std::log(kLengthMatch)) length = &u;
    if (!length) {
        out.reason = "no <DataUnits>, and the parts' mass properties fit no length unit against their STEP solids (" +
                     format("%.4g", scale) + " m per unit): the numbers are taken as metres and kilograms" + model_units;
        return out;
    }
    // Density of each part in kg/m^3 per unit of mass as written.
    std::vector<double> per_unit;
    for (const UnitEvidence& e : evidence)
        if (e.mass > 0 && e.volume > 0) per_unit.push_back(e.mass / e.volume);
    std::sort(per_unit.begin(), per_unit.end());
    const double written = per_unit[per_unit.size() / 2];
    const Unit* mass = &kMasses[0];
    double best = INFINITY;
    for (const Unit& u : kMasses)
        for (double material : kMaterials) {
            const double off = std::abs(std::log(written * u.si / material));
            if (off < best) best = off, mass = &u;
        }
    out.length_to_m = length->si;
    out.mass_to_kg = mass->si;
    out.length_name = length->name;
    out.mass_name = mass->name;
    out.from_geometry = true;
    out.reason = "no <DataUnits>: the numbers are taken as " + out.length_name + " and " + out.mass_name + ", told by " +
                 std::to_string(scales.size()) + (scales.size() == 1 ? " part's" : " parts'") +
                 " STEP solids: their radius of gyration is the mass properties' at " +
                 format("%.6g", scale) + " m per unit, and their median density is then " +
                 format("%.0f", written * mass->si) + " kg/m^3" + model_units;
    return out;
}

}  // namespace mbx_files
