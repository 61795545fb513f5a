#include "sim/contact/detection.h"

#include <fcl/fcl.h>

#include <algorithm>
#include <cmath>

#include "core/finding.h"
#include "sim/dynamics.h"

namespace mbx::sim::contact {

namespace {

std::shared_ptr<fcl::CollisionGeometryd> geometry(const Shape& s) {
    switch (s.kind) {
    case ShapeKind::Sphere: return std::make_shared<fcl::Sphered>(s.radius);
    case ShapeKind::Box: return std::make_shared<fcl::Boxd>(s.size.x(), s.size.y(), s.size.z());
    case ShapeKind::Cylinder: return std::make_shared<fcl::Cylinderd>(s.radius, s.length);
    case ShapeKind::Capsule: return std::make_shared<fcl::Capsuled>(s.radius, s.length);
    case ShapeKind::HalfSpace: return std::make_shared<fcl::Halfspaced>(Eigen::Vector3d::UnitZ(), 0.0);
    case ShapeKind::Convex: {
        auto vertices = std::make_shared<const std::vector<Eigen::Vector3d>>(s.hull->vertices);
        auto faces = std::make_shared<const std::vector<int>>(s.hull->faces);
        return std::make_shared<fcl::Convexd>(vertices, s.hull->face_count, faces);
    }
    }
    return nullptr;
}

[[noreturn]] void bad_shape(const Shape& s, const std::string& what) {
    throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(s.name), "collision shape '" + s.name + "': " + what);
}

void check(const Shape& s, int body_count) {
    if (s.body < 0 || s.body >= body_count) bad_shape(s, "its body " + std::to_string(s.body) + " is not in the model");
    if (!s.position.allFinite() || !s.rotation.allFinite()) bad_shape(s, "its pose is not finite");
    auto positive = [&](double v, const char* what) {
        if (!(std::isfinite(v) && v > 0)) bad_shape(s, std::string(what) + " must be a positive number");
    };
    switch (s.kind) {
    case ShapeKind::Sphere: positive(s.radius, "radius"); break;
    case ShapeKind::Box:
        for (int k = 0; k < 3; ++k) positive(s.size[k], "every side of a box");
        break;
    case ShapeKind::Cylinder:
    case ShapeKind::Capsule:
        positive(s.radius, "radius");
        positive(s.length, "length");
        break;
    case ShapeKind::HalfSpace: break;
    case ShapeKind::Convex:
        if (!s.hull || s.hull->vertices.size() < 4 || s.hull->face_count < 4)
            bad_shape(s, "a convex shape needs at least 4 vertices and 4 faces");
        for (const Eigen::Vector3d& v : s.hull->vertices)
            if (!v.allFinite()) bad_shape(s, "a hull vertex is not finite");
        break;
    }
}

}  // namespace

struct Scene::Impl {
    std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;  // per shape
    std::vector<int> planes;                                      // half-space shapes (outside the tree)
    fcl::DynamicAABBTreeCollisionManagerd tree;
    bool set_up = false;
};

Scene::Scene(const Model& m, std::vector<Shape> shapes) : impl_(std::make_unique<Impl>()), shapes_(std::move(shapes)) {
    body_count_ = m.body_count();
    joined_.assign(size_t(body_count_) * size_t(body_count_), 0);
    for (int b = 1; b < body_count_; ++b) {
        const int p = m.bodies[size_t(b)].parent;
        // A floating body's free joint ties it to nothing: it collides with the
        // world. So does a body jointed to the world: the world holds the
        // environment (ground, obstacles, end stops) as well as the ground
        // part, and MuJoCo filters parent and child the same way (a joint's
        // own seat on the ground is kept apart with groups and masks).
        if (p <= 0 || m.joints[size_t(b - 1)].kind == JointKind::Free) continue;
        joined_[size_t(b) * size_t(body_count_) + size_t(p)] = joined_[size_t(p) * size_t(body_count_) + size_t(b)] = 1;
    }
    // A joint cut to close a loop joins its two bodies as much as a tree
    // joint does: their shapes overlap at the joint by construction.
    for (const LoopClosureT<double>& c : m.closures)
        if (c.body_a > 0 && c.body_b > 0 && c.body_a < body_count_ && c.body_b < body_count_)
            joined_[size_t(c.body_a) * size_t(body_count_) + size_t(c.body_b)] =
                joined_[size_t(c.body_b) * size_t(body_count_) + size_t(c.body_a)] = 1;
    for (size_t i = 0; i < shapes_.size(); ++i) {
        check(shapes_[i], body_count_);
        auto o = std::make_unique<fcl::CollisionObjectd>(geometry(shapes_[i]));
        o->setUserData(reinterpret_cast<void*>(i));
        if (shapes_[i].kind == ShapeKind::HalfSpace) impl_->planes.push_back(int(i));
        impl_->objects.push_back(std::move(o));
    }
    bool skipping = false;
    for (const Shape& s : shapes_) skipping |= s.skip_if_overlapping_at_reference;
    if (skipping) {
        Data reference(m);  // at m.q_reference: the CAD configuration
        update_positions(m, reference);
        std::vector<Contact> found;
        detect(reference, found);
        for (const Contact& c : found)
            if (shapes_[size_t(c.shape_a)].skip_if_overlapping_at_reference &&
                shapes_[size_t(c.shape_b)].skip_if_overlapping_at_reference)
                skipped_.push_back({std::min(c.shape_a, c.shape_b), std::max(c.shape_a, c.shape_b)});
        std::sort(skipped_.begin(), skipped_.end());
        skipped_.erase(std::unique(skipped_.begin(), skipped_.end()), skipped_.end());
        stats_ = DetectionStats{};
    }
}

