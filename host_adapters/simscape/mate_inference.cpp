#include "mate_inference.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace mbx_files {
namespace {

using Eigen::Vector3d;
using Row = Eigen::Matrix<double, 6, 1>;  // acts on the twist (omega, v), v the velocity at the origin

// Directions within this of parallel (perpendicular) count as such: exporters
// print nine digits.
constexpr double kAngle = 1e-6;
// The mobility analysis' rank rule: singular values above 1e-9 * max(1, largest).
constexpr double kRank = 1e-9;

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Two unit vectors across n.
void across(const Vector3d& n, Vector3d& e1, Vector3d& e2) {
    e1 = n.unitOrthogonal();
    e2 = n.cross(e1);
}

bool axial(const std::string& t) { return t == "cylinder" || t == "circle" || t == "line" || t == "axis" || t == "cone"; }
bool pointlike(const std::string& t) { return t == "point" || t == "vertex" || t == "sphere"; }

class Stack {
public:
    Stack(const Vector3d& centre, double length) : c_(centre), l_(length) {}
    // The follower's point p may not move along e relative to the base.
    void translation(const Vector3d& p, const Vector3d& e) {
        const Vector3d q = (p - c_) / l_;
        Row r;
        r << q.cross(e), e;
        rows_.push_back(r);
    }
    // The follower may not turn about e relative to the base.
    void rotation(const Vector3d& e) {
        Row r;
        r << e, Vector3d::Zero();
        rows_.push_back(r);
    }
    size_t size() const { return rows_.size(); }
    Eigen::MatrixXd matrix() const {
        Eigen::MatrixXd a(rows_.size(), 6);
        for (size_t k = 0; k < rows_.size(); ++k) a.row(Eigen::Index(k)) = rows_[k].transpose();
        return a;
    }
    const Vector3d& centre() const { return c_; }
    double length() const { return l_; }

private:
    Vector3d c_;
    double l_;
    std::vector<Row> rows_;
};

int rank_of(const Eigen::MatrixXd& a) {
    if (a.rows() == 0) return 0;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a);
    const Eigen::VectorXd s = svd.singularValues();
    const double tau = kRank * std::max(1.0, s.size() ? s[0] : 0.0);
    int r = 0;
    for (Eigen::Index k = 0; k < s.size(); ++k) r += s[k] > tau;
    return r;
}

