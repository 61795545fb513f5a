// The motion of a closed chain from its measured coordinates, for inverse
// dynamics along measured motion (regression_rows.h, and the effort-driven
// replays of replay.h).
#pragma once
#include <Eigen/Dense>
#include <vector>

#include "sim/closure_factor.h"
#include "sim/data.h"

namespace mbx::calibration {

// The motion of a closed chain from its measured (independent) coordinates:
// the others follow from the loop closures, positions by Gauss-Newton from
// the last sample's solution (so the solution stays on the assembly's
// branch), velocities from J v = 0 and accelerations from J a = -Jdot v.
// With J = [Ji Jd] over independent and dependent coordinates, every motion
// the loops allow is v = G vi with G = [I; -Jd^+ Ji]. The closure's forces
// do no work along such motions (J G = 0), so the tree's inverse dynamics
// tau, which needs the loop forces J^T lambda besides the actuators, gives
// the actuators' efforts on the independent coordinates as G^T tau.
struct ClosedChain {
    std::vector<int> independent, dependent;  // velocity coordinates
    std::vector<char> fixed;                  // per coordinate: independent
    sim::ClosureFactor<double> factor;

    bool active() const { return !dependent.empty(); }

    // d.q holds the independent positions and a start for the others; on
    // return every coordinate of d.q, qd and qdd is closure-consistent and G
    // maps independent to all velocities. Throws mbx::Error when the
    // measured coordinates close no loop or do not fix the others.
    void close(const sim::Model& m, sim::Data& d, Eigen::VectorXd& qd, Eigen::VectorXd& qdd, Eigen::MatrixXd& G);
};

// The chain whose independent coordinates are those `measured` marks (all of
// a tree's). Throws mbx::Error unless they are exactly as many as the loops
// leave free at the assembly pose.
ClosedChain closed_chain(const sim::Model& m, const std::vector<char>& measured);

}  // namespace mbx::calibration