Scene::~Scene() = default;

bool Scene::collides(int a, int b) const {
    const Shape& sa = shapes_[size_t(a)];
    const Shape& sb = shapes_[size_t(b)];
    if (sa.body == sb.body) return false;
    if (!skipped_.empty() && sa.skip_if_overlapping_at_reference && sb.skip_if_overlapping_at_reference &&
        std::binary_search(skipped_.begin(), skipped_.end(), std::pair<int, int>(std::min(a, b), std::max(a, b))))
        return false;
    if (joined_[size_t(sa.body) * size_t(body_count_) + size_t(sb.body)]) return false;
    return (sa.group & sb.mask) && (sb.group & sa.mask);
}

void Scene::narrowphase(int a, int b, std::vector<Contact>& out) {
    ++stats_.candidate_pairs;
    const Shape& sa = shapes_[size_t(a)];
    const Shape& sb = shapes_[size_t(b)];
    // A box or a convex hull on a half-space: every corner (hull vertex)
    // below the plane, not only FCL's deepest one.
    const auto polytope = [](const Shape& s) { return s.kind == ShapeKind::Box || s.kind == ShapeKind::Convex; };
    if ((polytope(sa) && sb.kind == ShapeKind::HalfSpace) || (sa.kind == ShapeKind::HalfSpace && polytope(sb))) {
        const bool solid_first = sa.kind != ShapeKind::HalfSpace;
        const Shape& solid = solid_first ? sa : sb;
        const fcl::Transform3d& xb = impl_->objects[size_t(solid_first ? a : b)]->getTransform();
        const fcl::Transform3d& xh = impl_->objects[size_t(solid_first ? b : a)]->getTransform();
        const Eigen::Vector3d n = xh.linear().col(2);
        const double offset = n.dot(xh.translation());
        const Eigen::Vector3d half = 0.5 * solid.size;
        const int count = solid.kind == ShapeKind::Box ? 8 : int(solid.hull->vertices.size());
        for (int k = 0; k < count; ++k) {
            const Eigen::Vector3d local =
                solid.kind == ShapeKind::Box
                    ? Eigen::Vector3d((k & 1 ? 1 : -1) * half.x(), (k & 2 ? 1 : -1) * half.y(), (k & 4 ? 1 : -1) * half.z())
                    : solid.hull->vertices[size_t(k)];
            const Eigen::Vector3d corner = xb * local;
            const double distance = n.dot(corner) - offset;
            if (distance >= 0) continue;
            // From a into b: into the plane's solid when the polytope is a, out of it otherwise.
            out.push_back({a, b, corner, solid_first ? Eigen::Vector3d(-n) : n, -distance, k});
        }
        return;
    }
    try {
        fcl::CollisionRequestd request(4, true);
        fcl::CollisionResultd result;
        fcl::collide(impl_->objects[size_t(a)].get(), impl_->objects[size_t(b)].get(), request, result);
        std::vector<fcl::Contactd> found;
        result.getContacts(found);
        int feature = 0;
        for (const fcl::Contactd& c : found) {
            // FCL's contact may name the objects in the other order.
            const bool swapped = c.o1 != impl_->objects[size_t(a)]->collisionGeometry().get();
            Eigen::Vector3d normal = swapped ? Eigen::Vector3d(-c.normal) : c.normal;
            const double length = normal.norm();
            if (!(c.pos.allFinite() && std::isfinite(c.penetration_depth) && length > 0.5 && length < 2)) {
                ++stats_.failed_pairs;
                continue;
            }
            out.push_back({a, b, c.pos, normal / length, c.penetration_depth, feature++});
        }
    } catch (const std::exception&) {
        ++stats_.failed_pairs;  // FCL's EPA can throw on degenerate simplices
    }
}

void Scene::detect(const Data& d, std::vector<Contact>& out) {
    out.clear();
    stats_ = DetectionStats{};
    for (size_t i = 0; i < shapes_.size(); ++i) {
        const Shape& s = shapes_[i];
        const Transform<double>& x = d.x_world[size_t(s.body)];
        fcl::Transform3d t = fcl::Transform3d::Identity();
        t.linear() = x.R * s.rotation;
        t.translation() = x.R * s.position + x.p;
        impl_->objects[i]->setTransform(t);
        impl_->objects[i]->computeAABB();
    }
    if (!impl_->set_up) {
        std::vector<fcl::CollisionObjectd*> in_tree;
        for (size_t i = 0; i < shapes_.size(); ++i)
            if (shapes_[i].kind != ShapeKind::HalfSpace) in_tree.push_back(impl_->objects[i].get());
        impl_->tree.registerObjects(in_tree);
        impl_->tree.setup();
        impl_->set_up = true;
    } else {
        impl_->tree.update();
    }
    struct Pass {
        Scene* scene;
        std::vector<Contact>* out;
    } pass{this, &out};
    impl_->tree.collide(&pass, [](fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
        Pass& p = *static_cast<Pass*>(data);
        int a = int(reinterpret_cast<size_t>(o1->getUserData())), b = int(reinterpret_cast<size_t>(o2->getUserData()));
        if (a > b) std::swap(a, b);  // a stable order, whatever the tree's
        if (p.scene->collides(a, b)) p.scene->narrowphase(a, b, *p.out);
        return false;
    });
    // Half-spaces are unbounded: tested against every other shape directly.
    for (int h : impl_->planes)
        for (size_t i = 0; i < shapes_.size(); ++i) {
            if (int(i) == h || shapes_[i].kind == ShapeKind::HalfSpace || !collides(h, int(i))) continue;
            narrowphase(h, int(i), out);  // the plane first: contacts push the other shape along +normal
        }
}

}  // namespace mbx::sim::contact
