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
// plastic by its value.
//
// Within the range, a ratio that is an exact power of ten in the host's own
// units (1e-5 kg/mm^3 = 10 000 kg/m^3) is a placeholder someone typed, not a
// material's measured density: in the 2015 legs export the eight mirrored
// left-leg parts carry exactly 1e-5 kg/mm^3, 2 to 8 times the mass of their
// right-leg twins of equal volume. Six printed digits on mass and volume
// leave the ratio within 1e-5 of the typed value, while a real density lands
// that close to a power of ten about once in 10^5 parts.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/text_format.h"
#include "core/translator/translate.h"

namespace mbx {
namespace {

// Mass and volume are both printed with 6 significant digits by CAD exports.
bool is_unit_density(double host_density) { return std::fabs(host_density - 1.0) <= 1e-4; }

// The power of ten `host_density` was typed as, or 0 if it is not one.
double typed_power_of_ten(double host_density) {
    if (!(host_density > 0)) return 0;
    const double p = std::pow(10.0, std::round(std::log10(host_density)));
    return std::fabs(host_density / p - 1) <= 1.5e-5 ? p : 0;
}

void check_densities(Mechanism& m) {
    for (const Part& p : m.assembly.parts) {
        if (p.is_helper() || p.is_ground() || !(p.mass > 0) || !(p.volume > 0)) continue;
        const double density = p.mass / p.volume;
        if (density >= kDensityMin && density <= kDensityMax) {
            if (const double typed = typed_power_of_ten(p.host_density))
                m.add(MBX_SEVERITY_WARNING, MBX_FINDING_IMPLAUSIBLE_DENSITY, Subject::body(p.id, p.name),
                      "part '" + p.name + "' has mass " + formatted("%.6g kg in a CAD volume of %.6g m^3", p.mass, p.volume) +
                          ": density " + formatted("%.6g kg/m^3, exactly %g in the host's units; ", density, typed) +
                          "a round placeholder rather than a material's density (mirrored or copied parts often "
                          "lose their material)");
            continue;
        }
        std::string why = is_unit_density(p.host_density)
                              ? "the mass equals the volume in the host's own units: the CAD default density of 1, "
                                "no material assigned"
                              : "suspect a part without a material (a default density) or a wrong mass or volume unit";
        m.add(MBX_SEVERITY_WARNING, MBX_FINDING_IMPLAUSIBLE_DENSITY, Subject::body(p.id, p.name),
              "part '" + p.name + "' has mass " + formatted("%.6g kg in a CAD volume of %.6g m^3", p.mass, p.volume) +
                  ": density " + formatted("%.6g kg/m^3, outside %g to %g kg/m^3 (light foams to osmium); ", density,
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
          "the host states an assembly mass of " + formatted("%.6g kg, but its %g parts add up to %.6g kg", stated, n, sum) +
              formatted(" (%.3g %% apart, tolerance %g %%); suspect parts missing from the export, a mass override on "
                  "the assembly or parts without a material",
                  100 * diff / std::max(stated, sum), 100 * kAssemblyMassTolerance));
}

}  // namespace

void check_mass_plausibility(Mechanism& m) {
    check_densities(m);
    check_assembly_mass(m);
}

}  // namespace mbx
