#include "sim/simulation.h"

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>

#include <sys/statvfs.h>

#include "core/report/json_writer.h"
#include "sim/cvode_session.h"
#include "sim/transmission.h"

namespace mbx::sim {
namespace {

std::string number(double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, r.ptr);
}

// Three significant figures: sizes and counts in messages.
std::string brief(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

double total_energy(const Model& m, Data& d) {
    update_kinematics(m, d);
    double k = 0, g = 0, s = 0;
    energy(m, d, k, g, s);
    return k + g + s + transmission_energy(m, d);
}

bool model_is_passive(const Model& m) {
    if (!m.drives.empty()) return false;
    for (const Transmission& t : m.transmissions)
        if (t.damping != 0 || t.backlash != 0) return false;
    for (const JointT<double>& j : m.joints)
        if (j.dynamics.damping != 0 || (j.dynamics.asymmetric && j.dynamics.damping_negative != 0) ||
            j.dynamics.dry_friction() || j.dynamics.offset != 0 || j.dynamics.limited)
            return false;
    return true;
}

}  // namespace

int find_joint(const Model& m, const std::string& key, bool* ambiguous) {
    int found = -1;
    if (ambiguous) *ambiguous = false;
    for (size_t k = 0; k < m.joints.size(); ++k) {
        const JointT<double>& j = m.joints[k];
        if (j.name == key || (!j.constraint_id.empty() && j.constraint_id == key)) {
            if (found >= 0 && found != int(k)) {
                if (ambiguous) *ambiguous = true;
                return -1;
            }
            found = int(k);
        }
    }
    return found;
}

void initial_state(const Model& m, Data& d, const std::vector<FixedValue>& fixed, double closure_tolerance) {
    d.q = m.q_reference;
    d.v.setZero(m.nv);
    d.time = 0;
    d.stats = RunStats{};
    d.drives.reset();
    std::vector<char> q_fixed(size_t(m.nv), 0), v_fixed(size_t(m.nv), 0);
    for (const FixedValue& f : fixed) {
        const JointT<double>& j = m.joints[size_t(f.joint)];
        if (!std::isfinite(f.value))
            throw Error(MBX_ERROR_INVALID_INPUT, j.subject(), "joint '" + j.name + "': initial value is not finite");
        const int n = f.velocity ? j.nv() : j.nq();
        if (f.index < 0 || f.index >= n)
            throw Error(MBX_ERROR_INVALID_INPUT, j.subject(), "joint '" + j.name + "' has no coordinate " + std::to_string(f.index));
        if (f.velocity) {
            d.v[j.v_index + f.index] = f.value;
            v_fixed[size_t(j.v_index + f.index)] = 1;
        } else {
            d.q[j.q_index + f.index] = f.value;
            // The velocity coordinates that move the fixed position: one for a
            // revolute, prismatic or a free joint's translation; the whole
            // rotation for any quaternion component.
            const bool translation = j.kind == JointKind::Free && f.index < 3;
            const bool rotation = j.kind == JointKind::Spherical || (j.kind == JointKind::Free && f.index >= 3);
            const int first = translation ? f.index : rotation ? j.nv() - 3 : 0;
            const int count = rotation ? 3 : 1;
            for (int k = first; k < first + count; ++k) q_fixed[size_t(j.v_index + k)] = 1;
        }
    }
    for (const JointT<double>& j : m.joints) {
        if (j.kind == JointKind::Spherical || j.kind == JointKind::Free) {
            const int o = j.kind == JointKind::Free ? 3 : 0;
            Eigen::Map<Eigen::Vector4d> quat(d.q.data() + j.q_index + o);
            if (!(quat.norm() > 1e-12))
                throw Error(MBX_ERROR_INVALID_INPUT, j.subject(), "joint '" + j.name + "': quaternion of zero length");
            quat.normalize();
        }
    }
    check_finite_state(m, d, "in the initial state");
    // Motors from their links' state, at rest against the load (after the
    // loops are closed, below, when there are loops).
    if (m.closures.empty()) return settle_transmissions(m, d);
    const double tol = closure_tolerance / m.length_scale;
    if (!project_positions(m, d, d.closure_factor, tol, 100, &q_fixed)) {
        const int worst = worst_closure(m, d.residual);
        const LoopClosureT<double>& c = m.closures[size_t(worst < 0 ? 0 : worst)];
        throw Error(MBX_ERROR_INVALID_INPUT, c.subject(),
                    "no loop closure satisfies the initial values: the loop closed by cut joint '" + c.name +
                        "' stays open by " + number(d.residual.lpNorm<Eigen::Infinity>() * m.length_scale) + " m (or rad)");
    }
    update_positions(m, d);
    const double left = project_velocities(m, d, d.closure_factor, &v_fixed);
    update_closure_jacobian(m, d);
    const Eigen::VectorXd jv = d.J * d.v;
    if (left > 1e-9) {
        const LoopClosureT<double>& c = m.closures[size_t(std::max(0, worst_closure(m, jv)))];
        throw Error(MBX_ERROR_INVALID_INPUT, c.subject(),
                    "no loop closure satisfies the initial velocities: the loop closed by cut joint '" + c.name +
                        "' would open at " + number(left * m.length_scale) + " per second");
    }
    settle_transmissions(m, d);
}

std::vector<std::string> trajectory_columns(const Model& m) {
    std::vector<std::string> cols{"time"};
    std::map<std::string, int> uses;
    for (const JointT<double>& j : m.joints) ++uses[j.name];
    auto name_of = [&](const JointT<double>& j) {
        return uses[j.name] > 1 && !j.constraint_id.empty() ? j.name + "@" + j.constraint_id : j.name;
    };
    for (const JointT<double>& j : m.joints) {
        const std::string n = name_of(j);
        switch (j.kind) {
        case JointKind::Revolute:
        case JointKind::Prismatic: cols.insert(cols.end(), {n + ".q", n + ".qd"}); break;
        case JointKind::Spherical: cols.insert(cols.end(), {n + ".qw", n + ".qx", n + ".qy", n + ".qz", n + ".wx", n + ".wy", n + ".wz"}); break;
        case JointKind::Free:
            cols.insert(cols.end(), {n + ".x", n + ".y", n + ".z", n + ".qw", n + ".qx", n + ".qy", n + ".qz", n + ".vx",
                                     n + ".vy", n + ".vz", n + ".wx", n + ".wy", n + ".wz"});
            break;
        case JointKind::Fixed: break;
        }
    }
    // The motors of elastic transmissions, after the joints (the joint's
    // own columns are its link's).
    for (const Transmission& t : m.transmissions) {
        const std::string n = name_of(m.joints[size_t(t.joint)]);
        cols.insert(cols.end(), {n + ".motor_q", n + ".motor_qd"});
    }
    for (const Drive& drive : m.drives)
        cols.insert(cols.end(), {drive.name + ".target", drive.name + ".u", drive.name + ".current", drive.name + ".effort"});
    return cols;
}

namespace {

// The state as one trajectory row, in trajectory_columns' order.
void sample(const Model& m, const Data& d, std::vector<double>& row) {
    row.clear();
    row.push_back(d.time);
    for (const JointT<double>& j : m.joints) {
        for (int k = 0; k < j.nq(); ++k) row.push_back(d.q[j.q_index + k]);
        for (int k = 0; k < j.nv(); ++k) row.push_back(d.v[j.v_index + k]);
    }
    for (Eigen::Index i = 0; i < d.motor_q.size(); ++i) row.insert(row.end(), {d.motor_q[i], d.motor_v[i]});
    for (const DriveSignals& s : d.drives.signals) row.insert(row.end(), {s.target, s.output, s.current, s.effort});
}

}  // namespace

void Trajectory::open(const std::vector<std::string>& names, double rows) {
    const double bytes = rows * 8.0 * double(names.size());
    if (bytes > double(kTrajectoryLimitBytes))
        throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::model(""),
                    "the run would hold " + brief(rows) + " samples (" + brief(bytes / 1073741824.0) +
                        " GiB) in memory and the limit is " + brief(double(kTrajectoryLimitBytes) / 1073741824.0) +
                        " GiB: raise the output step or shorten the run");
    columns = names;
    values.clear();
}

