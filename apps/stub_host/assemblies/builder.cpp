#include "builder.h"

#include <cmath>
#include <stdexcept>

namespace mbx_stub {
namespace build {

mbx_pose make_pose(const Mat3& rotation, const Vec3& position) {
    mbx_pose pose{};
    for (int i = 0; i < 3; ++i) {
        pose.position[i] = position[i];
        for (int j = 0; j < 3; ++j) pose.rotation[3 * i + j] = rotation(i, j);  // row-major
    }
    return pose;
}

Mat3 rotation_of(const mbx_pose& pose) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = pose.rotation[3 * i + j];
    return r;
}

Vec3 position_of(const mbx_pose& pose) { return Vec3(pose.position[0], pose.position[1], pose.position[2]); }

Mat3 axis_angle(const Vec3& axis, double angle) {
    return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Mat3 rotation_x_to(const Vec3& x, const Vec3& y_hint) {
    const Vec3 ex = x.normalized();
    const Vec3 ez = ex.cross(y_hint).normalized();
    Mat3 r;
    r.col(0) = ex;
    r.col(1) = ez.cross(ex);
    r.col(2) = ez;
    return r;
}

Mat3 rotation_z_to(const Vec3& z, double twist) {
    const Vec3 ez = z.normalized();
    const Vec3 hint = std::abs(ez.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 ex = (hint - hint.dot(ez) * ez).normalized();
    Mat3 r;
    r.col(0) = ex;
    r.col(1) = ez.cross(ex);
    r.col(2) = ez;
    return r * axis_angle(Vec3::UnitZ(), twist);
}

Mat3 box_inertia(double mass, double a, double b, double c) {
    Mat3 i = Mat3::Zero();
    i(0, 0) = mass / 12.0 * (b * b + c * c);
    i(1, 1) = mass / 12.0 * (a * a + c * c);
    i(2, 2) = mass / 12.0 * (a * a + b * b);
    return i;
}

Mesh box_mesh(const std::string& name, const Vec3& size, const Mat3& rotation, const Vec3& centre) {
    Mesh m;
    m.name = name;
    m.pose = make_pose(rotation, centre);
    const Vec3 h = size / 2.0;
    for (int k = 0; k < 8; ++k) {
        m.vertices.push_back(k & 1 ? h.x() : -h.x());
        m.vertices.push_back(k & 2 ? h.y() : -h.y());
        m.vertices.push_back(k & 4 ? h.z() : -h.z());
    }
    // Two outward triangles per face; vertex k has bit 0 = +x, bit 1 = +y, bit 2 = +z.
    static const uint32_t faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                          {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& f : faces) m.triangles.insert(m.triangles.end(), f, f + 3);
    return m;
}

double length_factor(const mbx_units& u) { return u.length_to_m != 0 ? u.length_to_m : 1.0; }
double mass_factor(const mbx_units& u) { return u.mass_to_kg != 0 ? u.mass_to_kg : 1.0; }
double inertia_factor(const mbx_units& u) {
    if (u.inertia_to_kg_m2 != 0) return u.inertia_to_kg_m2;
    return mass_factor(u) * length_factor(u) * length_factor(u);
}

Prim revolute(const Vec3& axis, mbx_axis_reference reference) {
    Prim p;
    p.type = MBX_PRIMITIVE_REVOLUTE;
    p.axis = axis.normalized();
    p.reference = reference;
    return p;
}

Prim revolute(const Vec3& axis, mbx_axis_reference reference, double lower, double upper) {
    Prim p = revolute(axis, reference);
    p.has_limits = true;
    p.lower = lower;
    p.upper = upper;
    return p;
}

Prim spherical() {
    Prim p;
    p.type = MBX_PRIMITIVE_SPHERICAL;
    return p;
}

Prim weld() {
    Prim p;
    p.type = MBX_PRIMITIVE_WELD;
    return p;
}

Builder::Builder(Assembly& out, std::string prefix, mbx_units body_units, mbx_units frame_units)
    : out_(out), prefix_(std::move(prefix)), body_units_(body_units), frame_units_(frame_units) {
    for (size_t i = 0; i < out_.bodies.size(); ++i) body_index_[out_.bodies[i].id] = i;
}

Body& Builder::body(const std::string& local, const std::string& name, uint32_t flags, double mass,
                    const Mat3& rotation, const Vec3& position, const Vec3& com_world, const Mat3& inertia_body) {
    const double lf = length_factor(body_units_);
    Body b;
    b.id = id(local);
    b.name = name;
    b.flags = flags;
    b.units = body_units_;
    b.mass = mass / mass_factor(body_units_);
    const Vec3 com_body = rotation.transpose() * (com_world - position) / lf;
    const Mat3 inertia = inertia_body / inertia_factor(body_units_);
    for (int i = 0; i < 3; ++i) {
        b.com[i] = com_body[i];
        for (int j = 0; j < 3; ++j) b.inertia[3 * i + j] = inertia(i, j);
    }
    b.pose = make_pose(rotation, position / lf);
    if (!body_index_.emplace(b.id, out_.bodies.size()).second) throw std::logic_error("duplicate body " + b.id);
    out_.bodies.push_back(std::move(b));
    return out_.bodies.back();
}

const Body& Builder::find(const std::string& local) const {
    auto it = body_index_.find(id(local));
    if (it == body_index_.end()) throw std::logic_error("unknown body " + id(local));
    return out_.bodies[it->second];
}

Mat3 Builder::body_rotation(const std::string& local) const { return rotation_of(find(local).pose); }

Vec3 Builder::body_position(const std::string& local) const {
    const Body& b = find(local);
    return position_of(b.pose) * length_factor(b.units);
}

Frame& Builder::frame(const std::string& local, const std::string& body_local, const Mat3& rotation, const Vec3& at,
                      mbx_frame_reference reference) {
    const double lf = length_factor(frame_units_);
    Frame f;
    f.id = id(local);
    f.name = local;
    f.body_id = id(body_local);
    f.reference = reference;
    f.units = frame_units_;
    if (reference == MBX_FRAME_IN_WORLD) {
        f.pose = make_pose(rotation, at / lf);
    } else {
        const Mat3 rb = body_rotation(body_local);
        const Vec3 pb = body_position(body_local);
        f.pose = make_pose(rb.transpose() * rotation, rb.transpose() * (at - pb) / lf);
    }
    out_.frames.push_back(std::move(f));
    return out_.frames.back();
}

Constraint& Builder::joint(const std::string& local, const std::string& base_body, const std::string& follower_body,
                           const Vec3& at, const Mat3& frame_rotation, const std::vector<Prim>& chain,
                           mbx_frame_reference base_reference, mbx_frame_reference follower_reference) {
    Constraint c;
    c.id = id(local);
    c.name = local;
    c.base_frame_id = frame(local + "/base", base_body, frame_rotation, at, base_reference).id;
    c.follower_frame_id = frame(local + "/follower", follower_body, frame_rotation, at, follower_reference).id;
    for (const Prim& p : chain) {
        Primitive q{p.type};
        q.axis_reference = p.reference;
        const Vec3 axis = p.reference == MBX_AXIS_IN_WORLD ? p.axis : Vec3(frame_rotation.transpose() * p.axis);
        for (int i = 0; i < 3; ++i) q.axis[i] = axis[i];
        if (p.type == MBX_PRIMITIVE_WELD || p.type == MBX_PRIMITIVE_SPHERICAL) {
            q.axis[0] = q.axis[1] = 0;  // ignored by the SDK; serve what a CAD system would
            q.axis[2] = 1;
        }
        q.has_limits = p.has_limits;
        // mbx.h: prismatic limits are in the length unit of the base frame.
        const double scale = p.type == MBX_PRIMITIVE_PRISMATIC ? length_factor(frame_units_) : 1.0;
        q.lower = p.lower / scale;
        q.upper = p.upper / scale;
        c.chain.push_back(q);
    }
    out_.constraints.push_back(std::move(c));
    return out_.constraints.back();
}

void Builder::mesh(const std::string& body_local, Mesh m) {
    const double lf = length_factor(find(body_local).units);
    for (double& v : m.vertices) v /= lf;
    for (double& p : m.pose.position) p /= lf;
    out_.shapes[id(body_local)].push_back(std::move(m));
}

}  // namespace build
}  // namespace mbx_stub
