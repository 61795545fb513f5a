#include "sim/cvode_session.h"

#include <cvode/cvode.h>
#include <cvode/cvode_proj.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/QR>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <exception>
#include <string>

#include "core/heartbeat.h"

namespace mbx::sim {
namespace {

// State layout: y = (q, v, then each elastic transmission's motor position
// and rate) with nq + nv + 2 nt entries. Quaternions are integrated
// as they are (q' = q (x) (0, w) / 2, exact and polynomial in q) and put back
// on the unit sphere by the projection, which CVODE applies to every step
// without restarting; local coordinates re-centred after each step would
// need a CVodeReInit each time, losing the multistep history. Projection
// needs BDF, hence BDF (with a dense Newton solver, which also copes with
// stiff springs, limits and drive gains).

constexpr int kStuck = 0;

std::string num(double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, r.ptr);
}

// A continuous controller without integral action or delay has no memory:
// its law can be evaluated at any time, in any order, so at every
// evaluation of the derivative (exactly what the continuous law means).
bool stateless_controller(const ControllerSpec& c) {
    return c.sample_period == 0 && c.ki == 0 && c.kvi == 0 && c.delay == 0;
}

struct Session {
    const Model* model = nullptr;
    const Data* owner = nullptr;
    int nq = 0, nv = 0, nt = 0, n = 0;

    SUNContext ctx = nullptr;
    void* mem = nullptr;
    N_Vector y = nullptr, y_out = nullptr, abstol = nullptr;
    SUNMatrix A = nullptr;
    SUNLinearSolver ls = nullptr;
    bool project = false;

    // Dry friction: per joint that has some (dry_friction()), its velocity coordinate,
    // mode (kStuck, or +-1: slipping that way), and the position it is held at.
    std::vector<int> friction_dof;
    std::vector<int> mode;
    std::vector<double> held_q;
    std::vector<char> coulomb_dof;  // per dof: friction added here, not by passive_forces
    std::vector<char> stuck_dof;    // per dof
    int stuck_count = 0;
    Eigen::MatrixXd stuck_rows;
    Eigen::VectorXd stuck_bias;
    Eigen::VectorXd holding;        // per friction joint: the effort that holds it (stuck ones)
    std::vector<int> root_direction;

    // Drives: scratch copies for the memoryless continuous laws.
    std::vector<DriveController> law;
    std::vector<char> memoryless;
    bool stateful_continuous = false;

    // What data held when the last call returned, to continue seamlessly.
    bool live = false;
    double t_left = 0;
    Eigen::VectorXd q_left, v_left, effort_left, motor_q_left, motor_v_left;
    std::vector<double> override_left;
    double rtol = 0, hmax = 0, closure_tolerance = 0;

    // During a call.
    Data* d = nullptr;
    const InputFunction* inputs = nullptr;
    std::exception_ptr error;
    std::string message;

    Session() = default;
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;
    ~Session() {
        if (mem) CVodeFree(&mem);
        if (ls) SUNLinSolFree(ls);
        if (A) SUNMatDestroy(A);
        if (y) N_VDestroy(y);
        if (y_out) N_VDestroy(y_out);
        if (abstol) N_VDestroy(abstol);
        if (ctx) SUNContext_Free(&ctx);
    }

    const Model& m() const { return *model; }
    const JointT<double>& joint_of_dof(int dof) const { return m().joints[size_t(m().dof_joint[size_t(dof)])]; }
    const JointDynamics& friction(int i) const { return joint_of_dof(friction_dof[size_t(i)]).dynamics; }
    // A stuck joint held by effort h carries the load -h: it would slip along
    // -h, so that direction's static friction (asymmetric Coulomb level plus
    // the Stribeck peak) is what h must exceed.
    double stick_margin(int i) const {
        const double h = holding[long(i)];
        return static_friction(friction(i), h > 0 ? -1 : 1) - std::fabs(h);
    }

