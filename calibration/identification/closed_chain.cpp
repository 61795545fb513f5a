#include "calibration/identification/closed_chain.h"

#include "core/finding.h"
#include "sim/dynamics.h"
#include "sim/loop_closure.h"

namespace mbx::calibration {

void ClosedChain::close(const sim::Model& m, sim::Data& d, Eigen::VectorXd& qd, Eigen::VectorXd& qdd, Eigen::MatrixXd& G) {
    const Eigen::Index ni = Eigen::Index(independent.size()), nd = Eigen::Index(dependent.size());
    if (!sim::project_positions(m, d, factor, 1e-11, 50, &fixed))
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name),
                    "the measured coordinates put the loops where no closure holds (a reading off the mechanism's "
                    "range, or the wrong joints measured)");
    d.v.setZero();
    sim::update_kinematics(m, d);
    sim::update_closure_jacobian(m, d);
    Eigen::MatrixXd Ji(d.J.rows(), ni), Jd(d.J.rows(), nd);
    for (Eigen::Index k = 0; k < ni; ++k) Ji.col(k) = d.J.col(independent[size_t(k)]);
    for (Eigen::Index k = 0; k < nd; ++k) Jd.col(k) = d.J.col(dependent[size_t(k)]);
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Jd);
    cod.setThreshold(1e-9);
    if (cod.rank() < nd)
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name),
                    "the measured coordinates do not fix the loops' other coordinates (at this pose): measure "
                    "independent coordinates of the loops");
    const Eigen::MatrixXd Gd = -cod.solve(Ji);
    G.setZero(m.nv, ni);
    for (Eigen::Index k = 0; k < ni; ++k) G(independent[size_t(k)], k) = 1;
    for (Eigen::Index k = 0; k < nd; ++k) G.row(dependent[size_t(k)]) = Gd.row(k);
    Eigen::VectorXd vi(ni), ai(ni);
    for (Eigen::Index k = 0; k < ni; ++k) vi[k] = qd[independent[size_t(k)]], ai[k] = qdd[independent[size_t(k)]];
    qd = G * vi;
    d.v = qd;
    sim::update_kinematics(m, d);
    Eigen::VectorXd tau;
    sim::inverse_dynamics(m, d, Eigen::VectorXd::Zero(m.nv).eval(), tau);
    sim::update_closure_bias(m, d);
    const Eigen::VectorXd ad = cod.solve((d.gamma - Ji * ai).eval());
    qdd = G * ai;  // the dependents then get their whole solution, velocity-product part included
    for (Eigen::Index k = 0; k < nd; ++k) qdd[dependent[size_t(k)]] = ad[k];
}

ClosedChain closed_chain(const sim::Model& m, const std::vector<char>& measured) {
    ClosedChain chain;
    chain.fixed.assign(size_t(m.nv), 0);
    for (int dof = 0; dof < m.nv; ++dof) {
        if (measured[size_t(dof)] || m.closures.empty()) {
            chain.independent.push_back(dof);
            chain.fixed[size_t(dof)] = 1;
        } else {
            chain.dependent.push_back(dof);
        }
    }
    if (!chain.active()) return chain;
    // As many measured coordinates as the loops leave free (at the assembly pose).
    sim::Data d(m);
    d.q = m.q_reference;
    sim::update_positions(m, d);
    sim::update_closure_jacobian(m, d);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(d.J);
    qr.setThreshold(1e-9);
    const int mobility = m.nv - int(qr.rank());
    if (int(chain.independent.size()) != mobility)
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(m.name),
                    "the loops leave " + std::to_string(mobility) + " coordinate(s) free but " +
                        std::to_string(chain.independent.size()) +
                        " are measured: identification of a closed chain needs the positions of exactly its "
                        "independent coordinates");
    return chain;
}

}  // namespace mbx::calibration
