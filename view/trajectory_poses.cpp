#include "view/trajectory_poses.h"

#include <Eigen/Geometry>
#include <cmath>

#include "core/csv_table.h"
#include "core/finding.h"
#include "sim/build_model.h"
#include "sim/dynamics.h"
#include "sim/simulation.h"

namespace mbx {

namespace {

// Meshed moving bodies in node order and the sim body each is. The ground's
// nodes are left out: the page keeps them at their CAD pose.
struct Posing {
    sim::Model model;
    std::vector<std::string> nodes;
    std::vector<int> sim_body;
};

Posing posing(ExportModel& export_model) {
    Posing p;
    const Mechanism& m = export_model.mechanism();
    p.model = sim::build_model(m);
    for (int b = 1; b < p.model.body_count(); ++b) {
        const int source = p.model.bodies[size_t(b)].source;
        if (source < 0 || !export_model.has_mesh(source)) continue;
        p.nodes.push_back(export_model.mesh_stem(source));
        p.sim_body.push_back(b);
    }
    return p;
}

void append_poses(const Posing& p, sim::Data& d, std::vector<double>& out) {
    sim::update_positions(p.model, d);
    for (int b : p.sim_body) {
        const sim::Transform<double>& x = d.x_world[size_t(b)];
        const Eigen::Quaterniond q(x.R);
        out.insert(out.end(), {x.p.x(), x.p.y(), x.p.z(), q.w(), q.x(), q.y(), q.z()});
    }
}

}  // namespace

PosedTrajectory pose_configuration(ExportModel& model, const std::vector<double>& q) {
    const Posing p = posing(model);
    if (q.size() != size_t(p.model.nq))
        throw Error(MBX_ERROR_INVALID_ARGUMENT, {}, "a configuration of " + std::to_string(p.model.nq) +
                                                         " coordinates is needed, not " + std::to_string(q.size()));
    sim::Data d(p.model);
    d.q = Eigen::Map<const Eigen::VectorXd>(q.data(), long(q.size()));
    PosedTrajectory out;
    out.nodes = p.nodes;
    out.times = {0};
    append_poses(p, d, out.poses);
    return out;
}

PosedTrajectory pose_trajectory(ExportModel& model, const std::string& trajectory_csv) {
    const Posing p = posing(model);
    const CsvTable table = read_csv_table(trajectory_csv, Subject::model("trajectory"));
    // Which column holds each position coordinate: a joint's block in
    // trajectory_columns starts with its positions, in q order.
    const std::vector<std::string> columns = sim::trajectory_columns(p.model);
    std::vector<int> column_of_q(size_t(p.model.nq), -1);
    size_t next = 1;  // after "time"
    for (const sim::JointT<double>& j : p.model.joints) {
        const int nq = j.nq(), nv = j.nv();
        for (int k = 0; k < nq; ++k) {
            const std::string& name = columns[next + size_t(k)];
            const int c = table.column(name);
            if (c < 0)
                throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("trajectory"),
                            trajectory_csv + ": no column '" + name + "' (was the trajectory simulated from this model?)",
                            trajectory_csv, 1);
            column_of_q[size_t(j.q_index + k)] = c;
        }
        next += size_t(nq + nv);
    }
    const int time = table.column("time");
    if (time < 0)
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("trajectory"), trajectory_csv + ": no column 'time'",
                    trajectory_csv, 1);
    PosedTrajectory out;
    out.nodes = p.nodes;
    sim::Data d(p.model);
    const size_t rows = table.columns[size_t(time)].size();
    for (size_t r = 0; r < rows; ++r) {
        const double t = table.columns[size_t(time)][r];
        if (!out.times.empty() && !(t > out.times.back()))
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("trajectory"),
                        trajectory_csv + ":" + std::to_string(r + 2) + ": time does not increase", trajectory_csv,
                        int(r + 2));
        for (int k = 0; k < p.model.nq; ++k) d.q[k] = table.columns[size_t(column_of_q[size_t(k)])][r];
        out.times.push_back(t);
        append_poses(p, d, out.poses);
    }
    return out;
}

}  // namespace mbx
