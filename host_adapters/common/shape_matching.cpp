// Geometry to bodies by pose (thesis section 2.7.2). See shape_matching.h for
// the rules; the notes here say why the code looks the way it does.
//
// Choices the header leaves open:
//  - Every node is resolved on its own pose, not only where the transform
//    changes: an Inline or Model_Info node on its parent's pose resolves the
//    same way unless its own name breaks a tie the parent could not.
//  - Orientation keeps the candidates within angle_tolerance; when it keeps
//    none, names decide among all that share the position (and a failure is
//    reported as a coincidence "in position" only).
//  - Names: an exact (case-insensitive) name first, then the stem; the part
//    name (Model_Info) first, then the DEF name.
//  - An ambiguity is reported once per place: a child on its ambiguous
//    parent's exact pose is not reported again.
//  - With all bodies on one point (or one body) there is no extent to take
//    1e-4 of; positions must then agree to about 1e-9 relative.
#include "shape_matching.h"
#include "host_adapters/common/text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <tuple>
#include <utility>

#include <Eigen/SVD>

namespace mbx_files {
namespace {

// Body positions bucketed in cubes of edge `tolerance`: any body within the
// tolerance of a point lies in one of the 27 cubes around the point's cube,
// so a lookup costs the handful of bodies nearby, whatever the assembly size.
// The cubes live in one flat open-addressing table over a body list sorted
// by cube (27 probes per node must stay in cache: a node-based map made the
// lookups themselves the cost), and points outside the bodies' bounding box
// skip the probes, which is what most nodes do under a wrong VRML scale.
class PositionGrid {
public:
    PositionGrid(const std::vector<BodyPose>& bodies, double tolerance) : bodies_(bodies), tolerance_(tolerance) {
        std::vector<std::pair<Cell, int>> keyed;
        keyed.reserve(bodies.size());
        for (size_t b = 0; b < bodies.size(); ++b) {
            const Eigen::Vector3d p = bodies[b].world.translation();
            if (!p.allFinite()) continue;
            keyed.emplace_back(cell_of(p), int(b));
            lo_ = lo_.cwiseMin(p);
            hi_ = hi_.cwiseMax(p);
        }
        lo_.array() -= tolerance;
        hi_.array() += tolerance;
        // Sorting by cube, then body, groups each cube's bodies in body order.
        std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
            return std::tie(a.first.x, a.first.y, a.first.z, a.second) < std::tie(b.first.x, b.first.y, b.first.z, b.second);
        });
        size_t capacity = 16;
        while (capacity < 2 * keyed.size()) capacity *= 2;
        slots_.assign(capacity, Slot{});
        mask_ = capacity - 1;
        order_.reserve(keyed.size());
        for (size_t i = 0; i < keyed.size(); ++i) {
            order_.push_back(keyed[i].second);
            if (i > 0 && keyed[i].first == keyed[i - 1].first) {
                ++find_slot(keyed[i].first)->end;
                continue;
            }
            Slot* s = find_slot(keyed[i].first);
            *s = Slot{keyed[i].first, uint32_t(i), uint32_t(i + 1)};
        }
    }

    // Bodies whose position is within the tolerance of `p`, in body order.
    void near(const Eigen::Vector3d& p, std::vector<int>& out) const {
        out.clear();
        if (!p.allFinite() || (p.array() < lo_.array()).any() || (p.array() > hi_.array()).any()) return;
        const Cell c = cell_of(p);
        for (int64_t dx = -1; dx <= 1; ++dx)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dz = -1; dz <= 1; ++dz) {
                    const Slot* s = find_slot(Cell{c.x + dx, c.y + dy, c.z + dz});
                    for (uint32_t i = s->begin; i < s->end; ++i) {
                        const int b = order_[i];
                        if ((bodies_[size_t(b)].world.translation() - p).norm() <= tolerance_) out.push_back(b);
                    }
                }
        std::sort(out.begin(), out.end());  // body order keeps messages and tie-breaks stable
    }

