// generate_assembly(n, seed): deterministic pseudo-random mechanisms of
// exactly max(n, 2) parts, for benchmarks and scale tests.
//
// Shape: a ground part and a massless helper "RootPart" welded to it, then
// ceil((n - 2) / 40) branches of about 40 parts, each hanging from ground (even
// branches) or from RootPart (odd ones), so the tree stays wide and shallow
// and every loop is local to its branch. A branch repeats the pattern
//   R, W, R|U, L
// where
//   R  one link on a revolute                       1 part, 1 R,        dof +1
//   U  one link on a universal-joint chain (2R)     1 part, 2 R, 1 node, dof +2
//      (one in four of the third slots)
//   W  a welded cluster: a link on a revolute and 1-2 parts welded to it,
//      each a massless helper with probability 0.3; the next joint hangs
//      from a welded part when one is not a helper
//                                                   2-3 parts, 1 R, 1-2 welds, dof +1
//   L  a loop closed back onto the previous link, its closing constraint
//      last in host order (so it is the cut):
//      P  planar four-bar, axes along one random normal (some flipped):
//         3 parts, 4 R, dof +1, redundant +3, planar
//      S  spatial RSSR (revolute, 2 spherical, revolute, skew axes; the
//         coupler's spin about its S-S line is the second freedom):
//         3 parts, 2 R + 2 S, dof +2, redundant 0
//   (P or S with equal probability.) When the branch's quota has less room
//   than the next slot needs, an R is used instead.
// Counts, all exact and returned in GeneratedCounts: parts = max(n, 2);
// welds = 1 + cluster welds; rigid bodies = parts - 1 - welds; loops = P + S;
// dof = R + W + 2U + P + 2S; redundant = 3P. For scale, generate_assembly(1000, 42)
// gives 25 branches, 203 welds (69 helpers), 796 rigid bodies, 37 joint
// nodes, 125 loops (53 planar), dof 655, tree depth at most 36 -- with any
// compiler and standard library.
// Geometry is generic (random directions, no singular poses): every joint's
// two frames coincide, every inertia is a positive-definite box tensor.
#include <array>
#include <cmath>
#include <string>

#include "builder.h"

namespace mbx_stub {
namespace {

using namespace build;

// splitmix64: portable, unlike the std:: distributions. Every draw below is
// its own statement: C++ leaves the order of evaluating function arguments
// and operands unspecified, and GCC and Clang do differ, so two draws in one
// expression would make the output compiler-dependent.
class Rng {
public:
    explicit Rng(uint32_t seed) : state_(0x9E3779B97F4A7C15ull * (uint64_t(seed) + 1)) {}
    uint64_t next() {
        uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform(double lo, double hi) { return lo + (hi - lo) * double(next() >> 11) * 0x1.0p-53; }
    bool chance(double p) { return uniform(0, 1) < p; }
    Vec3 unit() {
        for (;;) {
            const double x = uniform(-1, 1);
            const double y = uniform(-1, 1);
            const double z = uniform(-1, 1);
            const Vec3 v(x, y, z);
            const double n = v.norm();
            if (n > 0.2 && n <= 1) return v / n;
        }
    }
    // A unit vector at least ~25 degrees away from `v` (and from -v).
    Vec3 unit_away_from(const Vec3& v) {
        for (;;) {
            const Vec3 u = unit();
            if (std::abs(u.dot(v)) < 0.9) return u;
        }
    }

private:
    uint64_t state_;
};

class Generator {
public:
    Generator(Assembly& a, uint32_t seed) : rng_(seed), b_(a, "gen", kSi, kSi) {}

    void run(size_t n, GeneratedCounts& c);

private:
    struct Tip {
        std::string body;  // local name of the body the next joint hangs from
        Vec3 point;        // where it hangs
        Vec3 direction;    // rough growth direction
        size_t depth;      // tree depth of that body's rigid body
    };

