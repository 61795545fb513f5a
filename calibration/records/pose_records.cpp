#include "calibration/records/pose_records.h"

#include <map>

#include "calibration/records/records.h"
#include "core/finding.h"

namespace mbx::calibration {

namespace {

[[noreturn]] void fail(const std::string& path, int line, const std::string& message) {
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model("experiment"),
                path + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + message, path, line);
}

}  // namespace

std::vector<PoseRecord> read_pose_records(const std::string& path, const PoseColumns& columns) {
    const Table table = read_csv(path);
    auto column = [&](const std::string& name) {
        const int c = table.column(name);
        if (c < 0) fail(path, 1, "no column '" + name + "' in the header");
        return c;
    };
    const int trial = column(columns.trial), time = column(columns.time);
    int p[3], q[4], v[3], w[3];
    for (int k = 0; k < 3; ++k) p[k] = column(columns.position[k]);
    for (int k = 0; k < 4; ++k) q[k] = column(columns.orientation[k]);
    for (int k = 0; k < 3; ++k) v[k] = column(columns.velocity[k]);
    for (int k = 0; k < 3; ++k) w[k] = column(columns.angular_velocity[k]);

    std::vector<PoseRecord> out;
    std::map<long long, size_t> index;
    const size_t rows = table.columns.empty() ? 0 : table.columns[0].size();
    auto at = [&](int c, size_t r) { return table.columns[size_t(c)][r]; };
    for (size_t r = 0; r < rows; ++r) {
        // Data rows start on the file's second line (blank lines aside).
        const int line = int(r) + 2;
        const long long id = (long long)at(trial, r);
        auto [it, inserted] = index.emplace(id, out.size());
        if (inserted) out.push_back(PoseRecord{int(id), {}});
        PoseRecord& record = out[it->second];
        PoseSample s;
        s.t = at(time, r);
        s.p = Eigen::Vector3d(at(p[0], r), at(p[1], r), at(p[2], r));
        Eigen::Quaterniond orientation(at(q[0], r), at(q[1], r), at(q[2], r), at(q[3], r));
        if (!(orientation.norm() > 1e-6)) fail(path, line, "the orientation quaternion is zero");
        s.q = orientation.normalized();
        s.v = Eigen::Vector3d(at(v[0], r), at(v[1], r), at(v[2], r));
        s.w = Eigen::Vector3d(at(w[0], r), at(w[1], r), at(w[2], r));
        if (!record.samples.empty() && !(s.t > record.samples.back().t))
            fail(path, line, "time does not increase within trial " + std::to_string(id));
        record.samples.push_back(s);
    }
    if (out.empty()) fail(path, 2, "no samples");
    for (const PoseRecord& r : out)
        if (r.samples.size() < 2) fail(path, 0, "trial " + std::to_string(r.trial) + " has fewer than two samples");
    return out;
}

}  // namespace mbx::calibration