// The rows one mate adds; false (with a problem) where it cannot hold at the
// exported pose or its geometry is not one mbx reads for its type.
bool add_mate(const Mate& m, int index, double length, Stack& rows, std::vector<MateProblem>& problems) {
    const std::string type = lower(m.type), t1 = lower(m.first.type), t2 = lower(m.second.type);
    const Vector3d p1 = m.first.position, p2 = m.second.position;
    auto fail = [&](bool error, const std::string& why) {
        problems.push_back({index, error, m.type + " mate '" + m.name + "' " + why});
        return false;
    };
    if (!(p1.allFinite() && p2.allFinite() && m.first.axis.allFinite() && m.second.axis.allFinite()))
        return fail(true, "has a geometry that is not a number");
    const bool directed = t1 == "plane" || axial(t1) || !pointlike(t1);
    if (directed && (m.first.axis.norm() < 1e-12 || m.second.axis.norm() < 1e-12) && !(pointlike(t1) && pointlike(t2)))
        return fail(true, "has an axis of zero length");
    const Vector3d n1 = m.first.axis.normalized(), n2 = m.second.axis.normalized();
    const double tol = 1e-6 * length;
    const bool parallel = n1.cross(n2).norm() <= kAngle;
    Vector3d e1, e2;
    across(n1, e1, e2);
    auto point_rows = [&](const Vector3d& p) {
        rows.translation(p, Vector3d::UnitX());
        rows.translation(p, Vector3d::UnitY());
        rows.translation(p, Vector3d::UnitZ());
    };
    auto axis_rows = [&]() {
        rows.translation(p1, e1);
        rows.translation(p1, e2);
        rows.rotation(e1);
        rows.rotation(e2);
    };
    const std::string pair = t1 + "/" + t2;
    if (type == "coincident") {
        if (t1 == "plane" && t2 == "plane") {
            if (!parallel) return fail(true, "joins planes that are not parallel at the exported pose");
            if (std::abs((p2 - p1).dot(n1)) > tol)
                return fail(true, "joins planes " + std::to_string((p2 - p1).dot(n1)) + " apart at the exported pose");
            rows.translation(p1, n1);
            rows.rotation(e1);
            rows.rotation(e2);
            return true;
        }
        if (pointlike(t1) && pointlike(t2)) {
            if ((p2 - p1).norm() > tol) return fail(true, "joins points that are apart at the exported pose");
            point_rows(p1);
            return true;
        }
        if ((pointlike(t1) && t2 == "plane") || (t1 == "plane" && pointlike(t2))) {
            const Vector3d point = pointlike(t1) ? p1 : p2, on = pointlike(t1) ? p2 : p1, n = pointlike(t1) ? n2 : n1;
            if (std::abs((point - on).dot(n)) > tol) return fail(true, "puts a point off its plane at the exported pose");
            rows.translation(point, n);
            return true;
        }
        if (axial(t1) && axial(t2)) {
            if (!parallel || (p2 - p1).cross(n1).norm() > tol)
                return fail(true, "joins axes that do not coincide at the exported pose");
            axis_rows();
            return true;
        }
        return fail(false, "joins a " + pair + " pair, which mbx does not read as a coincident mate; it is left out");
    }
    if (type == "concentric") {
        if (axial(t1) && axial(t2)) {
            if (!parallel || (p2 - p1).cross(n1).norm() > tol)
                return fail(true, "joins axes that do not coincide at the exported pose");
            axis_rows();
            return true;
        }
        if (pointlike(t1) && pointlike(t2)) {
            if ((p2 - p1).norm() > tol) return fail(true, "joins centres that are apart at the exported pose");
            point_rows(p1);
            return true;
        }
        return fail(false, "joins a " + pair + " pair, which mbx does not read as a concentric mate; it is left out");
    }
    if (type == "parallel") {
        if (!parallel) return fail(true, "joins directions that are not parallel at the exported pose");
        rows.rotation(e1);
        rows.rotation(e2);
        return true;
    }
    if (type == "perpendicular" || type == "angle") {
        const Vector3d hinge = n1.cross(n2);
        if (type == "perpendicular" && std::abs(n1.dot(n2)) > kAngle)
            return fail(true, "joins directions that are not perpendicular at the exported pose");
        if (hinge.norm() <= kAngle) return fail(false, "joins parallel directions, whose angle holds no turn; it is left out");
        rows.rotation(hinge.normalized());
        return true;
    }
    if (type == "distance") {
        if (t1 == "plane" && t2 == "plane") {
            if (!parallel) return fail(true, "joins planes that are not parallel at the exported pose");
            rows.translation(p1, n1);
            rows.rotation(e1);
            rows.rotation(e2);
            return true;
        }
        if (pointlike(t1) && pointlike(t2)) {
            const Vector3d d = p2 - p1;
            if (d.norm() <= tol) return fail(false, "keeps two points at no distance; read it as coincident");
            rows.translation(p2, d.normalized());
            return true;
        }
        return fail(false, "joins a " + pair + " pair, which mbx does not read as a distance mate; it is left out");
    }
    return fail(false, "is a mate type mbx does not read (it reads Coincident, Concentric, Parallel, "
                       "Perpendicular, Angle and Distance); it is left out");
}

Eigen::Isometry3d frame_at(const Vector3d& origin, const Vector3d& z, const Vector3d& x_hint) {
    Vector3d x = x_hint - x_hint.dot(z) * z;
    if (x.norm() < 1e-9) x = z.unitOrthogonal();
    x.normalize();
    Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
    f.linear().col(0) = x;
    f.linear().col(1) = z.cross(x);
    f.linear().col(2) = z;
    f.translation() = origin;
    return f;
}

// The point q (scaled coordinates) about which every twist in `twists` is a
// pure rotation, if there is one: v + omega x q = 0 for each.
bool common_point(const std::vector<Row>& twists, Vector3d& q) {
    Eigen::MatrixXd a(3 * twists.size(), 3);
    Eigen::VectorXd b(3 * twists.size());
    for (size_t k = 0; k < twists.size(); ++k) {
        const Vector3d w = twists[k].head<3>(), v = twists[k].tail<3>();
        Eigen::Matrix3d cross;
        cross << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
        a.block(Eigen::Index(3 * k), 0, 3, 3) = cross;
        b.segment(Eigen::Index(3 * k), 3) = -v;
    }
    q = a.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(b);
    return (a * q - b).norm() <= 1e-6 * std::max(1.0, b.norm());
}

}  // namespace