private:
    struct Cell {
        int64_t x = 0, y = 0, z = 0;
        bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct Slot {
        Cell cell;
        uint32_t begin = 0, end = 0;  // range in order_; empty slot: begin == end
    };

    static size_t hash(const Cell& c) {
        uint64_t h = uint64_t(c.x) * 0x9E3779B97F4A7C15ull ^ uint64_t(c.y) * 0xC2B2AE3D27D4EB4Full ^
                     uint64_t(c.z) * 0x165667B19E3779F9ull;
        return size_t(h ^ (h >> 29));
    }
    // The slot holding `c`, or the empty slot where it would go.
    const Slot* find_slot(const Cell& c) const {
        for (size_t i = hash(c) & mask_;; i = (i + 1) & mask_) {
            const Slot& s = slots_[i];
            if (s.begin == s.end || s.cell == c) return &s;
        }
    }
    Slot* find_slot(const Cell& c) { return const_cast<Slot*>(static_cast<const PositionGrid*>(this)->find_slot(c)); }

    // Clamped so that coordinates far beyond the grid's reach (a tiny
    // tolerance against huge positions) cannot overflow the integer cast.
    static int64_t index(double v) {
        const double limit = 0x1.0p61;
        return int64_t(std::clamp(std::floor(v), -limit, limit));
    }
    Cell cell_of(const Eigen::Vector3d& p) const {
        return Cell{index(p.x() / tolerance_), index(p.y() / tolerance_), index(p.z() / tolerance_)};
    }

    const std::vector<BodyPose>& bodies_;
    double tolerance_;
    Eigen::Vector3d lo_ = Eigen::Vector3d::Constant(INFINITY), hi_ = Eigen::Vector3d::Constant(-INFINITY);
    std::vector<int> order_;   // body indices sorted by cube
    std::vector<Slot> slots_;  // open addressing, linear probing, at most half full
    size_t mask_ = 0;
};

// Rotation part of a transform that may carry scale (VRML `scale`, or an
// Inline scaled from millimetres): the polar factor U V^T, made proper so a
// mirroring scale still yields a rotation to compare with the body's.
Eigen::Matrix3d rotation_of(const Eigen::Matrix3d& linear) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(linear, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d u = svd.matrixU();
    const Eigen::Matrix3d v = svd.matrixV();
    if ((u * v.transpose()).determinant() < 0) u.col(2) = -u.col(2);
    return u * v.transpose();
}

double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
    // Through the quaternion: acos of the trace loses precision near zero,
    // exactly where the tolerance sits.
    return Eigen::AngleAxisd(Eigen::Quaterniond(a.transpose() * b).normalized()).angle();
}

// "Obj01", "Obj-1", "obj_2" and "Obj" all share the stem "obj": CAD systems
// number instances and exporters write the numbers differently.
std::string stem(const std::string& name) {
    size_t end = name.size();
    while (end > 0) {
        const char c = name[end - 1];
        if (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '_') --end;
        else break;
    }
    std::string s = name.substr(0, end);
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Candidates whose body name equals `name` (ignoring case), or failing that
// shares its stem; an exact name is the stronger evidence when "Obj01" and
// "Obj02" sit on the same pose.
std::vector<int> by_name(const std::vector<BodyPose>& bodies, const std::vector<int>& candidates,
                         const std::string& name) {
    std::vector<int> out;
    if (name.empty()) return out;
    const std::string wanted = lower_case(name);
    for (int b : candidates)
        if (lower_case(bodies[size_t(b)].name) == wanted) out.push_back(b);
    if (!out.empty()) return out;
    const std::string wanted_stem = stem(name);
    if (wanted_stem.empty()) return out;
    for (int b : candidates)
        if (stem(bodies[size_t(b)].name) == wanted_stem) out.push_back(b);
    return out;
}

std::string describe_node(const VrmlNode& node) {
    std::string s = "VRML " + (node.kind.empty() ? std::string("node") : node.kind);
    if (!node.name.empty()) s += " '" + node.name + "'";
    if (!node.part_name.empty()) s += " (part '" + node.part_name + "')";
    if (!node.file.empty()) s += " at " + node.file + ":" + std::to_string(node.line);
    return s;
}

std::string describe_bodies(const std::vector<BodyPose>& bodies, const std::vector<int>& list) {
    std::string s;
    for (size_t i = 0; i < list.size(); ++i) {
        const BodyPose& b = bodies[size_t(list[i])];
        if (i) s += ", ";
        s += "'" + b.name + "' (id '" + b.id + "')";
    }
    return s;
}

std::string format_point(const Eigen::Vector3d& p) {
    char text[96];
    std::snprintf(text, sizeof text, "(%g, %g, %g)", p.x(), p.y(), p.z());
    return text;
}

double default_tolerance(const std::vector<BodyPose>& bodies) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    double largest = 0;
    for (const BodyPose& b : bodies) {
        const Eigen::Vector3d p = b.world.translation();
        if (!p.allFinite()) continue;
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
        largest = std::max(largest, p.cwiseAbs().maxCoeff());
    }
    const double diagonal = bodies.empty() || !(hi.x() >= lo.x()) ? 0 : (hi - lo).norm();
    if (diagonal > 0) return 1e-4 * diagonal;
    // One body, or all on one point: no size to scale by, so only positions
    // that agree to the last few digits coincide.
    return largest > 0 ? 1e-9 * largest : 1e-12;
}