    std::string next_name(const char* kind) { return std::string(kind) + std::to_string(++serial_); }
    mbx_frame_reference frame_ref() { return rng_.chance(0.5) ? MBX_FRAME_IN_BODY : MBX_FRAME_IN_WORLD; }
    mbx_axis_reference axis_ref() { return rng_.chance(0.5) ? MBX_AXIS_IN_BASE_FRAME : MBX_AXIS_IN_WORLD; }
    Mat3 frame_rotation(const Vec3& axis) { return rotation_z_to(axis, rng_.uniform(-3, 3)); }

    // A bar-shaped part from p to q.
    void link(const std::string& local, const Vec3& p, const Vec3& q);
    void joint(const std::string& base, const std::string& follower, const Vec3& at, const std::vector<Prim>& chain) {
        const Vec3 axis = chain.front().type == MBX_PRIMITIVE_REVOLUTE ? chain.front().axis : rng_.unit();
        const Mat3 rotation = frame_rotation(axis);
        const mbx_frame_reference base_ref = frame_ref();
        const mbx_frame_reference follower_ref = frame_ref();
        b_.joint(next_name("j"), base, follower, at, rotation, chain, base_ref, follower_ref);
    }
    Prim rev(const Vec3& axis) {
        const bool flip = rng_.chance(0.2);
        const mbx_axis_reference reference = axis_ref();
        return revolute(flip ? Vec3(-axis) : axis, reference);
    }
    Vec3 bend(const Vec3& d) { return (d + 0.6 * rng_.unit()).normalized(); }

    Tip revolute_link(const Tip& t, GeneratedCounts& c);
    Tip universal_link(const Tip& t, GeneratedCounts& c);
    Tip welded_cluster(const Tip& t, size_t extras, GeneratedCounts& c);
    Tip planar_fourbar(const Tip& t, GeneratedCounts& c);
    Tip rssr(const Tip& t, GeneratedCounts& c);
    // Crank p0-p1, coupler p1-p2 and rocker p3-p2, hung from t.body at p0
    // and p3; the joint at p3 is listed last.
    Tip closed_loop(const Tip& t, const std::array<Vec3, 4>& p, const std::array<Prim, 4>& joints);