    void refresh_stuck() {
        std::fill(stuck_dof.begin(), stuck_dof.end(), 0);
        stuck_count = 0;
        for (size_t i = 0; i < friction_dof.size(); ++i)
            if (mode[i] == kStuck) stuck_dof[size_t(friction_dof[i])] = 1, ++stuck_count;
        stuck_rows.setZero(stuck_count, nv);
        stuck_bias.setZero(stuck_count);
        int r = 0;
        for (size_t i = 0; i < friction_dof.size(); ++i)
            if (mode[i] == kStuck) stuck_rows(r++, friction_dof[i]) = 1;
    }
    const std::vector<char>* stuck_mask() const { return stuck_count ? &stuck_dof : nullptr; }

    // y -> data (unit quaternions, stuck joints exactly where they are held).
    void load(double t, const double* yp) {
        Data& dd = *d;
        dd.time = t;
        std::copy(yp, yp + nq, dd.q.data());
        std::copy(yp + nq, yp + nq + nv, dd.v.data());
        for (int i = 0; i < nt; ++i) dd.motor_q[i] = yp[nq + nv + 2 * i], dd.motor_v[i] = yp[nq + nv + 2 * i + 1];
        for (const JointT<double>& j : m().joints) {
            if (j.kind != JointKind::Spherical && j.kind != JointKind::Free) continue;
            Eigen::Map<Eigen::Vector4d> quat(dd.q.data() + j.q_index + (j.kind == JointKind::Free ? 3 : 0));
            const double norm = quat.norm();
            if (norm > 0) quat /= norm;
        }
        for (size_t i = 0; i < friction_dof.size(); ++i)
            if (mode[i] == kStuck) {
                const int dof = friction_dof[i];
                dd.q[joint_of_dof(dof).q_index] = held_q[i];
                dd.v[dof] = 0;
            }
    }
    void store(double* yp) const {
        std::copy(d->q.data(), d->q.data() + nq, yp);
        std::copy(d->v.data(), d->v.data() + nv, yp + nq);
        for (int i = 0; i < nt; ++i) yp[nq + nv + 2 * i] = d->motor_q[i], yp[nq + nv + 2 * i + 1] = d->motor_v[i];
    }

    // Forces and forward dynamics at data's state; with `holding_effort`,
    // also the effort each stuck joint's friction must supply.
    void dynamics(bool holding_effort) {
        const Model& mm = m();
        Data& dd = *d;
        if (inputs && *inputs) (*inputs)(dd.time, dd);
        passive_forces(mm, dd, FrictionLaw::Slipping, &coulomb_dof);
        for (size_t i = 0; i < friction_dof.size(); ++i)
            if (mode[i] != kStuck)
                dd.qfrc_passive[friction_dof[i]] += slip_friction(friction(int(i)), dd.v[friction_dof[i]], mode[i]);
        for (size_t k = 0; k < mm.drives.size(); ++k) {
            if (!memoryless[k]) continue;
            const int dof = mm.drive_dof[k];
            const double over = dd.drives.target_override[k];
            const double target = std::isnan(over) ? mm.drives[k].spec.motion.at(dd.time).position : over;
            DriveController& c = law[k];
            c.reset();
            dd.drives.signals[k].target = target;
            dd.drives.signals[k].output = c.update(dd.time, target, sensed_position(mm, dd, dof), sensed_rate(mm, dd, dof));
        }
        drive_forces(mm, dd);
        dd.qfrc_total = dd.effort + dd.qfrc_passive + dd.qfrc_drive;
        apply_transmissions(mm, dd);
        if (dd.applied_forces) add_applied_forces(mm, dd);
        if (stuck_count)
            forward_dynamics(mm, dd, &stuck_rows, &stuck_bias);
        else
            forward_dynamics(mm, dd);
        ++dd.stats.evaluations;
        if (!holding_effort || !stuck_count) return;
        // M qacc + bias - f = J^T l + E^T h: the constraint efforts. The
        // minimum-norm split shares a load evenly where closures and stuck
        // joints hold the same motion (statically indeterminate friction).
        const Eigen::VectorXd r = dd.M * dd.qacc + dd.bias - dd.qfrc_total;
        Eigen::MatrixXd At(nv, dd.J.rows() + stuck_count);
        At << dd.J.transpose(), stuck_rows.transpose();
        const Eigen::VectorXd lambda = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(At).solve(r);
        int row = int(dd.J.rows());
        for (size_t i = 0; i < friction_dof.size(); ++i) holding[long(i)] = mode[i] == kStuck ? lambda[row++] : 0.0;
    }