// How one node resolved.
enum class Resolution { none, unique, ambiguous };

class Matcher {
public:
    Matcher(const VrmlScene& scene, const std::vector<BodyPose>& bodies, const MatchOptions& options)
        : scene_(scene), bodies_(bodies), options_(options),
          tolerance_(options.position_tolerance > 0 ? options.position_tolerance : default_tolerance(bodies)),
          grid_(bodies, tolerance_) {}

    // The body each node's shapes belong to (-1: none), plus the count of
    // nodes that singled out a body by their own pose; ambiguities go to
    // `issues`.
    size_t assign(double scale, std::vector<int>& current, std::vector<MatchIssue>& issues) {
        const std::vector<VrmlNode>& nodes = scene_.nodes;
        current.assign(nodes.size(), -1);
        ambiguous_.assign(nodes.size(), 0);
        size_t matched = 0;
        for (size_t i = 0; i < nodes.size(); ++i) {
            const VrmlNode& node = nodes[i];
            const bool has_parent = node.parent >= 0 && size_t(node.parent) < i;
            const int inherited = has_parent ? current[size_t(node.parent)] : -1;
            int chosen = -1;
            const Resolution r = resolve(node, scale, chosen);
            if (r == Resolution::unique) {
                current[i] = chosen;
                ++matched;
                continue;
            }
            current[i] = inherited;
            if (r != Resolution::ambiguous) continue;
            ambiguous_[i] = 1;
            // An Inline or Model_Info node on its parent's pose repeats the
            // parent's question; one report per place is enough.
            if (has_parent && ambiguous_[size_t(node.parent)] &&
                node.world.matrix() == nodes[size_t(node.parent)].world.matrix())
                continue;
            std::string kept = inherited >= 0 ? "body '" + bodies_[size_t(inherited)].name + "'" : "no body";
            issues.push_back({MatchIssue::ambiguous, int(i),
                              describe_node(node) + " at " + format_point(position_) + " coincides in position" +
                                  (aligned_ ? " and orientation" : "") + " with " + std::to_string(candidates_.size()) +
                                  " bodies that its name does not tell apart: " + describe_bodies(bodies_, candidates_) +
                                  "; its shapes stay with " + kept});
        }
        return matched;
    }

private:
    Resolution resolve(const VrmlNode& node, double scale, int& chosen) {
        position_ = scale * node.world.translation();
        grid_.near(position_, candidates_);
        if (candidates_.empty()) return Resolution::none;
        if (candidates_.size() == 1) {
            chosen = candidates_[0];
            return Resolution::unique;
        }
        // Scale does not change the rotation: only the length unit differs.
        const Eigen::Matrix3d rotation = rotation_of(node.world.linear());
        std::vector<int> aligned;
        for (int b : candidates_)
            if (angle_between(rotation, bodies_[size_t(b)].world.linear()) < options_.angle_tolerance)
                aligned.push_back(b);
        if (aligned.size() == 1) {
            chosen = aligned[0];
            return Resolution::unique;
        }
        // None aligned: the node is a CAD sub-assembly placement or a rotated
        // instance; names still decide among all that share the position.
        aligned_ = !aligned.empty();
        const std::vector<int>& pool = aligned_ ? aligned : candidates_;
        std::vector<int> named = by_name(bodies_, pool, node.part_name);
        if (named.size() != 1) {
            std::vector<int> by_def = by_name(bodies_, named.empty() ? pool : named, node.name);
            if (!by_def.empty()) named = std::move(by_def);
        }
        if (named.size() == 1) {
            chosen = named[0];
            return Resolution::unique;
        }
        candidates_ = named.empty() ? pool : named;
        return Resolution::ambiguous;
    }