InferredJoint infer_joint(const std::vector<Mate>& mates, double length, std::vector<MateProblem>& problems) {
    InferredJoint out;
    if (!(length > 0) || !std::isfinite(length)) length = 1;
    Vector3d centre = Vector3d::Zero();
    int counted = 0;
    for (const Mate& m : mates)
        if (m.first.position.allFinite()) centre += m.first.position, ++counted;
    if (counted) centre /= counted;
    Stack rows(centre, length);
    int rank = 0;
    int anchor_mate = -1;
    for (size_t k = 0; k < mates.size(); ++k) {
        const size_t before = rows.size();
        if (!add_mate(mates[k], int(k), length, rows, problems)) continue;
        if (anchor_mate < 0) anchor_mate = int(k);
        const int now = rank_of(rows.matrix());
        // (a mate that repeats part of another, as a hinge's face does its
        // bore's turns, is how CAD users define a joint; one that adds
        // nothing at all is redundant)
        if (now == rank && rows.size() > before) out.redundant.push_back(int(k));
        rank = now;
    }
    out.freedoms = 6 - rank;
    const Vector3d anchor = anchor_mate >= 0 ? mates[size_t(anchor_mate)].first.position : centre;
    if (rank == 6) {
        out.type = "Weld";
        out.frame = frame_at(anchor, Vector3d::UnitZ(), Vector3d::UnitX());
        return out;
    }
    if (rank == 0) return out;  // nothing holds the parts together: no joint
    // The motion left: the null space of the rows, split into its pure
    // translations and the rotations beside them.
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(rows.matrix(), Eigen::ComputeFullV);
    const Eigen::MatrixXd null = svd.matrixV().rightCols(6 - rank);
    const Eigen::JacobiSVD<Eigen::MatrixXd> turn(null.topRows(3), Eigen::ComputeFullV);
    const Eigen::VectorXd ts = turn.singularValues();
    int turning = 0;
    for (Eigen::Index k = 0; k < ts.size(); ++k) turning += ts[k] > 1e-6;
    std::vector<Vector3d> slides;  // unit directions, world
    std::vector<Row> turns;        // twists with a rotation, scaled coordinates
    const Eigen::MatrixXd v = turn.matrixV();
    for (Eigen::Index k = 0; k < null.cols(); ++k) {
        const Row t = null * v.col(k);
        if (k < turning) turns.push_back(t);
        else slides.push_back(t.tail<3>().normalized());
    }
    // Axes point the way the first mate's first geometry does (where it is
    // not across them), so that a joint's sign follows the CAD's.
    const Vector3d reference = anchor_mate >= 0 ? mates[size_t(anchor_mate)].first.axis.normalized() : Vector3d::UnitZ();
    auto oriented = [&](Vector3d a) { return a.dot(reference) < -1e-6 ? Vector3d(-a) : a; };
    for (Vector3d& d : slides) d = oriented(d);
    auto world = [&](const Vector3d& q) { return rows.centre() + rows.length() * q; };
    auto on_axis = [&](const Vector3d& q, const Vector3d& a) { return world(q) + a * (anchor - world(q)).dot(a); };
    const size_t n = size_t(6 - rank);
    if (turning == 0) {
        out.type = n == 1 ? "Prismatic" : n == 2 ? "Rectangular" : n == 3 ? "Cartesian" : "";
        if (out.type.empty()) return out;
        if (n == 1) out.frame = frame_at(anchor, slides[0], Vector3d::UnitX());
        else {
            const Vector3d z = n == 2 ? slides[0].cross(slides[1]).normalized() : Vector3d::UnitZ();
            out.frame = frame_at(anchor, z, n == 2 ? slides[0] : Vector3d::UnitX());
        }
        return out;
    }
    if (turning == 1) {
        const Vector3d w = turns[0].head<3>(), vel = turns[0].tail<3>();
        const Vector3d a = oriented(w.normalized());
        const Vector3d q = w.cross(vel) / w.squaredNorm();  // the axis' point nearest the centre
        const double pitch = w.dot(vel) / w.squaredNorm();
        if (n == 1) {
            if (std::abs(pitch) > 1e-6) return out;  // a screw: no joint of the table
            out.type = "Revolute";
            out.frame = frame_at(on_axis(q, a), a, Vector3d::UnitX());
            return out;
        }
        if (n == 2) {
            const Vector3d d = slides[0];
            if (d.cross(a).norm() <= 1e-6) {
                out.type = "Cylindrical";
                out.frame = frame_at(on_axis(q, a), a, Vector3d::UnitX());
            } else if (std::abs(d.dot(a)) <= 1e-6 && std::abs(pitch) <= 1e-6) {
                out.type = "PinSlot";
                out.frame = frame_at(on_axis(q, a), a, d);
            }
            return out;
        }
        if (n == 3 && std::abs(slides[0].dot(a)) <= 1e-6 && std::abs(slides[1].dot(a)) <= 1e-6) {
            out.type = "Planar";
            out.frame = frame_at(on_axis(q, a), a, slides[0]);
        }
        return out;
    }
    if (size_t(turning) == n) {
        Vector3d q;
        if (!common_point(turns, q)) return out;
        if (n == 3) {
            out.type = "Spherical";
            out.frame = frame_at(world(q), Vector3d::UnitZ(), Vector3d::UnitX());
        } else if (n == 2) {
            // Rotations about every axis of a plane through q: x and y in it.
            const Vector3d x = turns[0].head<3>().normalized();
            const Vector3d z = x.cross(turns[1].head<3>()).normalized();
            out.type = "Universal";
            out.frame = frame_at(world(q), z, x);
        }
    }
    return out;
}

}  // namespace mbx_files
