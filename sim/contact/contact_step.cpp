#include "sim/contact/contact_step.h"

#include <algorithm>

#include "sim/dynamics.h"

namespace mbx::sim::contact {

void add_point_force(const Model& m, const Data& d, int body, const Eigen::Vector3d& p, const Eigen::Vector3d& f,
                     Eigen::VectorXd& tau) {
    // Column k of the point Jacobian is [w; v + w x p]: its power with f is v.f + w.(p x f).
    const Eigen::Vector3d moment = p.cross(f);
    for (int b = body; b > 0; b = m.bodies[size_t(b)].parent) {
        const JointT<double>& j = m.joints[size_t(b - 1)];
        for (int k = 0; k < j.nv(); ++k) {
            const Vec6T<double> w = d.x_world[size_t(b)].motion_to_parent(Vec6T<double>(d.subspace[size_t(b)].col(k)));
            tau[j.v_index + k] += w.tail<3>().dot(f) + w.head<3>().dot(moment);
        }
    }
}

ContactWorld::ContactWorld(const Model& m, std::vector<Shape> shapes, ContactSettings settings,
                           std::vector<MaterialPair> pairs)
    : scene_(m, std::move(shapes)), settings_(settings), any_spring_(settings.friction_spring) {
    for (const MaterialPair& p : pairs) {
        pairs_[{std::min(p.a, p.b), std::max(p.a, p.b)}] = p.settings;
        any_spring_ = any_spring_ || p.settings.friction_spring;
    }
}

const ContactSettings& ContactWorld::settings_for(int shape_a, int shape_b) const {
    if (pairs_.empty()) return settings_;
    const int a = scene_.shapes()[size_t(shape_a)].material, b = scene_.shapes()[size_t(shape_b)].material;
    const auto it = pairs_.find({std::min(a, b), std::max(a, b)});
    return it == pairs_.end() ? settings_ : it->second;
}

void ContactWorld::evaluate(const Model& m, const Data& d, Eigen::VectorXd& tau, std::map<Key, FrictionState>* next_anchors) {
    scene_.detect(d, contacts_);
    forces_.clear();
    for (const Contact& c : contacts_) {
        const int ba = scene_.shapes()[size_t(c.shape_a)].body, bb = scene_.shapes()[size_t(c.shape_b)].body;
        // Velocity of b's material point relative to a's, at the contact.
        const Eigen::Vector3d v_rel = point_velocity(d, bb, c.point).tail<3>() - point_velocity(d, ba, c.point).tail<3>();
        const double depth_rate = -c.normal.dot(v_rel);
        const ContactSettings& settings = settings_for(c.shape_a, c.shape_b);
        ContactForce cf;
        cf.contact = c;
        cf.normal_force = normal_force(settings.normal, c.depth, depth_rate);
        const Eigen::Vector3d v_t = v_rel - c.normal * c.normal.dot(v_rel);
        if (settings.friction_spring) {
            const Key key{c.shape_a, c.shape_b, c.feature};
            const auto it = anchors_.find(key);
            // The anchor rides on one side, the carrier (the world when one
            // side is the world, else a), and is kept in its frame: a box on
            // a moving platform stays tied to the spot it sits on. The spring
            // stretches with the other side's point; when that is a, its
            // force on b is the reverse.
            const bool a_moves = ba != 0 && bb == 0;
            const Transform<double>& carrier = d.x_world[size_t(a_moves ? bb : ba)];
            FrictionState last = it == anchors_.end() ? FrictionState{} : it->second;
            last.anchor = carrier.apply(last.anchor);
            FrictionState next;
            const Eigen::Vector3d f_mover = spring_friction(settings.friction, last, c.point, c.normal,
                                                            a_moves ? Eigen::Vector3d(-v_t) : v_t, cf.normal_force, next);
            cf.friction = a_moves ? Eigen::Vector3d(-f_mover) : f_mover;
            cf.sticking = next.sticking;
            next.anchor = carrier.R.transpose() * (next.anchor - carrier.p);
            if (next_anchors && next.active) (*next_anchors)[key] = next;
        } else {
            cf.friction = regularised_friction(settings.friction, cf.normal_force, v_t, settings.smoothing_speed);
        }
        const Eigen::Vector3d f = cf.normal_force * c.normal + cf.friction;  // onto b
        add_point_force(m, d, bb, c.point, f, tau);
        add_point_force(m, d, ba, c.point, -f, tau);
        forces_.push_back(cf);
    }
}

void ContactWorld::apply(const Model& m, Data& d) {
    if (cached_ && d.time == cached_time_ && d.q == cached_q_ && d.v == cached_v_) {
        d.qfrc_applied += cached_tau_;
        return;
    }
    evaluate(m, d, d.qfrc_applied, nullptr);
}

void ContactWorld::step_taken(const Model& m, Data& d) {
    // The anchors move with the kept step's end state. The forces there are
    // the same with the old anchors and the new ones (the new are the old
    // ones' own update at this state), so they serve the next evaluation.
    std::map<Key, FrictionState> next;
    cached_tau_.setZero(m.nv);
    evaluate(m, d, cached_tau_, any_spring_ ? &next : nullptr);
    if (any_spring_) anchors_ = std::move(next);
    cached_ = true, cached_time_ = d.time, cached_q_ = d.q, cached_v_ = d.v;
}

ContactWorld::Memory ContactWorld::memory() const {
    return {anchors_, cached_, cached_time_, cached_q_, cached_v_, cached_tau_};
}

void ContactWorld::restore(const Memory& m) {
    anchors_ = m.anchors;
    cached_ = m.cached, cached_time_ = m.cached_time;
    cached_q_ = m.cached_q, cached_v_ = m.cached_v, cached_tau_ = m.cached_tau;
}

void ContactWorld::step(const Model& m, Data& d, const IntegratorSettings& s) {
    AppliedForces* before = d.applied_forces;
    d.applied_forces = this;
    try {
        fixed_step(m, d, s);
    } catch (...) {
        d.applied_forces = before;
        throw;
    }
    d.applied_forces = before;
}

}  // namespace mbx::sim::contact