    static constexpr mbx_units kSi{1, 1, 1};
    Rng rng_;
    Builder b_;
    size_t serial_ = 0;
};

void Generator::link(const std::string& local, const Vec3& p, const Vec3& q) {
    const Vec3 d = q - p;
    const double len = d.norm();
    const double mass = rng_.uniform(0.2, 3.0);
    const double w = rng_.uniform(0.02, 0.05), h = rng_.uniform(0.02, 0.05);
    const Mat3 r = rotation_x_to(d, rng_.unit_away_from(d / len));
    const bool frame_at_p = rng_.chance(0.5);
    const Vec3 origin = frame_at_p ? p : Vec3((p + q) / 2);
    b_.body(local, local, 0, mass, r, origin, (p + q) / 2, box_inertia(mass, len + w, w, h));
    b_.mesh(local, box_mesh("bar", Vec3(len + w, w, h), Mat3::Identity(),
                            frame_at_p ? Vec3(len / 2, 0, 0) : Vec3::Zero()));
}

Generator::Tip Generator::revolute_link(const Tip& t, GeneratedCounts& c) {
    const std::string name = next_name("link");
    const Vec3 d = bend(t.direction);
    const Vec3 q = t.point + rng_.uniform(0.1, 0.2) * d;
    link(name, t.point, q);
    joint(t.body, name, t.point, {rev(rng_.unit())});
    ++c.revolutes;
    c.dof += 1;
    return {name, q, d, t.depth + 1};
}

Generator::Tip Generator::universal_link(const Tip& t, GeneratedCounts& c) {
    const std::string name = next_name("link");
    const Vec3 d = bend(t.direction);
    const Vec3 q = t.point + rng_.uniform(0.1, 0.2) * d;
    link(name, t.point, q);
    const Vec3 a = rng_.unit();
    const Vec3 b = a.cross(rng_.unit_away_from(a)).normalized();  // perpendicular, as a cross's arms
    joint(t.body, name, t.point, {rev(a), rev(b)});
    c.revolutes += 2;
    c.joint_nodes += 1;
    c.dof += 2;
    return {name, q, d, t.depth + 2};
}

Generator::Tip Generator::welded_cluster(const Tip& t, size_t extras, GeneratedCounts& c) {
    Tip main = revolute_link(t, c);
    Tip next = main;
    for (size_t k = 0; k < extras; ++k) {
        const std::string name = next_name("part");
        const bool helper = rng_.chance(0.3);
        const Vec3 p = main.point + 0.05 * rng_.unit();
        if (helper) {
            b_.body(name, name, MBX_BODY_HELPER, 0.0, Mat3::Identity(), p, p, Mat3::Zero());
            ++c.helpers;
        } else {
            link(name, p, p + 0.06 * bend(main.direction));
            next = {name, p, main.direction, main.depth};
        }
        const Mat3 rotation = frame_rotation(rng_.unit());
        const mbx_frame_reference base_ref = frame_ref();
        const mbx_frame_reference follower_ref = frame_ref();
        b_.joint(next_name("w"), main.body, name, p, rotation, {weld()}, base_ref, follower_ref);
        ++c.welds;
    }
    return next;
}

Generator::Tip Generator::planar_fourbar(const Tip& t, GeneratedCounts& c) {
    const Vec3 n = rng_.unit();
    const Vec3 u = (t.direction - t.direction.dot(n) * n).norm() > 0.2
                       ? Vec3((t.direction - t.direction.dot(n) * n).normalized())
                       : Vec3(n.cross(rng_.unit_away_from(n)).normalized());
    const Vec3 v = n.cross(u);
    const double s = rng_.uniform(0.08, 0.12);
    // Proportions of the fourbar builtin, jittered: never near a singular pose.
    auto at = [&](double x, double y) {
        const double jx = rng_.uniform(-0.05, 0.05);
        const double jy = rng_.uniform(-0.05, 0.05);
        return Vec3(t.point + s * (x + jx) * u + s * (y + jy) * v);
    };
    const Vec3 A = t.point;
    const Vec3 B = at(0.24, 0.32);
    const Vec3 C = at(1.14, 0.62);
    const Vec3 D = at(1.2, 0.0);
    const Prim at_a = rev(n);
    const Prim at_b = rev(n);
    const Prim at_c = rev(n);
    const Prim at_d = rev(n);
    c.revolutes += 4;
    c.loops += 1;
    c.planar_loops += 1;
    c.redundant += 3;
    c.dof += 1;
    return closed_loop(t, {A, B, C, D}, {at_a, at_b, at_c, at_d});
}

Generator::Tip Generator::closed_loop(const Tip& t, const std::array<Vec3, 4>& p, const std::array<Prim, 4>& joints) {
    const std::string crank = next_name("crank");
    const std::string coupler = next_name("coupler");
    const std::string rocker = next_name("rocker");
    link(crank, p[0], p[1]);
    link(coupler, p[1], p[2]);
    link(rocker, p[3], p[2]);
    joint(t.body, crank, p[0], {joints[0]});
    joint(crank, coupler, p[1], {joints[1]});
    joint(coupler, rocker, p[2], {joints[2]});
    joint(t.body, rocker, p[3], {joints[3]});  // closes the loop, last in host order: the cut
    const Vec3 out = p[2] - p[3];
    return {rocker, p[2] + 0.3 * out, out.normalized(), t.depth + 3};
}

Generator::Tip Generator::rssr(const Tip& t, GeneratedCounts& c) {
    const Vec3 A = t.point;
    const double reach = rng_.uniform(0.12, 0.18);
    const Vec3 D = t.point + reach * bend(t.direction);
    for (;;) {
        const Vec3 a = rng_.unit();
        const Vec3 b = rng_.unit();
        const Vec3 B = A + 0.05 * a.cross(rng_.unit_away_from(a)).normalized();
        const Vec3 radial = b.cross(rng_.unit_away_from(b)).normalized();
        const Vec3 offset = rng_.unit();
        const Vec3 C = D + 0.08 * radial + 0.03 * offset;
        const Vec3 bc = (C - B).normalized();
        // Generic only if neither crank axis is coplanar with the coupler's
        // S-S line (else the closure loses rank or sits at a dead point).
        const bool skew_a = std::abs(a.cross(bc).dot(B - A)) > 0.2 * (B - A).norm();
        const bool skew_b = std::abs(b.cross(bc).dot(C - D)) > 0.2 * (C - D).norm();
        if (!skew_a || !skew_b || (C - B).norm() < 0.05) continue;
        const Prim at_a = rev(a);
        const Prim at_d = rev(b);
        c.revolutes += 2;
        c.sphericals += 2;
        c.loops += 1;
        c.spatial_loops += 1;
        c.dof += 2;
        return closed_loop(t, {A, B, C, D}, {at_a, spherical(), spherical(), at_d});
    }
}

void Generator::run(size_t n, GeneratedCounts& c) {
    const Mat3 I = Mat3::Identity();
    b_.body("ground", "Ground", MBX_BODY_GROUND, 100.0, I, Vec3::Zero(), Vec3::Zero(), box_inertia(100.0, 2, 2, 0.1));
    b_.mesh("ground", box_mesh("floor", Vec3(2, 2, 0.1), I, Vec3(0, 0, -0.05)));
    b_.body("RootPart", "RootPart", MBX_BODY_HELPER, 0.0, I, Vec3::Zero(), Vec3::Zero(), Mat3::Zero());
    b_.joint("root_weld", "ground", "RootPart", Vec3::Zero(), I, {weld()}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_BODY);
    c.helpers = 1;
    c.welds = 1;
    size_t parts = 2;

    const size_t target = n > 2 ? n - 2 : 0;
    const size_t kPerBranch = 40;
    c.branches = target == 0 ? 0 : (target + kPerBranch - 1) / kPerBranch;
    for (size_t k = 0; k < c.branches; ++k) {
        const size_t quota = target / c.branches + (k < target % c.branches ? 1 : 0);
        const double phi = 2 * kPi * double(k) / double(c.branches);
        const Vec3 radial(std::cos(phi), std::sin(phi), 0);
        Tip tip{k % 2 ? "RootPart" : "ground", 0.5 * radial + Vec3(0, 0, 0.05 * double(k % 7)),
                (radial + Vec3(0, 0, 1)).normalized(), 0};
        size_t used = 0;
        for (size_t slot = 0; used < quota; ++slot) {
            const size_t room = quota - used;
            switch (slot % 4) {
                case 1:
                    if (room >= 2) {
                        const size_t extras = room >= 3 && rng_.chance(0.5) ? 2 : 1;
                        tip = welded_cluster(tip, extras, c);
                        used += 1 + extras;
                        break;
                    }
                    tip = revolute_link(tip, c);
                    used += 1;
                    break;
                case 2:
                    tip = rng_.chance(0.25) ? universal_link(tip, c) : revolute_link(tip, c);
                    used += 1;
                    break;
                case 3:
                    if (room >= 3) {
                        tip = rng_.chance(0.5) ? planar_fourbar(tip, c) : rssr(tip, c);
                        used += 3;
                        break;
                    }
                    tip = revolute_link(tip, c);
                    used += 1;
                    break;
                default:
                    tip = revolute_link(tip, c);
                    used += 1;
                    break;
            }
            if (tip.depth > c.max_depth) c.max_depth = tip.depth;
        }
        parts += used;
    }
    c.parts = parts;
    c.rigid_bodies = parts - 1 - c.welds;
    c.joints = c.revolutes + c.sphericals;
}

}  // namespace

Assembly generate_assembly(size_t body_count, uint32_t seed) { return generate_assembly(body_count, seed, nullptr); }

Assembly generate_assembly(size_t body_count, uint32_t seed, GeneratedCounts* counts) {
    Assembly a;
    a.name = "generated_" + std::to_string(body_count) + "_" + std::to_string(seed);
    a.source = "mbx_stub generate_assembly(" + std::to_string(body_count) + ", " + std::to_string(seed) + ")";
    GeneratedCounts c;
    Generator(a, seed).run(body_count, c);
    if (counts) *counts = c;
    return a;
}

}  // namespace mbx_stub
