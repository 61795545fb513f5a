#include "generate_pmxml.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "mechanism_builder.h"

namespace mbx_samples {
namespace {

// splitmix64: the same stream on every platform and standard library. Each
// draw is its own statement, since argument evaluation order is unspecified.
class Rng {
public:
    explicit Rng(uint32_t seed) : state_(0x2545F4914F6CDD1Dull ^ (uint64_t(seed) * 0x9E3779B97F4A7C15ull)) {}
    uint64_t next() {
        uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform(double lo, double hi) { return lo + (hi - lo) * double(next() >> 11) * 0x1.0p-53; }
    size_t index(size_t n) { return size_t(next() % n); }

private:
    uint64_t state_;
};

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinGap = 40;      // mm between any two part frames
constexpr double kCoupler = 60;     // mm: parallelogram offset = coupler length
constexpr size_t kPerPedestal = 25; // top-level sub-assemblies per pedestal

struct BarKind {
    double length;
    std::string url;
    VrmlShape shape;
    SolidProperties props;
};

class Generator {
public:
    Generator(const GeneratorOptions& options, const std::string& name)
        : o_(options), rng_(options.seed), m_(name, PmxmlUnits{}, 2.7e-6) {
        for (double length : {50.0, 60.0, 70.0, 90.0}) {
            BarKind k;
            k.length = length;
            k.url = "bar" + std::to_string(int(length)) + "_p.wrl";
            k.shape.name = "BAR" + std::to_string(int(length));
            k.shape.solid = box(Eigen::Vector3d(length + 12, 12, 8), make_pose(Eigen::Vector3d(length / 2, 0, 0)));
            k.shape.color = Eigen::Vector3d(0.6, 0.6 + 0.004 * length, 0.7);
            k.props = properties(k.shape.solid);
            if (!o_.inline_geometry) m_.add_geometry_file(VrmlGeometryFile{k.url, k.shape.name, {k.shape}});
            kinds_.push_back(std::move(k));
        }
    }

    GeneratedCounts run(const std::string& directory, const std::string& name);

private:
    // Where the next pattern hangs from: a body, and a point of it in the
    // sub-assembly plane with the heading the chain had there.
    struct Tip {
        int body;
        Eigen::Vector2d point;
        double heading;
    };

    Eigen::Vector3d world(const Eigen::Vector2d& p) const { return plane_ * Eigen::Vector3d(p.x(), p.y(), 0); }
    Eigen::Vector3d normal() const { return plane_.linear().col(2); }
    static Eigen::Vector2d dir(double heading) { return {std::cos(heading), std::sin(heading)}; }

    int bar(size_t kind, const Eigen::Vector2d& start, double heading) {
        const Eigen::Matrix3d r = plane_.linear() * Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        const BarKind& k = kinds_[kind];
        const int b = m_.add_shared_part(sub_, "LINK_" + std::to_string(++serial_), make_pose(world(start), r), k.props,
                                         k.url, k.shape.color);
        if (o_.inline_geometry) m_.set_shape_in_place(b, k.shape);
        ++counts_.parts;
        return b;
    }
    void hinge(int base, int follower, const Eigen::Vector2d& at) {
        m_.add_joint(base, follower, world(at), {revolute(normal())});
        ++counts_.revolutes;
    }
    // True when every point keeps the gap to the taken ones and each other,
    // and stays within reach of the sub-assembly origin.
    bool free(const std::vector<Eigen::Vector2d>& points) const {
        for (size_t i = 0; i < points.size(); ++i) {
            if (points[i].norm() > reach_) return false;
            for (const Eigen::Vector2d& t : taken_)
                if ((points[i] - t).norm() < kMinGap) return false;
            for (size_t j = 0; j < i; ++j)
                if ((points[i] - points[j]).norm() < kMinGap) return false;
        }
        return true;
    }
    // Where a pattern goes: its hinge point and heading, and the points
    // `make_points(start, heading)` says it would take. Tries headings near
    // the chain's, then any heading, then moves the hinge to a free spot of
    // the sub-assembly (a joint need not sit on its parent's geometry), so
    // part frames never come closer than kMinGap.
    struct Placement {
        Eigen::Vector2d start;
        double heading;
    };
    template <class MakePoints>
    Placement place(const Tip& t, MakePoints make_points) {
        for (int attempt = 0; attempt < 100000; ++attempt) {
            Placement p{t.point, t.heading};
            std::vector<Eigen::Vector2d> points;
            if (attempt >= 96) {
                const double r = rng_.uniform(0, reach_);
                const double a = rng_.uniform(-kPi, kPi);
                p.start = r * dir(a);
                points.push_back(p.start);
            }
            const double spread = attempt < 48 ? 1.2 : kPi;
            const double jitter = rng_.uniform(-spread, spread);
            p.heading = t.heading + jitter;
            const std::vector<Eigen::Vector2d> more = make_points(p.start, p.heading);
            points.insert(points.end(), more.begin(), more.end());
            if (free(points)) return p;
        }
        throw std::runtime_error("generator: no room left in a sub-assembly");
    }

