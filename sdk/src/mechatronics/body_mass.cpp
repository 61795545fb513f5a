#include "mechatronics/body_mass.h"

#include <cmath>
#include <map>

#include "translator/mechanism.h"

namespace mbx {

std::vector<ResolvedBodyMass> resolve_body_masses(const std::vector<BodyMassSpec>& specs, const Mechanism& m,
                                                  std::vector<LibraryError>& errors) {
    // A body answers to its own id and to the ids of the parts merged into it.
    std::map<std::string, int> by_id;
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        by_id.emplace(m.bodies[b].id, int(b));
        for (int p : m.bodies[b].parts) by_id.emplace(m.assembly.parts[size_t(p)].id, int(b));
    }
    std::vector<ResolvedBodyMass> out;
    std::map<int, int> seen;  // body -> line of its first correction
    for (size_t i = 0; i < specs.size(); ++i) {
        const BodyMassSpec& s = specs[i];
        auto fail = [&](const std::string& message) { errors.push_back({s.file, s.line, s.body, message}); };
        const auto it = by_id.find(s.body);
        if (it == by_id.end()) {
            fail("no body or CAD part '" + s.body + "' in the mechanism");
            continue;
        }
        const RigidBody& body = m.bodies[size_t(it->second)];
        if (!(std::isfinite(s.mass_scale) && s.mass_scale > 0)) {
            fail("mass_scale must be a positive number");
            continue;
        }
        if (body.kind != MBX_RIGID_BODY_DYNAMIC || !(body.mass > 0)) {
            fail("body '" + body.name + "' has no mass of its own to correct");
            continue;
        }
        if (const auto at = seen.find(it->second); at != seen.end()) {
            fail("body '" + body.name + "' is corrected twice (first at line " + std::to_string(at->second) + ")");
            continue;
        }
        seen.emplace(it->second, s.line);
        out.push_back({it->second, int(i), s.mass_scale});
    }
    return out;
}

CadInertia cad_inertia(const Mechanism& m) {
    CadInertia c;
    for (const RigidBody& b : m.bodies) c.bodies.emplace_back(b.mass, b.inertia);
    return c;
}

void apply_body_masses(Mechanism& m, const CadInertia& cad, const std::vector<ResolvedBodyMass>& masses) {
    for (size_t b = 0; b < m.bodies.size() && b < cad.bodies.size(); ++b) {
        m.bodies[b].mass = cad.bodies[b].first;
        m.bodies[b].inertia = cad.bodies[b].second;
    }
    for (const ResolvedBodyMass& r : masses) {
        RigidBody& b = m.bodies[size_t(r.body)];
        b.mass *= r.mass_scale;
        b.inertia *= r.mass_scale;
    }
}

}  // namespace mbx
