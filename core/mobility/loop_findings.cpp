// Findings name the loop by its cut joint and list its joints so a user can
// find it in the CAD tree; long loops list the first few and a count.
#include "core/mobility/loop_findings.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace mbx::mobility {
namespace {

constexpr size_t kListedJoints = 8;

std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

std::string joint_list(const Mechanism& mech, const Loop& loop) {
    std::string out;
    const size_t n = loop.joints.size();
    const size_t shown = n > kListedJoints ? kListedJoints : n;
    for (size_t k = 0; k < shown; ++k) {
        if (k > 0) out += (k + 1 == n) ? " and " : ", ";
        out += in_quotes(mech.joints[loop.joints[k]].name);
    }
    if (shown < n) out += " and " + std::to_string(n - shown) + " more";
    return out;
}

std::string number(double v) {
    if (std::abs(v) < 5e-7) v = 0;  // no "-0"
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", v);
    return buffer;
}

std::string plural(int n, const char* one, const char* many) { return std::to_string(n) + " " + (n == 1 ? one : many); }

int freedoms(const Mechanism& mech, const Loop& loop) {
    int f = 0;
    for (int j : loop.joints) f += mech.joints[j].freedoms();
    return f;
}

}  // namespace

void report_loop(Mechanism& mech, int loop_index) {
    const Loop& loop = mech.loops[loop_index];
    const std::string id = "loop" + std::to_string(loop_index);
    const std::string title = "Loop " + std::to_string(loop_index) + " (cut at joint " +
                              in_quotes(mech.joints[loop.cut_joint].name) + "; joints " + joint_list(mech, loop) + ")";
    const int equations = loop.planar ? 3 : 6;
    // A planar loop's 3 out-of-plane equations are dependent by design; only
    // redundancy beyond them is a modelling problem.
    const int unexpected = loop.redundant - (loop.planar ? 3 : 0);

    if (loop.planar) {
        const Vec3& n = loop.planar_normal;
        mech.add(MBX_SEVERITY_INFO, MBX_FINDING_PLANAR_LOOP, Subject::loop(id),
                 title + " is planar about normal (" + number(n.x()) + ", " + number(n.y()) + ", " + number(n.z()) +
                     "); Modelica needs one planar-loop cut joint here.");
    }
    if (unexpected > 0) {
        const int independent = 6 - loop.redundant;
        const std::string are = independent == 1 ? " is" : " are";
        std::string what = loop.planar ? " beyond the 3 out-of-plane equations every planar loop has (only " +
                                             std::to_string(independent) + " of its 3 in-plane equations" + are +
                                             " independent)"
                                       : " (only " + std::to_string(independent) + " of its 6 closure equations" +
                                             are + " independent)";
        mech.add(MBX_SEVERITY_WARNING, MBX_FINDING_REDUNDANT_CONSTRAINTS, Subject::loop(id),
                 title + " has " + plural(unexpected, "redundant constraint", "redundant constraints") + what +
                     "; a solver sees a singular constraint Jacobian unless joints are relaxed by " +
                     (unexpected == 1 ? "one freedom" : "that many freedoms") +
                     " (e.g. a revolute replaced by a universal or spherical joint).");
    }
    if (loop.dof != loop.gruebler_dof) {
        const int f = freedoms(mech, loop);
        std::string why;
        if (loop.dof == 0 && loop.gruebler_dof < 0) {
            why = "its " + plural(f, "joint freedom is", "joint freedoms are") + " fewer than its " +
                  std::to_string(equations) + " closure equations, so it is rigid and the negative count only " +
                  "measures by how much it is over-constrained.";
        } else if (loop.dof > loop.gruebler_dof) {
            why = "its geometry is special (parallel, intersecting or coincident axes), which makes " +
                  plural(loop.dof - loop.gruebler_dof, "closure equation", "closure equations") +
                  " dependent and lets the loop move more than the count predicts.";
        } else {
            why = "its axes are parallel only within the planarity tolerance, and the closure equations resolve "
                  "the small misalignment, so the loop moves less than an exactly planar one would.";
        }
        mech.add(MBX_SEVERITY_INFO, MBX_FINDING_MOBILITY_MISMATCH, Subject::loop(id),
                 title + " has " + plural(loop.dof, "degree of freedom", "degrees of freedom") +
                     " numerically, while the " + (loop.planar ? "planar" : "spatial") +
                     " Gruebler-Kutzbach count gives " + std::to_string(loop.gruebler_dof) + ": " + why);
    }
}

}  // namespace mbx::mobility