    Tip pattern_r(const Tip& t);
    Tip pattern_w(const Tip& t);
    Tip pattern_l(const Tip& t);
    Tip subsystem(int parent, int anchor, size_t index, size_t quota);

    GeneratorOptions o_;
    Rng rng_;
    MechanismBuilder m_;
    std::vector<BarKind> kinds_;
    GeneratedCounts counts_;
    int sub_ = 0;
    Eigen::Isometry3d plane_ = Eigen::Isometry3d::Identity();
    std::vector<Eigen::Vector2d> taken_;  // part frames and future ones, this sub-assembly
    size_t serial_ = 0;
    size_t r_ = 0, w_ = 0, l_ = 0;
    size_t grid_ = 1;       // sub-assembly regions per axis
    double reach_ = 1100;   // mm: a sub-assembly stays within this of its origin
    double cell_ = 2600;    // mm between sub-assembly origins
    size_t pedestals_ = 0;
};

Generator::Tip Generator::pattern_r(const Tip& t) {
    const size_t kind = rng_.index(kinds_.size());
    const double len = kinds_[kind].length;
    const Placement p = place(t, [&](const Eigen::Vector2d& s, double a) {
        return std::vector<Eigen::Vector2d>{s + len * dir(a)};
    });
    const int b = bar(kind, p.start, p.heading);
    hinge(t.body, b, p.start);
    const Eigen::Vector2d end = p.start + len * dir(p.heading);
    taken_.push_back(p.start);
    taken_.push_back(end);
    ++r_;
    return {b, end, p.heading};
}

Generator::Tip Generator::pattern_w(const Tip& t) {
    const size_t kind = rng_.index(kinds_.size());
    const double len = kinds_[kind].length, bracket = kinds_[0].length;
    const Placement p = place(t, [&](const Eigen::Vector2d& s, double a) {
        return std::vector<Eigen::Vector2d>{s + len * dir(a), s + (len + bracket) * dir(a)};
    });
    const int link = bar(kind, p.start, p.heading);
    hinge(t.body, link, p.start);
    const Eigen::Vector2d q = p.start + len * dir(p.heading);
    const int welded = bar(0, q, p.heading);
    m_.add_joint(link, welded, world(q), {weld()});
    ++counts_.welds;
    const Eigen::Vector2d end = q + bracket * dir(p.heading);
    taken_.push_back(p.start);
    taken_.push_back(q);
    taken_.push_back(end);
    ++w_;
    return {welded, end, p.heading};
}

Generator::Tip Generator::pattern_l(const Tip& t) {
    // Crank A->B and rocker D->C parallel and equal, coupler B->C = D - A
    // (60 mm, at `phi`, drawn with each try): the loop closes exactly.
    const size_t kind = 1 + rng_.index(kinds_.size() - 1);
    const double len = kinds_[kind].length;
    double phi = 0;
    const Placement p = place(t, [&](const Eigen::Vector2d& A, double a) {
        const double side = rng_.uniform(-1, 1) < 0 ? -1.0 : 1.0;
        const double jitter = rng_.uniform(-0.5, 0.5);
        phi = t.heading + side * kPi / 2 + jitter;
        // A folded parallelogram (crank along the coupler) is out of reach.
        if (std::abs(std::sin(a - phi)) < 0.5) return std::vector<Eigen::Vector2d>{{2 * reach_, 0}};
        const Eigen::Vector2d B = A + len * dir(a), D = A + kCoupler * dir(phi);
        return std::vector<Eigen::Vector2d>{B, D, B + (D - A)};
    });
    const Eigen::Vector2d A = p.start, B = A + len * dir(p.heading), D = A + kCoupler * dir(phi), C = B + (D - A);
    const int crank = bar(kind, A, p.heading);
    const int coupler = bar(1, B, phi);  // kinds_[1]: the 60 mm bar
    const int rocker = bar(kind, D, p.heading);
    hinge(t.body, crank, A);
    hinge(crank, coupler, B);
    hinge(coupler, rocker, C);
    hinge(t.body, rocker, D);  // closes the loop: last in host order
    for (const Eigen::Vector2d& q : {A, B, D, C}) taken_.push_back(q);
    ++l_;
    ++counts_.loops;
    return {coupler, C, p.heading};
}

Generator::Tip Generator::subsystem(int parent, int anchor, size_t index, size_t quota) {
    // Its own region and plane; the first bar's frame at the plane origin,
    // the RootPart's (the placement) beside it, so neither hides the other.
    const size_t grid = grid_;
    const Eigen::Vector3d centre = cell_ * Eigen::Vector3d(double(1 + index % grid), double(1 + index / grid % grid),
                                                           double(1 + index / grid / grid));
    const double ax = rng_.uniform(-1, 1);
    const double ay = rng_.uniform(-1, 1);
    const double az = rng_.uniform(-1, 1);
    const double angle = rng_.uniform(0, kPi);
    Eigen::Vector3d axis(ax, ay, az);
    if (axis.norm() < 1e-3) axis = Eigen::Vector3d::UnitZ();
    plane_ = make_pose(centre, Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix());
    taken_.clear();
    const Eigen::Vector2d placement_point(-30, -30);
    taken_.push_back(placement_point);
    taken_.push_back(Eigen::Vector2d::Zero());
    sub_ = m_.add_subsystem(parent, "SUB_" + std::to_string(index + 1),
                            make_pose(world(placement_point), plane_.linear()));
    ++counts_.subsystems;

    Tip tip{anchor, Eigen::Vector2d::Zero(), 0};
    // The first bar hangs from the anchor outside this sub-assembly.
    tip = pattern_r(tip);
    m_.weld_to_root_part(sub_, tip.body);
    ++counts_.welds;
    size_t left = quota - 1;
    int next = 0;  // W, L, R, ...
    while (left > 0) {
        if (next == 0 && left >= 2) {
            tip = pattern_w(tip);
            left -= 2;
        } else if (next == 1 && left >= 3) {
            tip = pattern_l(tip);
            left -= 3;
        } else {
            tip = pattern_r(tip);
            left -= 1;
        }
        next = (next + 1) % 3;
    }
    return tip;
}

GeneratedCounts Generator::run(const std::string& directory, const std::string& name) {
    const size_t parts = std::max<size_t>(o_.parts, 1);
    const size_t size = std::max<size_t>(o_.subsystem_size, 1);
    const size_t expected_subsystems = (parts - 1 + size - 1) / size + 1;
    grid_ = size_t(std::ceil(std::cbrt(double(expected_subsystems))));
    // Room for the chain grows with the area it needs.
    reach_ = 1100 * std::max(1.0, std::sqrt(double(size) / 40));
    cell_ = 2 * reach_ + 400;

    const BarKind& base_kind = kinds_.back();
    const int base = m_.add_shared_part(0, "BASE", Eigen::Isometry3d::Identity(), base_kind.props, base_kind.url,
                                        base_kind.shape.color);
    if (o_.inline_geometry) m_.set_shape_in_place(base, base_kind.shape);
    ++counts_.parts;
    m_.weld_to_root_part(0, base);
    counts_.welds += 2;  // and RootGround--RootPart, added by finish()

    size_t left = parts - 1, index = 0, top_level = 0;
    int pedestal = base;
    int previous_sub = 0;
    Tip previous_tip{base, Eigen::Vector2d::Zero(), 0};
    while (left > 0) {
        const bool nested = index % 3 != 0;
        int parent = 0, anchor = pedestal;
        if (nested) {
            parent = previous_sub;
            anchor = previous_tip.body;
        } else {
            if (top_level % kPerPedestal == 0 && left >= 2) {
                const BarKind& k = kinds_.back();
                const Eigen::Vector3d at(-cell_, 0, cell_ * double(top_level / kPerPedestal));
                pedestal = m_.add_shared_part(0, "PEDESTAL_" + std::to_string(top_level / kPerPedestal + 1),
                                              make_pose(at), k.props, k.url, k.shape.color);
                if (o_.inline_geometry) m_.set_shape_in_place(pedestal, k.shape);
                ++counts_.parts;
                --left;
                m_.add_joint(base, pedestal, at, {weld()});
                ++counts_.welds;
                ++pedestals_;
            }
            anchor = pedestal;
            ++top_level;
        }
        const size_t quota = std::min(size, left);
        previous_tip = subsystem(parent, anchor, index, quota);
        previous_sub = sub_;
        left -= quota;
        ++index;
    }

    const PmxmlDocument& doc = m_.finish();
    PmxmlDocument out = doc;
    out.digits = o_.digits;
    out.created_from = "mbx_generate_pmxml (seed " + std::to_string(o_.seed) + ")";
    counts_.xml_path = directory + "/" + name + ".xml";
    counts_.wrl_path = directory + "/" + name + "_a.wrl";
    write_pmxml(counts_.xml_path, out);
    VrmlAssembly vrml = m_.vrml(name + "_a.wrl", 1.0, true);
    vrml.info = {"mbx_generate_pmxml: " + std::to_string(counts_.parts) + " parts, seed " + std::to_string(o_.seed)};
    write_vrml(directory, vrml);

    counts_.root_parts = 1 + counts_.subsystems;
    counts_.simple_joints = counts_.welds + counts_.revolutes;
    counts_.rigid_bodies = counts_.parts - 1 - pedestals_ - w_;
    counts_.dof = int(r_ + w_ + l_);
    counts_.redundant = int(3 * l_);
    counts_.vrml_nodes = counts_.parts + counts_.subsystems;
    return counts_;
}

}  // namespace

GeneratedCounts generate_pmxml(const std::string& directory, const std::string& name, const GeneratorOptions& options) {
    Generator g(options, name);
    return g.run(directory, name);
}

}  // namespace mbx_samples
