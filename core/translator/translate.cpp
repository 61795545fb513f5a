#include "core/translator/translate.h"

#include <algorithm>

#include "core/mobility/mobility.h"

namespace mbx {

std::unique_ptr<Mechanism> translate_assembly(Assembly assembly, Findings findings, const TranslateOptions& options,
                                              Progress& progress, const ShapeFetcher& shapes) {
    auto m = std::make_unique<Mechanism>();
    m->assembly = std::move(assembly);
    m->findings = std::move(findings);
    m->length_tolerance = options.length_tolerance > 0 ? options.length_tolerance
                                                       : std::max(1e-5 * m->assembly.size, 1e-9);
    merge_welds(*m, progress);
    build_tree(*m, progress);
    validate(*m, progress);
    check_mass_plausibility(*m);
    if (options.check_mass_with_shapes && shapes)
        check_mass_with_shapes(*m, shapes, options.centroid_tolerance, progress);
    analyze_mobility(*m, options, progress);
    return m;
}

}  // namespace mbx
