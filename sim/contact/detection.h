// Collision detection on the shapes of sim/contact/shape.h with FCL: a
// dynamic AABB tree over every shape, updated from the bodies' world poses
// each call, then narrowphase per candidate pair. FCL reports one point for
// a face contact (a box on a half-space: its deepest corner), on which a
// resting box would rock; box and half-space therefore get a manifold of
// every corner below the plane. Every FCL call is guarded: a failure in its
// solvers drops that pair and is counted, it never escapes.
#pragma once
#include <memory>
#include <utility>
#include <vector>

#include "sim/contact/shape.h"
#include "sim/data.h"

namespace mbx::sim::contact {

struct Contact {
    int shape_a = -1, shape_b = -1;  // indices into the scene's shapes
    Eigen::Vector3d point;           // world, on the deepest penetration
    Eigen::Vector3d normal;          // world, unit, from a into b
    double depth = 0;                // > 0: penetration
    int feature = 0;                 // which point of the pair (a box corner, FCL's k-th): matches contacts across steps
};

struct DetectionStats {
    size_t candidate_pairs = 0;  // from the broadphase, after filtering
    size_t failed_pairs = 0;     // narrowphase threw or returned non-finite data
};

class Scene {
public:
    // Pairs of shapes on bodies joined directly by a joint (parent and child,
    // or the two bodies of a loop's cut joint; a floating body's free joint
    // and a joint to the world do not count, as in MuJoCo) and shapes on the
    // same body never collide, nor do two shapes that skip overlaps at the
    // reference configuration and overlap there (Shape). Throws mbx::Error naming
    // the shape for a non-positive size, a body out of range or an empty hull.
    Scene(const Model& m, std::vector<Shape> shapes);
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    const std::vector<Shape>& shapes() const { return shapes_; }

    // Contacts at data's body poses (data.x_world, as update_positions leaves them).
    void detect(const Data& d, std::vector<Contact>& out);
    const DetectionStats& stats() const { return stats_; }
    // Shape pairs (a < b) left out because they overlap at the reference configuration.
    const std::vector<std::pair<int, int>>& skipped_at_reference() const { return skipped_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::vector<Shape> shapes_;
    std::vector<char> joined_;  // body pair adjacency, body_count^2
    std::vector<std::pair<int, int>> skipped_;  // sorted
    int body_count_ = 0;
    DetectionStats stats_;
    bool collides(int a, int b) const;
    void narrowphase(int a, int b, std::vector<Contact>& out);
};

}  // namespace mbx::sim::contact
