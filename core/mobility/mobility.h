// Mobility analysis: closes every loop of the spanning tree, ranks the
// velocity-level closure equations and compares with the Grübler count.
//
// Conventions (the rest of the SDK and the exporters rely on them):
//
//  * Loop::joints of the loop closed by cut joint c (parent P, child C, LCA =
//    lowest common tree ancestor of P and C) are listed as
//        c, then the tree joints from C up to the LCA (in walking order),
//        then the tree joints from the LCA down to P.
//    Loop::signs are -1 for c, +1 for the C side, -1 for the P side, so that
//        sum_j sign_j * S_j * qdot_j = 0,
//    S_j being the twist of joint j's child w.r.t. its parent. Joint::axis is
//    the host's follower-relative-to-base axis, so S_j uses -axis when the
//    joint is `reversed` (the sign never changes a rank).
//
//  * Twists are world twists (angular part; linear velocity of the point at
//    the reference) with rank-neutral changes that keep every loop's numbers
//    O(1) whatever its size and position in the model: each loop's rows are
//    referred to the centroid c of its joint points and its linear rows are
//    divided by the loop's own length l (largest distance of a joint point
//    from c, at least Mechanism::length_tolerance). Revolute: (w, (p-c) x w
//    / l); spherical: three such columns about world x, y, z; prismatic:
//    (0, a * u / l), its rate in units u = l of the first loop through it
//    (one unit per joint, as the column is shared). Per-row-block and
//    per-column scalings leave the rank unchanged, but the tolerance below
//    is relative, so the scale decides what counts as zero. A single length
//    for the whole model (Assembly::size) makes long chains of loops much
//    smaller than the model look translation-free: a ladder of 2000 unit
//    four-bars in its 2001 m bounding box then shows 9 spurious freedoms,
//    one of 10 000 shows 233 (and takes 13 s instead of 0.1 s).
//
//  * Numeric rank counts singular values above
//        tau = rank_tolerance * max(1, largest singular value).
//    Loops are ranked one by one (6 x f, dense SVD) for Loop::dof/redundant.
//    For the whole mechanism, loops sharing a joint are grouped (union-find
//    over joints) and each group is ranked on its own: dense SVD up to
//    MobilitySettings::dense_column_limit columns, beyond that a sparse
//    multifrontal QR with the same absolute tau, followed by a check of its
//    pivot rows for small singular values (rank.h: how it matches the SVD,
//    and why not Eigen::SparseQR). The total rank is the sum over groups.
//
//  * A loop is planar when it has at least two revolutes, every revolute axis
//    is parallel (either sign) to a common normal n and every prismatic axis
//    is perpendicular to it, within an angle of orthonormality_tolerance (the
//    precision the SDK assumes of host directions). n is the mean revolute
//    axis with its first component above that tolerance made positive.
#pragma once
#include "core/progress.h"
#include "core/translator/mechanism.h"

namespace mbx {

struct MobilitySettings {
    // Coupled loop groups with more Jacobian columns than this use the sparse
    // rank; tests lower it to exercise the sparse path on small mechanisms.
    int dense_column_limit = 256;
};

// Fills Loop::joints/signs/dof/gruebler_dof/redundant/planar/planar_normal,
// Mechanism::dof/gruebler_dof/redundant and adds the loop findings. Expects
// the spanning tree (bodies' parent_joint and depth, cut joints, loops'
// cut_joint, floating_roots) to be built. Throws Error(MBX_ERROR_INTERNAL)
// if the tree is inconsistent (a cut joint joining two separate trees, a
// parent_joint that does not lead upwards).
void analyze_mobility(Mechanism& mech, const TranslateOptions& options);
// The same, ticking `progress` once per loop (the caller starts the stage
// with loops.size() items); a cancelling host makes it throw from a tick.
void analyze_mobility(Mechanism& mech, const TranslateOptions& options, Progress& progress,
                      const MobilitySettings& settings = {});

}  // namespace mbx