    // Puts data on the closures (stuck joints kept); false if the positions
    // cannot be brought back.
    bool close(double tolerance) {
        if (m().closures.empty()) return true;
        Data& dd = *d;
        const bool ok = project_positions(m(), dd, dd.closure_factor, tolerance / m().length_scale, 50, stuck_mask());
        const double left = dd.residual.lpNorm<Eigen::Infinity>() * m().length_scale;
        if (!ok) return false;
        project_velocities(m(), dd, dd.closure_factor, stuck_mask());
        dd.stats.max_closure_residual = std::max(dd.stats.max_closure_residual, left);
        return true;
    }
};

int rhs(double t, N_Vector y, N_Vector ydot, void* user) {
    Session& s = *static_cast<Session*>(user);
    try {
        const double* yp = N_VGetArrayPointer(y);
        double* f = N_VGetArrayPointer(ydot);
        for (int k = 0; k < s.n; ++k)
            if (!std::isfinite(yp[k])) return 1;  // recoverable: CVODE retries with a smaller step
        s.load(t, yp);
        s.dynamics(false);
        const Data& d = *s.d;
        if (!d.qacc.allFinite() || !d.motor_acc.allFinite()) return 1;
        for (int i = 0; i < s.nt; ++i) f[s.nq + s.nv + 2 * i] = d.motor_v[i], f[s.nq + s.nv + 2 * i + 1] = d.motor_acc[i];
        for (const JointT<double>& j : s.m().joints) {
            const double* w = d.v.data() + j.v_index;
            auto quat_rate = [&](int o, const double* omega) {
                // q' = q (x) (0, w) / 2 with w in the child frame, from y's own q.
                const double qw = yp[o], qx = yp[o + 1], qy = yp[o + 2], qz = yp[o + 3];
                f[o] = -0.5 * (qx * omega[0] + qy * omega[1] + qz * omega[2]);
                f[o + 1] = 0.5 * (qw * omega[0] + qy * omega[2] - qz * omega[1]);
                f[o + 2] = 0.5 * (qw * omega[1] + qz * omega[0] - qx * omega[2]);
                f[o + 3] = 0.5 * (qw * omega[2] + qx * omega[1] - qy * omega[0]);
            };
            switch (j.kind) {
            case JointKind::Revolute:
            case JointKind::Prismatic: f[j.q_index] = s.stuck_dof[size_t(j.v_index)] ? 0.0 : w[0]; break;
            case JointKind::Fixed: break;
            case JointKind::Spherical: quat_rate(j.q_index, w); break;
            case JointKind::Free:
                for (int k = 0; k < 3; ++k) f[j.q_index + k] = w[k];
                quat_rate(j.q_index + 3, w + 3);
                break;
            }
        }
        for (int k = 0; k < s.nv; ++k) f[s.nq + k] = s.stuck_dof[size_t(k)] ? 0.0 : d.qacc[k];
        return 0;
    } catch (...) {
        s.error = std::current_exception();
        return -1;
    }
}

// Slipping: the joint speed, which reaches zero where the joint may stick.
// Stuck: the margin between the static friction and the holding effort.
int roots(double t, N_Vector y, double* g, void* user) {
    Session& s = *static_cast<Session*>(user);
    try {
        s.load(t, N_VGetArrayPointer(y));
        if (s.stuck_count) s.dynamics(true);
        for (size_t i = 0; i < s.friction_dof.size(); ++i)
            g[i] = s.mode[i] == kStuck ? s.stick_margin(int(i)) : s.d->v[s.friction_dof[i]];
        return 0;
    } catch (...) {
        s.error = std::current_exception();
        return -1;
    }
}

int projection(double t, N_Vector ycur, N_Vector corr, double, N_Vector, void* user) {
    Session& s = *static_cast<Session*>(user);
    try {
        double* yp = N_VGetArrayPointer(ycur);
        double* c = N_VGetArrayPointer(corr);
        for (int k = 0; k < s.n; ++k)
            if (!std::isfinite(yp[k])) return 1;
        s.load(t, yp);
        if (!s.close(s.closure_tolerance)) return 1;  // recoverable: a smaller step may close
        for (int k = 0; k < s.nq; ++k) c[k] = s.d->q[k] - yp[k];
        for (int k = 0; k < s.nv; ++k) c[s.nq + k] = s.d->v[k] - yp[s.nq + k];
        for (int k = s.nq + s.nv; k < s.n; ++k) c[k] = 0;  // the motors are outside the loops
        s.store(yp);
        return 0;
    } catch (...) {
        s.error = std::current_exception();
        return -1;
    }
}

void on_error(int code, const char*, const char*, char* msg, void* user) {
    Session& s = *static_cast<Session*>(user);
    if (code < 0 && msg) s.message = msg;  // warnings (CV_WARNING) are not failures
}

void check(int flag, const char* what) {
    if (flag < 0) throw Error(MBX_ERROR_INTERNAL, Subject::model(""), std::string("CVODE setup failed in ") + what);
}

Session& session_for(const Model& m, Data& d) {
    auto* s = static_cast<Session*>(d.accurate_session.get());
    if (s && s->model == &m && s->owner == &d && s->nq == m.nq && s->nv == m.nv && s->nt == int(m.transmissions.size()))
        return *s;
    auto fresh = std::make_shared<Session>();
    s = fresh.get();
    s->model = &m;
    s->owner = &d;
    s->nq = m.nq, s->nv = m.nv, s->nt = int(m.transmissions.size());
    s->n = m.nq + m.nv + 2 * s->nt;
    for (const JointT<double>& j : m.joints)
        if (j.nv() == 1 && j.dynamics.dry_friction()) s->friction_dof.push_back(j.v_index);
    const size_t nf = s->friction_dof.size();
    s->mode.assign(nf, 1);
    s->held_q.assign(nf, 0);
    s->holding.setZero(long(nf));
    s->root_direction.assign(nf, 0);
    s->coulomb_dof.assign(size_t(m.nv), 0);
    for (int dof : s->friction_dof) s->coulomb_dof[size_t(dof)] = 1;
    s->stuck_dof.assign(size_t(m.nv), 0);
    s->refresh_stuck();
    for (size_t k = 0; k < m.drives.size(); ++k) {
        const ControllerSpec& c = d.drives.controllers[k].spec();
        s->law.push_back(d.drives.controllers[k]);
        s->memoryless.push_back(stateless_controller(c) ? 1 : 0);
        if (c.sample_period == 0 && !stateless_controller(c)) s->stateful_continuous = true;
    }
    bool quaternions = false;
    for (const JointT<double>& j : m.joints) quaternions |= j.kind == JointKind::Spherical || j.kind == JointKind::Free;
    s->project = quaternions || !m.closures.empty() || nf > 0;
    if (s->n > 0) {
        check(SUNContext_Create(nullptr, &s->ctx), "SUNContext_Create");
        s->y = N_VNew_Serial(s->n, s->ctx);
        s->y_out = N_VNew_Serial(s->n, s->ctx);
        s->abstol = N_VNew_Serial(s->n, s->ctx);
        s->A = SUNDenseMatrix(s->n, s->n, s->ctx);
        s->ls = SUNLinSol_Dense(s->y, s->A, s->ctx);
        s->mem = CVodeCreate(CV_BDF, s->ctx);
        if (!s->y || !s->y_out || !s->abstol || !s->A || !s->ls || !s->mem)
            throw Error(MBX_ERROR_OUT_OF_MEMORY, Subject::model(m.name), "CVODE could not allocate its memory");
        std::fill(N_VGetArrayPointer(s->y), N_VGetArrayPointer(s->y) + s->n, 0.0);
        check(CVodeSetErrHandlerFn(s->mem, on_error, s), "CVodeSetErrHandlerFn");
        check(CVodeInit(s->mem, rhs, d.time, s->y), "CVodeInit");
        check(CVodeSetUserData(s->mem, s), "CVodeSetUserData");
        check(CVodeSetLinearSolver(s->mem, s->ls, s->A), "CVodeSetLinearSolver");
        if (s->project) {
            check(CVodeSetProjFn(s->mem, projection), "CVodeSetProjFn");
            // The error estimate is tested as integrated: projecting it too
            // would need the projector's Jacobian for no gain in safety.
            check(CVodeSetProjErrEst(s->mem, SUNFALSE), "CVodeSetProjErrEst");
        }
        if (nf > 0) {
            check(CVodeRootInit(s->mem, int(nf), roots), "CVodeRootInit");
            check(CVodeSetNoInactiveRootWarn(s->mem), "CVodeSetNoInactiveRootWarn");
        }
        check(CVodeSetMaxHnilWarns(s->mem, -1), "CVodeSetMaxHnilWarns");
    }
    d.accurate_session = fresh;
    return *s;
}

// Absolute tolerances: the relative one times each coordinate's scale
// (the model's size for lengths, 1 rad for angles and quaternion parts;
// the same per second for the rates).
void set_tolerances(Session& s, const IntegratorSettings& is) {
    double* a = N_VGetArrayPointer(s.abstol);
    const Model& m = s.m();
    for (const JointT<double>& j : m.joints) {
        const double L = m.length_scale;
        for (int k = 0; k < j.nq(); ++k) {
            const bool length = j.kind == JointKind::Prismatic || (j.kind == JointKind::Free && k < 3);
            a[j.q_index + k] = is.tolerance * (length ? L : 1.0);
        }
        for (int k = 0; k < j.nv(); ++k) {
            const bool length = j.kind == JointKind::Prismatic || (j.kind == JointKind::Free && k < 3);
            a[s.nq + j.v_index + k] = is.tolerance * (length ? L : 1.0);
        }
    }
    for (const TransmissionT<double>& t : m.transmissions) {
        const double scale = m.joints[size_t(t.joint)].kind == JointKind::Prismatic ? m.length_scale : 1.0;
        const int i = int(&t - m.transmissions.data());
        a[s.nq + s.nv + 2 * i] = a[s.nq + s.nv + 2 * i + 1] = is.tolerance * scale;
    }
    check(CVodeSVtolerances(s.mem, is.tolerance, s.abstol), "CVodeSVtolerances");
    check(CVodeSetMaxStep(s.mem, is.step > 0 ? is.step : 0.0), "CVodeSetMaxStep");
}

// Finds consistent friction modes at data's state after joints reached a
// switching condition: stuck joints whose holding effort exceeds their limit
// slip in the direction of the load; slipping joints at rest whose
// acceleration opposes their slip direction are tried stuck. Counts every
// change as a mode switch.
void settle_modes(Session& s, const std::vector<int>& before, bool count) {
    const size_t nf = s.friction_dof.size();
    Data& d = *s.d;
    for (size_t round = 0; round <= 2 * nf + 2; ++round) {
        s.refresh_stuck();
        s.dynamics(true);
        // The stuck joint furthest beyond its limit goes first: releasing it
        // changes the others' loads.
        int worst = -1;
        double excess = 0;
        for (size_t i = 0; i < nf; ++i) {
            if (s.mode[i] != kStuck) continue;
            const double e = -s.stick_margin(int(i));
            if (e >= 0 && (worst < 0 || e > excess)) worst = int(i), excess = e;
        }
        if (worst >= 0) {
            // Holding effort h on the joint: the load is -h, so it slips along -h.
            s.mode[size_t(worst)] = s.holding[worst] > 0 ? -1 : 1;
            continue;
        }
        int reverse = -1;
        for (size_t i = 0; i < nf && reverse < 0; ++i) {
            const int dof = s.friction_dof[i];
            if (s.mode[i] != kStuck && d.v[dof] == 0 && d.qacc[dof] * s.mode[i] < 0 && s.mode[i] == before[i])
                reverse = int(i);
        }
        if (reverse < 0) break;
        s.mode[size_t(reverse)] = kStuck;
        s.held_q[size_t(reverse)] = d.q[s.joint_of_dof(s.friction_dof[size_t(reverse)]).q_index];
    }
    s.refresh_stuck();
    for (size_t i = 0; i < nf; ++i) {
        if (count && s.mode[i] != before[i]) ++d.stats.mode_switches;
        // Slipping joints meet zero speed against their direction; stuck
        // ones' margins fall through zero.
        s.root_direction[i] = s.mode[i] == kStuck ? -1 : -s.mode[i];
    }
}

// (Re)starts CVODE at data's state: modes from the state when `fresh`
// (a joint at rest sticks if it can be held), loops closed, controllers
// sampled, stuck joints at exact rest.
void restart(Session& s, bool fresh) {
    Data& d = *s.d;
    const Model& m = s.m();
    const size_t nf = s.friction_dof.size();
    std::vector<int> before = s.mode;
    if (fresh) {
        for (size_t i = 0; i < nf; ++i) {
            const int dof = s.friction_dof[i];
            const double v = d.v[dof];
            s.mode[i] = v > 0 ? 1 : v < 0 ? -1 : kStuck;
            s.held_q[i] = d.q[s.joint_of_dof(dof).q_index];
        }
        before = s.mode;
    }
    for (size_t i = 0; i < nf; ++i)
        if (s.mode[i] == kStuck) d.v[s.friction_dof[i]] = 0;
    s.refresh_stuck();
    if (!s.close(s.closure_tolerance)) {
        const int worst = worst_closure(m, d.residual);
        const LoopClosureT<double>& c = m.closures[size_t(worst < 0 ? 0 : worst)];
        throw Error(MBX_ERROR_SIMULATION, c.subject(),
                    "at t = " + num(d.time) + " s the loop closed by cut joint '" + c.name + "' cannot be closed");
    }
    // Modes found at the start are not switches; after an event they are.
    if (nf > 0) settle_modes(s, before, !fresh);
    for (size_t i = 0; i < nf; ++i)
        if (s.mode[i] == kStuck) d.v[s.friction_dof[i]] = 0;
    if (s.n == 0) return;
    s.store(N_VGetArrayPointer(s.y));
    check(CVodeReInit(s.mem, d.time, s.y), "CVodeReInit");
    if (nf > 0) check(CVodeSetRootDirection(s.mem, s.root_direction.data()), "CVodeSetRootDirection");
}

bool same_hand_off(const Session& s, const Data& d, const IntegratorSettings& is) {
    return s.live && d.time == s.t_left && d.q == s.q_left && d.v == s.v_left &&
           d.motor_q == s.motor_q_left && d.motor_v == s.motor_v_left && d.effort == s.effort_left &&
           d.drives.target_override == s.override_left && is.tolerance == s.rtol && is.step == s.hmax &&
           is.closure_tolerance == s.closure_tolerance;
}

[[noreturn]] void fail(Session& s, int flag, double t) {
    if (s.error) std::rethrow_exception(s.error);
    const Model& m = s.m();
    std::string why;
    switch (flag) {
    case CV_ERR_FAILURE:
    case CV_TOO_CLOSE:
        why = "the step size underflowed (the run diverged, or the model is too stiff or discontinuous for the tolerance)";
        break;
    case CV_CONV_FAILURE: why = "the corrector did not converge at the smallest step (the run diverged)"; break;
    case CV_REPTD_RHSFUNC_ERR: why = "the state became non-finite (the run diverged)"; break;
    case CV_REPTD_PROJFUNC_ERR:
    case CV_PROJFUNC_FAIL: why = "the loops could not be closed again (the run diverged)"; break;
    default: why = "the integrator failed"; break;
    }
    char* name = CVodeGetReturnFlagName(flag);
    std::string detail = name ? name : "";
    free(name);
    if (!s.message.empty()) detail += ": " + s.message;
    throw Error(MBX_ERROR_SIMULATION, Subject::model(m.name),
                "the accurate integrator stopped at t = " + num(t) + " s: " + why + " [CVODE " + detail + "]");
}

// The next sample instant of any discrete controller after t.
double next_sample_instant(const Model& m, const Data& d, double t) {
    double next = INFINITY;
    for (size_t k = 0; k < m.drives.size(); ++k) {
        const double Ts = d.drives.controllers[k].spec().sample_period;
        if (!(Ts > 0)) continue;
        // As DriveController counts samples: within 1e-9 Ts of an instant is on it.
        const double i = std::floor(t / Ts + 1e-9) + 1;
        next = std::min(next, i * Ts);
    }
    return next;
}

}  // namespace