namespace {

// The most characters a sample takes in trajectory.csv: a shortest
// round-trip double is at most 24 characters, then its separator.
constexpr double kCsvBytesPerValue = 25;

}  // namespace

void RunFiles::open(const std::vector<std::string>& names, double rows) {
    csv_ = std::make_unique<StreamedFile>(dir_ + "/trajectory.csv");
    struct statvfs fs {};
    const double need = rows * kCsvBytesPerValue * double(names.size());
    if (::statvfs(dir_.c_str(), &fs) == 0) {
        const double free_bytes = double(fs.f_bavail) * double(fs.f_frsize);
        if (need > free_bytes) {
            csv_.reset();
            throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject{MBX_SUBJECT_FILE, dir_ + "/trajectory.csv", ""},
                        "the trajectory of " + brief(rows) + " samples may take up to " + brief(need / 1073741824.0) +
                            " GiB and the file system of '" + dir_ + "' has " + brief(free_bytes / 1073741824.0) +
                            " GiB free: raise the output step or shorten the run");
        }
    }
    columns_ = names.size();
    line_.clear();
    for (size_t c = 0; c < names.size(); ++c) {
        if (c) line_ += ',';
        line_ += names[c];
    }
    line_ += '\n';
    csv_->append(line_);
}

void RunFiles::add(const double* row) {
    line_.clear();
    char buf[32];
    for (size_t c = 0; c < columns_; ++c) {
        if (c) line_ += ',';
        const auto r = std::to_chars(buf, buf + sizeof buf, row[c]);
        line_.append(buf, r.ptr);
    }
    line_ += '\n';
    csv_->append(line_);
}

