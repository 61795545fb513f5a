// Measured motion of one free body over several trials (tosses, drops,
// pushes), read from one CSV: per sample its time, position, orientation and
// velocities. This is what contact calibration fits to (contact_fit.h): a
// free body's contacts show only in its pose, not in any joint signal.
#pragma once
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace mbx::calibration {

struct PoseSample {
    double t = 0;                 // s
    Eigen::Vector3d p;            // body origin in the world, m
    Eigen::Quaterniond q;         // body into world
    Eigen::Vector3d v;            // origin velocity, world, m/s
    Eigen::Vector3d w;            // angular velocity in the body frame, rad/s
};

struct PoseRecord {
    int trial = 0;
    std::vector<PoseSample> samples;
};

// Column names; the defaults are those of the ContactNets cube tosses
// (../shared/data/measured/contactnets_cube).
struct PoseColumns {
    std::string trial = "toss_id", time = "t_s";
    std::string position[3] = {"x_m", "y_m", "z_m"};
    std::string orientation[4] = {"qw", "qx", "qy", "qz"};
    std::string velocity[3] = {"vx_mps", "vy_mps", "vz_mps"};
    std::string angular_velocity[3] = {"wx_body_radps", "wy_body_radps", "wz_body_radps"};
};

// Every trial of the file in the order they first appear, samples in time
// order. Throws mbx::Error naming file and line: a missing column, a cell
// that is not a finite number (read_csv's checks), a zero quaternion, time
// not increasing within a trial, a trial of fewer than two samples.
std::vector<PoseRecord> read_pose_records(const std::string& path, const PoseColumns& columns = {});

}  // namespace mbx::calibration