void accurate_advance(const Model& m, Data& d, const IntegratorSettings& is, const AccurateRequest& r) {
    auto bad = [&](const std::string& what) { throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::model(m.name), what); };
    if (!(std::isfinite(is.tolerance) && is.tolerance > 0 && is.tolerance < 1)) bad("the tolerance must be in (0, 1)");
    if (!(std::isfinite(is.step) && is.step >= 0)) bad("the largest step must be 0 (no bound) or positive");
    if (!(std::isfinite(r.stop_time) && r.stop_time >= d.time)) bad("the stop time must be finite and not before the current time");
    check_finite_state(m, d, "at the start");

    Session& s = session_for(m, d);
    s.d = &d;
    s.inputs = &r.inputs;
    s.error = nullptr;
    s.message.clear();
    // However the call ends, the session forgets this call's data; only a
    // call that reached the stop time may be continued.
    struct Detach {
        Session& s;
        bool ok = false;
        ~Detach() {
            s.d = nullptr, s.inputs = nullptr;
            s.live = ok;
        }
    } detach{s};

    const bool resume = same_hand_off(s, d, is);
    // A sample instant at the start (or a call's end time) is sampled here,
    // with the inputs the caller has set since.
    std::vector<double> held(m.drives.size());
    for (size_t k = 0; k < held.size(); ++k) held[k] = d.drives.signals[k].output;
    update_controllers(m, d, d.time);
    bool outputs_changed = false;
    for (size_t k = 0; k < held.size(); ++k) outputs_changed |= held[k] != d.drives.signals[k].output;
    if (!resume) {
        s.rtol = is.tolerance, s.hmax = is.step, s.closure_tolerance = is.closure_tolerance;
        if (s.n > 0) set_tolerances(s, is);
        restart(s, true);
    } else if (outputs_changed && d.time < r.stop_time) {
        restart(s, false);
    }

    const bool evenly = r.sample_count > 0;
    const size_t sample_total = evenly ? size_t(r.sample_count) : r.sample_times.size();
    auto sample_time = [&](size_t k) { return evenly ? r.sample_start + double(k + 1) * r.sample_step : r.sample_times[k]; };
    size_t next_sample = 0;
    auto emit_until = [&](double t_reached) {
        while (next_sample < sample_total && sample_time(next_sample) <= t_reached) {
            const double ts = sample_time(next_sample++);
            if (s.n > 0) {
                check(CVodeGetDky(s.mem, ts, 0, s.y_out), "CVodeGetDky");
                s.load(ts, N_VGetArrayPointer(s.y_out));
                // Interpolated states are put back on the closures for the samples.
                s.close(s.closure_tolerance);
            }
            d.time = ts;
            if (r.inputs) r.inputs(ts, d);
            s.dynamics(false);  // drive signals and accelerations at the sample
            if (r.sample) r.sample(d);
        }
    };

    const double t_end = r.stop_time;
    double t = d.time;
    if (s.n == 0) {
        emit_until(t_end);
        d.time = t_end;
    }
    Eigen::VectorXd y_good(s.n);
    if (s.n > 0) std::copy(N_VGetArrayPointer(s.y), N_VGetArrayPointer(s.y) + s.n, y_good.data());
    int tiny_steps = 0, events_here = 0;
    double last_event = -INFINITY;
    while (s.n > 0 && t < t_end) {
        // An instant within round-off of the end time is the end time (the
        // caller summed it): sampled by the next call, with its targets.
        const double round_off = 1e-12 * std::max(1.0, std::fabs(t_end));
        const double instant = next_sample_instant(m, d, t);
        const bool instant_first = instant < t_end - round_off;
        const double t_stop = instant_first ? instant : t_end;
        double t_ret = t;
        int flag = CV_TSTOP_RETURN;
        if (t_stop - t <= 1e-12 * std::max(1.0, std::fabs(t))) {
            // Within round-off of the stop (an end time summed by the caller,
            // an instant): there already, as CVODE would refuse so short a step.
            t_ret = t_stop;
        } else {
            check(CVodeSetStopTime(s.mem, t_stop), "CVodeSetStopTime");
            flag = CVode(s.mem, t_stop, s.y, &t_ret, CV_ONE_STEP);
            if (flag < 0) {
                s.load(t, y_good.data());
                fail(s, flag, t_ret);
            }
            ++d.stats.steps;
            // A step that no longer moves time would never end the run.
            tiny_steps = t_ret - t <= 64 * 2.2e-16 * std::max(1.0, std::fabs(t)) ? tiny_steps + 1 : 0;
            if (tiny_steps > 100) fail(s, CV_TOO_CLOSE, t_ret);
        }
        std::copy(N_VGetArrayPointer(s.y), N_VGetArrayPointer(s.y) + s.n, y_good.data());
        emit_until(t_ret);
        t = t_ret;
        if (r.step_taken)
            r.step_taken(t);
        else
            heartbeat();
        s.load(t, N_VGetArrayPointer(s.y));
        if (d.applied_forces) {
            // An accepted step: state that may change only on those (friction-spring anchors).
            update_kinematics(m, d);
            d.applied_forces->step_taken(m, d);
        }
        bool restart_needed = false;
        if (flag == CV_ROOT_RETURN) {
            std::vector<int> found(s.friction_dof.size(), 0);
            check(CVodeGetRootInfo(s.mem, found.data()), "CVodeGetRootInfo");
            const std::vector<int> before = s.mode;
            s.dynamics(true);
            for (size_t i = 0; i < found.size(); ++i) {
                if (!found[i]) continue;
                const int dof = s.friction_dof[i];
                if (s.mode[i] == kStuck) {
                    s.mode[i] = s.holding[long(i)] > 0 ? -1 : 1;
                } else {
                    // Speed zero: try holding it there.
                    s.mode[i] = kStuck;
                    d.v[dof] = 0;
                    s.held_q[i] = d.q[s.joint_of_dof(dof).q_index];
                }
            }
            settle_modes(s, before, true);
            if (std::fabs(t - last_event) <= 1e-12 * std::max(1.0, std::fabs(t))) {
                if (++events_here > 1000) {
                    int j = 0;
                    while (j + 1 < int(found.size()) && !found[size_t(j)]) ++j;
                    const JointT<double>& joint = s.joint_of_dof(s.friction_dof[size_t(j)]);
                    throw Error(MBX_ERROR_SIMULATION, joint.subject(),
                                "at t = " + num(t) + " s the friction of joint '" + joint.name +
                                    "' switches between stick and slip without end");
                }
            } else {
                events_here = 0;
            }
            last_event = t;
            restart_needed = true;
        }
        if (instant_first && t >= t_stop) {
            // A discrete controller's sample instant: new held outputs. One
            // at the end time is left to the next call, which may bring new
            // targets for it.
            update_controllers(m, d, t);
            restart_needed = true;
        } else if (s.stateful_continuous) {
            // Continuous controllers with integral action or delay keep
            // state that DriveController advances in time order; they are
            // updated at every accepted step and held within it (first
            // order in the step; discrete controllers are exact).
            update_controllers(m, d, t);
        }
        if (restart_needed) {
            restart(s, false);
            std::copy(N_VGetArrayPointer(s.y), N_VGetArrayPointer(s.y) + s.n, y_good.data());
        }
    }
    if (s.n > 0) {
        s.load(t_end, N_VGetArrayPointer(s.y));
        d.time = t_end;
    }
    s.q_left = d.q, s.v_left = d.v, s.effort_left = d.effort, s.t_left = d.time;
    s.motor_q_left = d.motor_q, s.motor_v_left = d.motor_v;
    s.override_left = d.drives.target_override;
    detach.ok = true;
}

int friction_mode(const Data& d, int dof) {
    const auto* s = static_cast<const Session*>(d.accurate_session.get());
    if (!s || s->owner != &d) return 2;
    for (size_t i = 0; i < s->friction_dof.size(); ++i)
        if (s->friction_dof[i] == dof) return s->mode[i];
    return 2;
}

}  // namespace mbx::sim