void RunFiles::commit(const Model& m, const RunSummary& s) {
    if (!csv_) throw Error(MBX_ERROR_INTERNAL, Subject::model(m.name), "the run's files were committed before the run");
    JsonWriter w;
    w.begin_object();
    w.key("model").value(m.name);
    w.key("integrator").value(s.integrator);
    w.key("stop_time").value(s.stop_time);
    w.key("step").value(s.step);
    if (s.integrator == "accurate") w.key("tolerance").value(s.tolerance);
    w.key("output_step").value(s.output_step);
    w.key("samples").value(s.samples);
    w.key("steps").value(s.stats.steps);
    w.key("function_evaluations").value(s.stats.evaluations);
    w.key("friction_mode_switches").value(s.stats.mode_switches);
    w.key("wall_time").value(s.wall_time);
    w.key("steps_per_second").value(s.steps_per_second);
    w.key("max_loop_closure_residual").value(s.stats.max_closure_residual);
    w.key("energy_start").value(s.energy_start);
    w.key("energy_drift").value(s.energy_drift);
    w.key("energy_drift_relative").value(s.energy_drift_relative);
    w.key("energy_conserved_expected").value(s.passive);
    w.key("gravity").begin_array();
    for (int k = 0; k < 3; ++k) w.value(m.gravity[k]);
    w.end_array();
    w.end_object();
    write_files_atomically({{dir_ + "/simulation.json", w.str() + "\n"}}, {csv_.get()});
}

