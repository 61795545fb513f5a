#include "calibration/records/records.h"

#include <cmath>
#include <map>

#include "calibration/records/body_quantities.h"
#include "core/finding.h"
#include "core/heartbeat.h"
#include "core/text_format.h"
#include "sim/simulation.h"

namespace mbx::calibration {

namespace {

[[noreturn]] void fail(const std::string& path, int line, const std::string& message) {
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"),
                path + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + message, path, line);
}

}  // namespace

int joint_of_key(const sim::Model& m, const std::string& key, const std::string& file, int line) {
    bool ambiguous = false;
    const int j = sim::find_joint(m, key, &ambiguous);
    if (j < 0)
        fail(file, line,
             ambiguous ? "joint '" + key + "' names several joints; give its CAD constraint id"
                       : "no joint '" + key + "' in the model (CAD constraint id or report name)");
    const sim::JointT<double>& joint = m.joints[size_t(j)];
    if (joint.nv() != 1)
        fail(file, line, "joint '" + joint.name + "' has no single coordinate (only revolute and prismatic joints can be measured)");
    return j;
}

std::vector<Record> load_records(const Experiment& e, const sim::Model& m) {
    // Bind columns to joints first: one error for an unknown joint, whatever the records.
    struct Binding {
        const ColumnSpec* spec;
        int joint, dof;
        double factor;
        int body = -1;
    };
    std::vector<Binding> bindings;
    for (const ColumnSpec& c : e.columns) {
        if (!c.body.empty()) {
            const int b = body_of_key(m, c.body, e.path, c.line);
            double factor = 1;
            if (!unit_factor(c.quantity, c.unit, true, factor))
                fail(e.path, c.line, "unit '" + c.unit + "' does not fit the " + quantity_name(c.quantity) + " of body '" +
                                         m.bodies[size_t(b)].name + "'");
            bindings.push_back({&c, -1, -1, factor * c.scale, b});
            continue;
        }
        const int j = joint_of_key(m, c.joint, e.path, c.line);
        const sim::JointT<double>& joint = m.joints[size_t(j)];
        const bool linear = joint.kind == sim::JointKind::Prismatic;
        double factor = 1;
        if (!unit_factor(c.quantity, c.unit, linear, factor))
            fail(e.path, c.line, "unit '" + c.unit + "' does not fit the " + quantity_name(c.quantity) + " of " +
                                     (linear ? "prismatic" : "revolute") + " joint '" + joint.name + "'");
        bindings.push_back({&c, j, joint.v_index, factor * c.scale});
    }
    std::vector<Record> out;
    for (const RecordSpec& rs : e.records) {
        // The records stage's progress: this file's share, read as it is parsed.
        const double done = double(&rs - e.records.data()), files = double(e.records.size());
        const HeartbeatShare share(done / files, (done + 1) / files);
        Table table = read_csv(rs.path);
        const int tc = table.column(e.time_column);
        if (tc < 0) fail(rs.path, 1, "no time column '" + e.time_column + "' (" + e.path + ":" + std::to_string(rs.line) + ")");
        const std::vector<double>& t_raw = table.columns[size_t(tc)];
        // The rows of each record: the whole file, or one trial's rows each.
        std::vector<std::pair<std::string, std::vector<size_t>>> parts;
        if (e.trial_column.empty()) {
            parts.emplace_back(rs.path, std::vector<size_t>(t_raw.size()));
            for (size_t k = 0; k < t_raw.size(); ++k) parts.back().second[k] = k;
        } else {
            const int trial = table.column(e.trial_column);
            if (trial < 0)
                fail(rs.path, 1, "no trial column '" + e.trial_column + "' (" + e.path + ":" + std::to_string(rs.line) + ")");
            std::map<long long, size_t> index;
            std::vector<long long> ids;
            std::vector<std::vector<size_t>> rows;
            for (size_t k = 0; k < t_raw.size(); ++k) {
                const double v = table.columns[size_t(trial)][k];
                if (v != std::floor(v)) fail(rs.path, int(k) + 2, "trial id " + readable(v) + " is not an integer");
                const auto [it, added] = index.emplace((long long)v, ids.size());
                if (added) ids.push_back((long long)v), rows.emplace_back();
                rows[it->second].push_back(k);
            }
            std::vector<long long> wanted = rs.trials.empty() ? ids : rs.trials;
            for (long long id : wanted) {
                const auto it = index.find(id);
                if (it == index.end())
                    fail(e.path, rs.line, "no trial " + std::to_string(id) + " in " + rs.path);
                parts.emplace_back(rs.path + "#" + std::to_string(id), rows[it->second]);
            }
        }
        // The binding that reads each column last (it may take the column whole).
        std::vector<const Binding*> last_use(table.columns.size(), nullptr);
        for (const Binding& b : bindings) {
            const int c = table.column(b.spec->name);
            if (c >= 0 && c != tc) last_use[size_t(c)] = &b;
        }
        const bool whole = e.trial_column.empty();
        // A trial is short (a toss lasts a second), and its samples serve a rollout, not identification.
        const size_t minimum = e.trial_column.empty() ? kMinimumSamples : kMinimumTrialSamples;
        for (const auto& [path, all_rows] : parts) {
            heartbeat();
            for (size_t i = 1; i < all_rows.size(); ++i)
                if (!(t_raw[all_rows[i]] > t_raw[all_rows[i - 1]]))
                    fail(rs.path, int(all_rows[i]) + 2,
                         e.trial_column.empty() ? "time does not increase" : "time does not increase within the trial");
            std::vector<size_t> rows;
            for (size_t k : all_rows) {
                const double t = t_raw[k] * e.time_factor;
                if ((rs.start < 0 || t >= rs.start) && (rs.stop < 0 || t <= rs.stop)) rows.push_back(k);
            }
            if (rows.size() < minimum)
                fail(path, 0, std::to_string(rows.size()) + " samples" +
                                  (rs.start >= 0 || rs.stop >= 0 ? " in the window" : "") + "; at least " +
                                  std::to_string(minimum) + " are needed (" + e.path + ":" + std::to_string(rs.line) + ")");
            Record r;
            r.path = path;
            r.role = rs.role;
            r.cutoff = e.cutoff;
            for (size_t k : rows) r.t.push_back(t_raw[k] * e.time_factor);
            r.start = r.t.front(), r.stop = r.t.back();
            for (const Binding& b : bindings) {
                const int c = table.column(b.spec->name);
                if (c < 0) {
                    if (b.spec->optional) continue;
                    fail(rs.path, 1, "no column '" + b.spec->name + "' (described at " + e.path + ":" +
                                         std::to_string(b.spec->line) + ")");
                }
                std::vector<double> values;
                std::vector<double>& column = table.columns[size_t(c)];
                if (whole && parts.size() == 1 && rows.size() == column.size() && last_use[size_t(c)] == &b) {
                    // A record of millions of rows: its column becomes the
                    // signal, not a second copy of it.
                    values = std::move(column);
                    if (b.factor != 1)
                        for (double& v : values) v *= b.factor;
                } else {
                    values.reserve(rows.size());
                    for (size_t k : rows) values.push_back(column[k] * b.factor);
                }
                if (b.body >= 0) {
                    BodySignal s;
                    s.quantity = b.spec->quantity, s.body = b.body, s.component = b.spec->component, s.column = b.spec->name;
                    s.point = Eigen::Vector3d(b.spec->point[0], b.spec->point[1], b.spec->point[2]);
                    s.values = std::move(values);
                    r.body_signals.push_back(std::move(s));
                    continue;
                }
                Signal s;
                s.quantity = b.spec->quantity, s.joint = b.joint, s.dof = b.dof, s.column = b.spec->name;
                s.values = std::move(values);
                r.signals.push_back(std::move(s));
            }
            out.push_back(std::move(r));
        }
    }
    return out;
}

}  // namespace mbx::calibration
