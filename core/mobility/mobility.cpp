#include "core/mobility/mobility.h"

#include <cmath>
#include <utility>
#include <vector>

#include "core/union_find.h"
#include "core/mobility/loop_findings.h"
#include "core/mobility/loop_path.h"
#include "core/mobility/rank.h"
#include "core/mobility/twist.h"

namespace mbx {
namespace {

double positive_or(double value, double fallback) { return value > 0 && std::isfinite(value) ? value : fallback; }

// Loops that share a joint share a Jacobian column, so only they need to be
// ranked together; everything else is block diagonal and ranks add up.
std::vector<std::vector<int>> coupled_groups(const Mechanism& mech) {
    UnionFind sets(mech.joints.size());
    for (const Loop& loop : mech.loops)
        for (size_t k = 1; k < loop.joints.size(); ++k)
            sets.unite(static_cast<size_t>(loop.joints[0]), static_cast<size_t>(loop.joints[k]));
    // Groups are numbered by their first loop, whatever root union-find picks.
    std::vector<int> group_of_root(mech.joints.size(), -1);
    std::vector<std::vector<int>> groups;
    for (size_t i = 0; i < mech.loops.size(); ++i) {
        size_t root = sets.find(static_cast<size_t>(mech.loops[i].joints[0]));
        if (group_of_root[root] < 0) {
            group_of_root[root] = static_cast<int>(groups.size());
            groups.emplace_back();
        }
        groups[group_of_root[root]].push_back(static_cast<int>(i));
    }
    return groups;
}

// Rank of all loops' closure equations stacked (columns: joint freedoms).
int mechanism_rank(const Mechanism& mech, std::vector<Eigen::MatrixXd> jacobians, const std::vector<int>& loop_rank,
                   double rank_tolerance, const MobilitySettings& settings) {
    std::vector<int> column_of(mech.joints.size(), -1);
    int rank = 0;
    for (const std::vector<int>& group : coupled_groups(mech)) {
        if (group.size() == 1) {
            rank += loop_rank[group[0]];
            continue;
        }
        int columns = 0;
        std::vector<int> used;
        std::vector<mobility::RowBlock> blocks(group.size());
        for (size_t g = 0; g < group.size(); ++g) {
            const Loop& loop = mech.loops[group[g]];
            for (int j : loop.joints) {
                if (column_of[j] < 0) {
                    column_of[j] = columns;
                    columns += mech.joints[j].freedoms();
                    used.push_back(j);
                }
                for (int k = 0; k < mech.joints[j].freedoms(); ++k) blocks[g].columns.push_back(column_of[j] + k);
            }
            blocks[g].values = std::move(jacobians[group[g]]);
        }
        if (columns <= settings.dense_column_limit)
            rank += mobility::dense_rank(mobility::assemble(blocks, columns), rank_tolerance);
        else
            rank += mobility::sparse_rank(std::move(blocks), columns, rank_tolerance);
        for (int j : used) column_of[j] = -1;
    }
    return rank;
}

}  // namespace

void analyze_mobility(Mechanism& mech, const TranslateOptions& options) {
    Progress silent;
    analyze_mobility(mech, options, silent);
}

void analyze_mobility(Mechanism& mech, const TranslateOptions& options, Progress& progress,
                      const MobilitySettings& settings) {
    const double rank_tolerance = positive_or(options.rank_tolerance, 1e-6);
    const double angle_tolerance = positive_or(options.orthonormality_tolerance, 1e-5);
    const double size = positive_or(mech.assembly.size, 1.0);
    const double min_length = positive_or(mech.length_tolerance, 1e-9 * size);

    const size_t loop_count = mech.loops.size();
    std::vector<mobility::LoopFrame> frames(loop_count);
    // A prismatic column is shared by every loop through the joint, so its
    // length unit must be one per joint: that of the first loop holding it.
    std::vector<double> prismatic_length(mech.joints.size(), 0.0);
    for (size_t i = 0; i < loop_count; ++i) {
        mobility::trace_loop(mech, static_cast<int>(i));
        frames[i] = mobility::loop_frame(mech, mech.loops[i], min_length);
        for (int j : mech.loops[i].joints)
            if (prismatic_length[j] == 0) prismatic_length[j] = frames[i].length;
    }

    std::vector<Eigen::MatrixXd> jacobians(loop_count);
    std::vector<int> loop_rank(loop_count);
    progress.stage("mobility", loop_count);
    for (size_t i = 0; i < loop_count; ++i) {
        Loop& loop = mech.loops[i];
        jacobians[i] = mobility::loop_jacobian(mech, loop, frames[i], &prismatic_length);
        const int freedoms = static_cast<int>(jacobians[i].cols());
        loop_rank[i] = mobility::dense_rank(jacobians[i], rank_tolerance);
        const mobility::Planarity planarity = mobility::loop_planarity(mech, loop, angle_tolerance);
        loop.planar = planarity.planar;
        loop.planar_normal = planarity.normal;
        loop.dof = freedoms - loop_rank[i];
        loop.redundant = 6 - loop_rank[i];
        loop.gruebler_dof = freedoms - (loop.planar ? 3 : 6);
        progress.tick();
    }

    int freedoms = 0;
    for (const Joint& joint : mech.joints) freedoms += joint.freedoms();
    const int loops = static_cast<int>(loop_count);
    const int rank = mechanism_rank(mech, std::move(jacobians), loop_rank, rank_tolerance, settings);
    mech.dof = freedoms + 6 * mech.floating_roots - rank;
    mech.redundant = 6 * loops - rank;
    mech.gruebler_dof = freedoms - 6 * loops + 6 * mech.floating_roots;

    for (size_t i = 0; i < loop_count; ++i) mobility::report_loop(mech, static_cast<int>(i));
    progress.finish();
}

}  // namespace mbx