RunSummary run(const Model& m, Data& d, const RunSettings& settings, SampleSink& out) {
    const IntegratorSettings& is = settings.integrator;
    auto bad = [](const std::string& what) { throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::model(""), what); };
    if (!(std::isfinite(settings.stop_time) && settings.stop_time > d.time)) bad("the stop time must be finite and after the current time");
    if (!(std::isfinite(settings.output_step) && settings.output_step > 0)) bad("the output step must be positive");
    const bool accurate = is.kind == IntegratorKind::Accurate;
    if (accurate) {
        // The step bounds CVODE's steps (0: none); outputs are interpolated.
        if (!(std::isfinite(is.step) && is.step >= 0)) bad("the largest step must be 0 (no bound) or positive");
        if (!(std::isfinite(is.tolerance) && is.tolerance > 0 && is.tolerance < 1)) bad("the tolerance must be in (0, 1)");
    } else if (!(std::isfinite(is.step) && is.step > 0)) {
        bad("the step must be positive");
    }
    // Counts from the times, checked before any work: a count that does not
    // fit would wrap (a 1e17 s run took 0 steps and succeeded).
    const double span = settings.stop_time - d.time, output_count = std::floor(span / settings.output_step + 1e-9);
    if (!(output_count >= 1))
        bad("the output step (" + number(settings.output_step) + " s) is longer than the run (" + number(span) +
            " s): not one sample would follow the start");
    if (!(output_count < 9e15)) bad("the run would take " + brief(output_count) + " output samples: raise the output step");
    const double ratio = accurate ? 1.0 : settings.output_step / is.step;
    if (!accurate && !(ratio < 9e15)) bad("the output step (" + number(settings.output_step) + " s) is too many steps (" + number(is.step) + " s)");
    const long long per_output = std::llround(ratio);
    if (per_output < 1 || std::fabs(ratio - double(per_output)) > 1e-9 * ratio)
        bad("the output step (" + number(settings.output_step) + " s) must be a whole number of steps (" + number(is.step) + " s)");
    if (!accurate && output_count * double(per_output) > double(kStepLimit))
        bad("the run would take " + brief(output_count * double(per_output)) + " steps of " + number(is.step) +
            " s, more than the limit of " + brief(double(kStepLimit)) + ": raise the step or shorten the run");
    check_finite_state(m, d, "at the start");
    out.open(trajectory_columns(m), output_count + 1);

    RunSummary s;
    s.integrator = integrator_name(is.kind);
    s.stop_time = settings.stop_time;
    s.step = is.step;
    s.tolerance = is.tolerance;
    s.output_step = settings.output_step;
    s.passive = model_is_passive(m);
    const auto start = std::chrono::steady_clock::now();
    Heartbeat heartbeat(settings.progress ? Heartbeat::Callback([&](const char*, double f) { return settings.progress(f); })
                                          : Heartbeat::Callback(),
                        "the simulation", settings.progress_interval);
    HeartbeatScope beating(&heartbeat);
    heartbeat.stage("simulating", 0);

    // Drive signals at t0 for the first sample.
    update_controllers(m, d, d.time);
    drive_forces(m, d);
    const double t0 = d.time;
    s.energy_start = total_energy(m, d);
    std::vector<double> row;
    auto take_sample = [&](Data& at) {
        sample(m, at, row);
        out.add(row.data());
        ++s.samples;
        s.energy_drift = std::max(s.energy_drift, std::fabs(total_energy(m, at) - s.energy_start));
    };
    take_sample(d);
    const long long outputs = (long long)output_count;
    if (accurate) {
        AccurateRequest request;
        request.stop_time = settings.stop_time;
        request.sample_start = t0;
        request.sample_step = settings.output_step;
        request.sample_count = outputs;
        request.sample = take_sample;
        request.step_taken = [&](double t) { heartbeat.beat((t - t0) / span); };
        accurate_advance(m, d, is, request);
    } else {
        long long step_index = 0;
        const double steps = output_count * double(per_output);
        for (long long k = 1; k <= outputs; ++k) {
            for (long long i = 0; i < per_output; ++i) {
                fixed_step(m, d, is);
                // Times from the step count, so that no round-off accumulates.
                d.time = t0 + double(++step_index) * is.step;
                heartbeat.beat(double(step_index) / steps);
            }
            take_sample(d);
        }
    }
    heartbeat.report_now(1.0);
    s.stats = d.stats;
    s.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    s.steps_per_second = s.wall_time > 0 ? double(s.stats.steps) / s.wall_time : 0;
    const double e_scale = std::max(std::fabs(s.energy_start), 1e-300);
    s.energy_drift_relative = s.energy_drift / e_scale;
    return s;
}

}  // namespace mbx::sim
