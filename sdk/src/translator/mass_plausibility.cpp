// Mass data a real assembly cannot have, from the CAD system's own numbers
// (no geometry needed): a part whose mass over its CAD volume is no real
// material's density, and an assembly mass the parts do not add up to.
//
// A part without a material usually carries the CAD system's default density
// of 1 in the model's own units: 1 kg/mm^3 (1e9 kg/m^3), 1 lbm/in^3
// (27 680 kg/m^3, Pro/E inch models such as FOURBAR), 1 kg/m^3. The accepted
// range is 50 to 25 000 kg/m^3. Above: osmium, the densest element, is
// 22 590 kg/m^3 and tungsten heavy alloys stay below 19 000, while the Pro/E
// inch default lies just beyond. Below: balsa (~100), structural and PU foams
// (30 and up) pass; the lightest packaging foams (EPS, 10-30) are flagged, a
// cheap false alarm next to a default of 1 kg/m^3 or 1 lbm/ft^3 (16 kg/m^3)
// going unnoticed. A default of 1 g/cm^3 (water) cannot be told from a real
// plastic and is not caught; its exact ratio of 1 in the host's units is
// named when the range is left, not used to flag on its own.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "translator/translate.h"

namespace mbx {
namespace {

std::string fmt(const char* format, double a, double b = 0, double c = 0) {
    char buf[200];
    std::snprintf(buf, sizeof buf, format, a, b, c);
    return buf;
}

// Mass and volume are both printed with 6 significant digits by CAD exports.
bool is_unit_density(double host_density) { return std::fabs(host_density - 1.0) <= 1e-4; }

void check_densities(Mechanism& m) {
    for (const Part& p : m.assembly.parts) {
        if (p.is_helper() || p.is_ground() || !(p.mass > 0) || !(p.volume > 0)) continue;
        const double density = p.mass / p.volume;
        if (density >= kDensityMin && density <= kDensityMax) continue;
        std::string why = is_unit_density(p.host_density)
                              ? "the mass equals the volume in the host's own units: the CAD default density of 1, "
                                "no material assigned"
                              : "suspect a part without a material (a default density) or a wrong mass or volume unit";
        m.add(MBX_SEVERITY_WARNING, MBX_FINDING_IMPLAUSIBLE_DENSITY, Subject::body(p.id, p.name),
              "part '" + p.name + "' has mass " + fmt("%.6g kg in a CAD volume of %.6g m^3", p.mass, p.volume) +
                  ": density " + fmt("%.6g kg/m^3, outside %g to %g kg/m^3 (light foams to osmium); ", density,
                                     kDensityMin, kDensityMax) +
                  why);
    }
}

void check_assembly_mass(Mechanism& m) {
    const double stated = m.assembly.stated_mass;
    if (!(stated > 0)) return;
    double sum = 0;
    int n = 0;
    for (const Part& p : m.assembly.parts)
        if (p.mass > 0) sum += p.mass, ++n;
    const double diff = std::fabs(stated - sum);
    if (diff <= kAssemblyMassTolerance * std::max(stated, sum)) return;
    m.add(MBX_SEVERITY_WARNING, MBX_FINDING_ASSEMBLY_MASS_MISMATCH, Subject::model(m.assembly.name),
          "the host states an assembly mass of " + fmt("%.6g kg, but its %g parts add up to %.6g kg", stated, n, sum) +
              fmt(" (%.3g %% apart, tolerance %g %%); suspect parts missing from the export, a mass override on "
                  "the assembly or parts without a material",
                  100 * diff / std::max(stated, sum), 100 * kAssemblyMassTolerance));
}

}  // namespace

void check_mass_plausibility(Mechanism& m) {
    check_densities(m);
    check_assembly_mass(m);
}

}  // namespace mbx
