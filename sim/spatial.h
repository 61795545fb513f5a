// Spatial (6D) algebra for the dynamics core, templated on the scalar so that
// Ceres' Jet runs through every algorithm. Conventions (Featherstone):
// motion vectors [angular; linear], force vectors [moment; force], both in
// the coordinates of some frame and referred to its origin.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <type_traits>

namespace mbx::sim {

template <class S> using Vec3T = Eigen::Matrix<S, 3, 1>;
template <class S> using Mat3T = Eigen::Matrix<S, 3, 3>;
template <class S> using Vec6T = Eigen::Matrix<S, 6, 1>;
template <class S> using Mat6T = Eigen::Matrix<S, 6, 6>;
template <class S> using QuatT = Eigen::Quaternion<S>;
template <class S> using VecXT = Eigen::Matrix<S, Eigen::Dynamic, 1>;
template <class S> using MatXT = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
// A joint's motion subspace: 6 x (1, 3 or 6) without heap allocation.
template <class S> using SubspaceT = Eigen::Matrix<S, 6, Eigen::Dynamic, Eigen::ColMajor, 6, 6>;

// The plain value of a scalar: itself for double, the real part of a Ceres
// Jet (its member `a`), for decisions and diagnostics that carry no derivative.
template <class S> double value_of(const S& x) {
    if constexpr (std::is_arithmetic_v<S>)
        return double(x);
    else
        return value_of(x.a);
}

template <class S> Mat3T<S> skew(const Vec3T<S>& v) {
    Mat3T<S> m;
    m << S(0), -v.z(), v.y(), v.z(), S(0), -v.x(), -v.y(), v.x(), S(0);
    return m;
}

// Pose of frame B in frame A (B's axes as columns in A, B's origin in A), and
// the transforms of spatial vectors between the two frames it implies.
template <class S> struct Transform {
    Mat3T<S> R = Mat3T<S>::Identity();
    Vec3T<S> p = Vec3T<S>::Zero();

    Transform operator*(const Transform& o) const { return {R * o.R, R * o.p + p}; }
    Transform inverse() const {
        Mat3T<S> rt = R.transpose();
        return {rt, -(rt * p)};
    }
    Vec3T<S> apply(const Vec3T<S>& x) const { return R * x + p; }

    // Motion in A coordinates -> B coordinates.
    Vec6T<S> motion_to_child(const Vec6T<S>& m) const {
        const Vec3T<S> w = m.template head<3>();
        Vec6T<S> r;
        r.template head<3>() = R.transpose() * w;
        r.template tail<3>() = R.transpose() * (m.template tail<3>() - p.cross(w));
        return r;
    }
    // Motion in B coordinates -> A coordinates.
    Vec6T<S> motion_to_parent(const Vec6T<S>& m) const {
        const Vec3T<S> w = R * m.template head<3>();
        Vec6T<S> r;
        r.template head<3>() = w;
        r.template tail<3>() = R * m.template tail<3>() + p.cross(w);
        return r;
    }
    // Force in B coordinates -> A coordinates.
    Vec6T<S> force_to_parent(const Vec6T<S>& f) const {
        const Vec3T<S> lin = R * f.template tail<3>();
        Vec6T<S> r;
        r.template head<3>() = R * f.template head<3>() + p.cross(lin);
        r.template tail<3>() = lin;
        return r;
    }
    // Force in A coordinates -> B coordinates.
    Vec6T<S> force_to_child(const Vec6T<S>& f) const {
        Vec6T<S> r;
        r.template head<3>() = R.transpose() * (f.template head<3>() - p.cross(f.template tail<3>()));
        r.template tail<3>() = R.transpose() * f.template tail<3>();
        return r;
    }
    // The 6x6 matrix of motion_to_child (Featherstone's X from A to B).
    Mat6T<S> motion_matrix_to_child() const {
        Mat6T<S> X;
        const Mat3T<S> rt = R.transpose();
        X.template topLeftCorner<3, 3>() = rt;
        X.template topRightCorner<3, 3>().setZero();
        X.template bottomLeftCorner<3, 3>() = -rt * skew<S>(p);
        X.template bottomRightCorner<3, 3>() = rt;
        return X;
    }

    template <class T> Transform<T> cast() const { return {R.template cast<T>(), p.template cast<T>()}; }
};

// Motion cross product v x m.
template <class S> Vec6T<S> cross_motion(const Vec6T<S>& v, const Vec6T<S>& m) {
    const Vec3T<S> w = v.template head<3>(), u = v.template tail<3>();
    Vec6T<S> r;
    r.template head<3>() = w.cross(m.template head<3>());
    r.template tail<3>() = w.cross(m.template tail<3>()) + u.cross(m.template head<3>());
    return r;
}

// Force cross product v x* f.
template <class S> Vec6T<S> cross_force(const Vec6T<S>& v, const Vec6T<S>& f) {
    const Vec3T<S> w = v.template head<3>(), u = v.template tail<3>();
    Vec6T<S> r;
    r.template head<3>() = w.cross(f.template head<3>()) + u.cross(f.template tail<3>());
    r.template tail<3>() = w.cross(f.template tail<3>());
    return r;
}

// Rigid-body inertia in a body frame: mass, first moment h = m c and the
// rotational inertia about the frame origin (not the centre of mass), the
// form in which products with motion vectors cost the least.
template <class S> struct Inertia {
    S mass = S(0);
    Vec3T<S> h = Vec3T<S>::Zero();
    Mat3T<S> I = Mat3T<S>::Zero();  // about the origin

    static Inertia from_com(const S& m, const Vec3T<S>& com, const Mat3T<S>& inertia_about_com) {
        Inertia r;
        r.mass = m;
        r.h = m * com;
        r.I = inertia_about_com + m * (com.dot(com) * Mat3T<S>::Identity() - com * com.transpose());
        return r;
    }

    Vec6T<S> operator*(const Vec6T<S>& v) const {
        const Vec3T<S> w = v.template head<3>(), u = v.template tail<3>();
        Vec6T<S> f;
        f.template head<3>() = I * w + h.cross(u);
        f.template tail<3>() = mass * u - h.cross(w);
        return f;
    }
    Mat6T<S> matrix() const {
        Mat6T<S> M;
        const Mat3T<S> hx = skew<S>(h);
        M.template topLeftCorner<3, 3>() = I;
        M.template topRightCorner<3, 3>() = hx;
        M.template bottomLeftCorner<3, 3>() = -hx;
        M.template bottomRightCorner<3, 3>() = mass * Mat3T<S>::Identity();
        return M;
    }
    // The same inertia expressed in the parent frame A of transform X (pose of this frame in A).
    Inertia to_parent(const Transform<S>& X) const {
        Inertia r;
        r.mass = mass;
        const Vec3T<S> hr = X.R * h;
        r.h = hr + mass * X.p;
        // I_A = R I R^T - [p]x [R h]x - [R h + m p]x [p]x  (parallel axis for a shifted origin)
        const Mat3T<S> px = skew<S>(X.p);
        const Mat3T<S> RI = X.R.lazyProduct(I);  // fixed-size lazy products: no generic kernel
        r.I = RI.lazyProduct(X.R.transpose()) - px.lazyProduct(skew<S>(hr)) - skew<S>(r.h).lazyProduct(px);
        return r;
    }
    Inertia& operator+=(const Inertia& o) {
        mass += o.mass;
        h += o.h;
        I += o.I;
        return *this;
    }
    template <class T> Inertia<T> cast() const {
        Inertia<T> r;
        r.mass = T(mass);
        r.h = h.template cast<T>();
        r.I = I.template cast<T>();
        return r;
    }
};

// Rotation of a unit quaternion by the rotation vector w dt applied in its
// own (moving) frame: q (x) exp(w dt / 2). Exact for constant body rates.
template <class S> QuatT<S> quat_integrate_local(const QuatT<S>& q, const Vec3T<S>& w, const S& dt) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Vec3T<S> phi = w * dt;
    const S angle2 = phi.squaredNorm();
    QuatT<S> dq;
    if (angle2 < S(1e-16)) {
        // Series of cos(a/2) and sin(a/2)/a: exact to double precision for tiny angles.
        dq.w() = S(1) - angle2 / S(8);
        dq.vec() = phi * (S(0.5) - angle2 / S(48));
    } else {
        const S angle = sqrt(angle2);
        dq.w() = cos(angle / S(2));
        dq.vec() = phi * (sin(angle / S(2)) / angle);
    }
    QuatT<S> r = q * dq;
    r.normalize();
    return r;
}

// Rotation vector of a rotation matrix (log map), stable near 0 and pi.
template <class S> Vec3T<S> rotation_vector(const Mat3T<S>& R) {
    using std::atan2;
    using std::sqrt;
    const Vec3T<S> axis_sin(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));  // 2 sin(a) n
    const S s2 = axis_sin.norm();                                                     // 2 sin a
    const S c2 = R.trace() - S(1);                                                    // 2 cos a
    const S angle = atan2(s2, c2);
    if (s2 < S(1e-7)) {
        if (c2 > S(0)) return axis_sin * (S(0.5) + angle * angle / S(12));  // a / (2 sin a) ~ 1/2 + a^2/12
        // Near pi: the axis from the symmetric part.
        Eigen::AngleAxis<S> aa(R);
        return aa.axis() * aa.angle();
    }
    return axis_sin * (angle / s2);
}

}  // namespace mbx::sim