    const VrmlScene& scene_;
    const std::vector<BodyPose>& bodies_;
    const MatchOptions& options_;
    const double tolerance_;
    const PositionGrid grid_;
    Eigen::Vector3d position_ = Eigen::Vector3d::Zero();  // of the node being resolved
    std::vector<int> candidates_;                         // scratch, reused across nodes
    bool aligned_ = false;                                // some candidates share its orientation
    std::vector<char> ambiguous_;                         // per node, this assignment
};

std::string mesh_name(const VrmlMesh& mesh, const VrmlNode& node) {
    if (!mesh.name.empty()) return mesh.name;
    if (!node.name.empty()) return node.name;
    return node.part_name;
}

}  // namespace

MatchResult match_shapes(const VrmlScene& scene, const std::vector<BodyPose>& bodies, const MatchOptions& options) {
    Matcher matcher(scene, bodies, options);
    MatchResult result;
    std::vector<int> current;

    double scale = options.vrml_scale;
    if (scale > 0) {
        result.matched_nodes = matcher.assign(scale, current, result.issues);
    } else {
        // Exporters write VRML in their own unit (Pro/E: the part's unit,
        // stl2vrml: metres), with nothing in the file to say which; the factor
        // that puts most nodes on a part frame is the one that was used.
        // Each trial is a full assignment, so the winner's is kept as is.
        std::vector<int> trial;
        std::vector<MatchIssue> trial_issues;
        bool first = true;
        for (double factor : {1.0, 0.001, 1000.0, 1 / 25.4, 25.4, 0.01, 100.0}) {
            trial_issues.clear();
            const size_t matched = matcher.assign(factor, trial, trial_issues);
            if (first || matched > result.matched_nodes) {
                first = false;
                scale = factor;
                result.matched_nodes = matched;
                current.swap(trial);
                result.issues.swap(trial_issues);
            }
        }
    }
    result.vrml_scale = scale;

    std::vector<Eigen::Isometry3d> body_from_world(bodies.size());
    for (size_t b = 0; b < bodies.size(); ++b) body_from_world[b] = bodies[b].world.inverse();

    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const VrmlNode& node = scene.nodes[i];
        if (node.meshes.empty()) continue;
        const int body = current[i];
        if (body < 0) {
            const Eigen::Vector3d p = scale * node.world.translation();
            result.issues.push_back({MatchIssue::unmatched, int(i),
                                     describe_node(node) + " holds " + std::to_string(node.meshes.size()) +
                                         " shape(s) at " + format_point(p) +
                                         " but neither it nor any node above it lies on a body's part frame (CS1)"});
            continue;
        }
        // VRML local -> world (VRML units) -> world (model units) -> body.
        Eigen::Affine3d to_model = node.world;
        to_model.linear() *= scale;
        to_model.translation() *= scale;
        const Eigen::Affine3d to_body = body_from_world[size_t(body)] * to_model;
        for (const VrmlMesh& mesh : node.meshes) {
            MatchedMesh m;
            m.body = body;
            m.node = int(i);
            m.name = mesh_name(mesh, node);
            m.vertices.resize(mesh.vertices.size());
            for (size_t v = 0; v + 2 < mesh.vertices.size(); v += 3) {
                const Eigen::Vector3d p =
                    to_body * Eigen::Vector3d(mesh.vertices[v], mesh.vertices[v + 1], mesh.vertices[v + 2]);
                m.vertices[v] = p.x();
                m.vertices[v + 1] = p.y();
                m.vertices[v + 2] = p.z();
            }
            m.triangles = mesh.triangles;
            result.meshes.push_back(std::move(m));
        }
    }
    return result;
}

}  // namespace mbx_files
