#include "core/mechatronics/body_mass.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <map>

#include "core/translator/mechanism.h"

namespace mbx {

Mat3 inertia_from_entries(const InertiaEntries& e) {
    Mat3 r;
    r << e[0], e[3], e[4], e[3], e[1], e[5], e[4], e[5], e[2];
    return r;
}

namespace {

void correct(CadInertia::Body& b, double mass_scale, const Vec3& com_shift, const InertiaEntries& change) {
    b.mass *= mass_scale;
    b.inertia = b.inertia * mass_scale + inertia_from_entries(change);
    b.com += com_shift;
}

}  // namespace

std::string implausible_inertia(const Mat3& inertia) {
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(inertia, Eigen::EigenvaluesOnly);
    const Vec3 p = eig.eigenvalues();  // ascending
    const double scale = std::max(1e-300, p.cwiseAbs().maxCoeff());
    if (!(p[0] > 1e-12 * scale)) return "the corrected inertia is not positive definite";
    // Principal moments of a real mass distribution obey the triangle
    // inequality (each is a sum of two second moments); a little slack for
    // thin plates and rods whose CAD moments sit on the bound.
    if (p[2] > (p[0] + p[1]) * (1 + 1e-6)) return "a corrected principal moment exceeds the sum of the other two";
    return "";
}

std::vector<ResolvedBodyMass> resolve_body_masses(const std::vector<BodyMassSpec>& specs, const Mechanism& m,
                                                  const CadInertia* cad, std::vector<LibraryError>& errors) {
    // A body answers to its own id and to the ids of the parts merged into it.
    std::map<std::string, int> by_id;
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        by_id.emplace(m.bodies[b].id, int(b));
        for (int p : m.bodies[b].parts) by_id.emplace(m.assembly.parts[size_t(p)].id, int(b));
    }
    const CadInertia own = cad ? CadInertia() : cad_inertia(m);
    const CadInertia& base = cad ? *cad : own;
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
        bool finite = s.com_shift.allFinite();
        for (double v : s.inertia_change) finite = finite && std::isfinite(v);
        if (!finite) {
            fail("com_shift and inertia_change must be finite numbers");
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
        if (size_t(it->second) < base.bodies.size()) {
            CadInertia::Body corrected = base.bodies[size_t(it->second)];
            correct(corrected, s.mass_scale, s.com_shift, s.inertia_change);
            if (const std::string why = implausible_inertia(corrected.inertia); !why.empty()) {
                fail("body '" + body.name + "': " + why);
                continue;
            }
        }
        seen.emplace(it->second, s.line);
        out.push_back({it->second, int(i), s.mass_scale, s.com_shift, s.inertia_change});
    }
    return out;
}

CadInertia cad_inertia(const Mechanism& m) {
    CadInertia c;
    for (const RigidBody& b : m.bodies) c.bodies.push_back({b.mass, b.com, b.inertia});
    return c;
}

void apply_body_masses(Mechanism& m, const CadInertia& cad, const std::vector<ResolvedBodyMass>& masses) {
    std::vector<CadInertia::Body> now = cad.bodies;
    for (const ResolvedBodyMass& r : masses)
        if (size_t(r.body) < now.size()) correct(now[size_t(r.body)], r.mass_scale, r.com_shift, r.inertia_change);
    for (size_t b = 0; b < m.bodies.size() && b < now.size(); ++b) {
        m.bodies[b].mass = now[b].mass;
        m.bodies[b].com = now[b].com;
        m.bodies[b].inertia = now[b].inertia;
    }
}

}  // namespace mbx
