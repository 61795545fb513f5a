#include "sdk/capi/contact_build.h"

#include <algorithm>
#include <limits>

#include "core/assembly/shape_loader.h"
#include "sdk/capi/handles.h"
#include "sim/contact/convex_hull.h"

namespace mbx {

namespace sc = sim::contact;

sc::ContactSettings contact_settings(const ContactMaterialSpec& spec, double mass) {
    sc::ContactSettings s;
    s.normal.model = spec.normal == ContactNormalLaw::HuntCrossley   ? sc::NormalModel::HuntCrossley
                     : spec.normal == ContactNormalLaw::SpringDamper ? sc::NormalModel::SpringDamper
                                                                     : sc::NormalModel::Spring;
    s.normal.stiffness = spec.stiffness;
    s.normal.exponent = spec.exponent;
    s.normal.damping = spec.damping;
    if (spec.use_restitution && spec.normal != ContactNormalLaw::Spring)
        s.normal.damping = sc::damping_for_restitution(s.normal, mass, spec.impact_speed, spec.restitution);
    s.friction.mu_static = spec.mu_static;
    s.friction.mu_kinetic = spec.mu_kinetic;
    s.friction.stiffness = spec.friction_stiffness;
    s.friction.damping = spec.friction_damping;
    s.friction.stick_speed = spec.stick_speed;
    s.friction_spring = spec.friction == ContactFrictionLaw::Spring;
    s.smoothing_speed = spec.smoothing_speed;
    return s;
}

void build_contact(const mbx_mechanism& mechanism, mbx_sim_model& model) {
    const ResolvedContact& rc = mechanism.contact;
    model.shapes.clear();
    model.contact_pairs.clear();
    model.contact_default = {};
    if (rc.empty()) return;
    const Mechanism& mech = *mechanism.model;
    const sim::Model& sm = model.model;
    const Pose ground = mech.bodies.empty() ? Pose{} : mech.bodies[0].pose;
    std::vector<std::vector<Mesh>> meshes(mech.bodies.size());
    std::vector<bool> loaded(mech.bodies.size(), false);
    for (size_t i = 0; i < rc.shapes.size(); ++i) {
        const ResolvedCollision& r = rc.shapes[i];
        sc::Shape s;
        s.name = r.name;
        s.material = rc.shape_material[i];
        s.group = r.spec.group, s.mask = r.spec.mask;
        // The ground's shapes ride on the simulation's world, whose frame is
        // the world's, not the ground part's.
        s.body = sm.body_of_source[size_t(r.body)];
        if (s.body < 0)
            throw Error(MBX_ERROR_INVALID_INPUT, Subject::body(r.spec.body, r.name),
                        "collision shape '" + r.name + "': its body is not in the simulation model");
        const Pose pose = r.body == 0 ? ground * r.pose : r.pose;
        s.rotation = pose.rotation, s.position = pose.position;
        switch (r.spec.kind) {
        case CollisionKind::Sphere: s.kind = sc::ShapeKind::Sphere, s.radius = r.spec.radius; break;
        case CollisionKind::Box: s.kind = sc::ShapeKind::Box, s.size = r.spec.size; break;
        case CollisionKind::Cylinder: s.kind = sc::ShapeKind::Cylinder, s.radius = r.spec.radius, s.length = r.spec.length; break;
        case CollisionKind::Capsule: s.kind = sc::ShapeKind::Capsule, s.radius = r.spec.radius, s.length = r.spec.length; break;
        case CollisionKind::Plane: s.kind = sc::ShapeKind::HalfSpace; break;
        case CollisionKind::Hull: {
            s.kind = sc::ShapeKind::Convex;
            const std::string& part_id = mech.assembly.parts[size_t(r.hull_part)].id;
            if (!loaded[size_t(r.body)]) {
                if (!mechanism.has_host)
                    throw Error(MBX_ERROR_INVALID_ARGUMENT, Subject::body(part_id, r.name),
                                "collision shape '" + r.name + "': the host was released, so the part's mesh for its hull cannot be asked for");
                meshes[size_t(r.body)] = load_body_shapes(mechanism.host, *mechanism.model, r.body);
                loaded[size_t(r.body)] = true;
            }
            std::vector<Eigen::Vector3d> points;
            for (const Mesh& mesh : meshes[size_t(r.body)])
                if (mesh.part_id == part_id) points.insert(points.end(), mesh.vertices.begin(), mesh.vertices.end());
            // The default asks for every part; one the CAD gave no mesh
            // simply has no hull (docs/contact.md).
            if (points.empty() && r.from_default) continue;
            if (points.empty())
                throw Error(MBX_ERROR_INVALID_INPUT, Subject::body(part_id, r.name),
                            "collision shape '" + r.name + "': the host gave no mesh for part '" + part_id + "' to wrap in a hull");
            // Mesh vertices are in the body frame; the ground's go to the world's.
            if (r.body == 0)
                for (Eigen::Vector3d& p : points) p = ground.apply(p);
            s.rotation.setIdentity(), s.position.setZero();
            s.hull = std::make_shared<const sc::ConvexHull>(sc::convex_hull(points, r.name));
            s.skip_if_overlapping_at_reference = r.from_default;
            break;
        }
        }
        model.shapes.push_back(std::move(s));
    }
    // The mass a restitution is solved for: the lightest moving body made of
    // either material (Hunt-Crossley's damping does not depend on it).
    auto pair_mass = [&](int a, int b) {
        double mass = std::numeric_limits<double>::infinity();
        for (const sc::Shape& s : model.shapes)
            if (s.body > 0 && (s.material == a || s.material == b) && sm.bodies[size_t(s.body)].inertia.mass > 0)
                mass = std::min(mass, sm.bodies[size_t(s.body)].inertia.mass);
        return std::isfinite(mass) ? mass : 1.0;
    };
    if (rc.default_entry >= 0) {
        double lightest = std::numeric_limits<double>::infinity();
        for (const sc::Shape& s : model.shapes)
            if (s.body > 0) lightest = std::min(lightest, sm.bodies[size_t(s.body)].inertia.mass);
        model.contact_default = contact_settings(rc.entries[size_t(rc.default_entry)], std::isfinite(lightest) ? lightest : 1.0);
    }
    for (const ResolvedContact::Pair& p : rc.pairs)
        model.contact_pairs.push_back({p.a, p.b, contact_settings(rc.entries[size_t(p.entry)], pair_mass(p.a, p.b))});
}

}  // namespace mbx
