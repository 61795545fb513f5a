#include "step_writer.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <stdexcept>

#include "whole_file.h"

namespace mbx_samples {

StepLengthUnit step_millimetre() { return {"mm", 1e-3}; }
StepLengthUnit step_metre() { return {"m", 1}; }
StepLengthUnit step_inch() { return {"inch", 0.0254}; }

namespace {

// A STEP REAL always has a decimal point ("1.", "1.E-05").
std::string real(double x) {
    if (std::abs(x) < 1e-300) x = 0;
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.15G", x);
    std::string s = buffer;
    if (s.find('.') == std::string::npos) {
        const size_t e = s.find('E');
        if (e == std::string::npos) s += '.';
        else s.insert(e, ".");
    }
    return s;
}

std::string quoted(const std::string& text) {
    std::string out = "'";
    for (char c : text) {
        out += c;
        if (c == '\'') out += '\'';
    }
    return out + "'";
}

class Writer {
public:
    Writer(const std::string& name, const StepLengthUnit& unit) : name_(name), unit_(unit) {}

    std::string run(const std::vector<Solid>& solids) {
        const int context = units_and_context();
        const int origin = axis_placement(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX());
        std::string items = "#" + std::to_string(origin);
        for (size_t s = 0; s < solids.size(); ++s) items += ",#" + std::to_string(solid(solids[s], s));
        const int representation =
            add("ADVANCED_BREP_SHAPE_REPRESENTATION(" + quoted(name_) + ",(" + items + "),#" + std::to_string(context) + ")");
        product(representation);
        return "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('mbx sample part'),'2;1');\n"
               "FILE_NAME(" + quoted(name_) + ",'2024-01-01T00:00:00',('mbx'),('mbx'),'mbx_make_samples','mbx','');\n"
               "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n" +
               data_ + "ENDSEC;\nEND-ISO-10303-21;\n";
    }

private:
    int add(const std::string& entity) {
        const int id = next_++;
        data_ += "#" + std::to_string(id) + "=" + entity + ";\n";
        return id;
    }
    static std::string ref(int id) { return "#" + std::to_string(id); }

    std::string triple(const Eigen::Vector3d& v) { return "(" + real(v.x()) + "," + real(v.y()) + "," + real(v.z()) + ")"; }
    int point(const Eigen::Vector3d& metres) { return add("CARTESIAN_POINT(''," + triple(metres / unit_.metres) + ")"); }
    int direction(const Eigen::Vector3d& d) { return add("DIRECTION(''," + triple(d) + ")"); }
    int axis_placement(const Eigen::Vector3d& at, const Eigen::Vector3d& z, const Eigen::Vector3d& x) {
        const int p = point(at), dz = direction(z), dx = direction(x);
        return add("AXIS2_PLACEMENT_3D(''," + ref(p) + "," + ref(dz) + "," + ref(dx) + ")");
    }

    int units_and_context() {
        int length = 0;
        if (unit_.name == "m") {
            length = add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT($,.METRE.))");
        } else if (unit_.name == "mm") {
            length = add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
        } else if (unit_.name == "inch") {
            const int mm = add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
            const int measure = add("LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4)," + ref(mm) + ")");
            const int exponents = add("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)");
            length = add("(CONVERSION_BASED_UNIT('INCH'," + ref(measure) + ")LENGTH_UNIT()NAMED_UNIT(" + ref(exponents) + "))");
        } else {
            throw std::invalid_argument("step_part: unknown length unit '" + unit_.name + "'");
        }
        const int angle = add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))");
        const int solid_angle = add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())");
        const int uncertainty = add("UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(" + real(1e-6 / unit_.metres) + ")," +
                                    ref(length) + ",'distance_accuracy_value','confusion accuracy')");
        return add("(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((" + ref(uncertainty) +
                   "))GLOBAL_UNIT_ASSIGNED_CONTEXT((" + ref(length) + "," + ref(angle) + "," + ref(solid_angle) +
                   "))REPRESENTATION_CONTEXT('',''))");
    }

    void product(int representation) {
        const int application = add("APPLICATION_CONTEXT('core data for automotive mechanical design processes')");
        add("APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000," + ref(application) + ")");
        const int product_context = add("PRODUCT_CONTEXT(''," + ref(application) + ",'mechanical')");
        const int definition_context = add("PRODUCT_DEFINITION_CONTEXT('part definition'," + ref(application) + ",'design')");
        const int product = add("PRODUCT(" + quoted(name_) + "," + quoted(name_) + ",'',(" + ref(product_context) + "))");
        const int formation = add("PRODUCT_DEFINITION_FORMATION('',''," + ref(product) + ")");
        const int definition = add("PRODUCT_DEFINITION('design',''," + ref(formation) + "," + ref(definition_context) + ")");
        const int shape = add("PRODUCT_DEFINITION_SHAPE(''," + quoted(name_) + "," + ref(definition) + ")");
        add("SHAPE_DEFINITION_REPRESENTATION(" + ref(shape) + "," + ref(representation) + ")");
    }

    // A face's boundary: the group's directed edges whose reverse is not in
    // the group, chained into loops. Empty when a vertex has two ways on
    // (the caller then writes the group's triangles one by one).
    static std::vector<std::vector<uint32_t>> loops_of(const Solid& s, const std::vector<int>& triangles) {
        std::map<std::pair<uint32_t, uint32_t>, int> directed;
        for (int t : triangles)
            for (int k = 0; k < 3; ++k) ++directed[{s.triangles[size_t(t)][size_t(k)], s.triangles[size_t(t)][size_t((k + 1) % 3)]}];
        std::map<uint32_t, uint32_t> next;
        for (const auto& [edge, count] : directed) {
            if (directed.count({edge.second, edge.first})) continue;
            if (count != 1 || !next.emplace(edge.first, edge.second).second) return {};
        }
        std::vector<std::vector<uint32_t>> loops;
        while (!next.empty()) {
            std::vector<uint32_t> loop{next.begin()->first};
            for (;;) {
                auto it = next.find(loop.back());
                if (it == next.end()) return {};
                const uint32_t to = it->second;
                next.erase(it);
                if (to == loop.front()) break;
                loop.push_back(to);
            }
            loops.push_back(std::move(loop));
        }
        return loops;
    }

    int edge(const Solid& s, uint32_t a, uint32_t b, bool& same_sense) {
        const std::pair<uint32_t, uint32_t> key{std::min(a, b), std::max(a, b)};
        same_sense = a < b;
        auto found = edges_.find(key);
        if (found != edges_.end()) return found->second;
        const Eigen::Vector3d from = s.vertices[key.first], to = s.vertices[key.second];
        const Eigen::Vector3d d = to - from;
        const int dir = direction(d.normalized());
        const int vector = add("VECTOR(''," + ref(dir) + "," + real(d.norm() / unit_.metres) + ")");
        const int line = add("LINE(''," + ref(vertex_points_[key.first].first) + "," + ref(vector) + ")");
        const int e = add("EDGE_CURVE(''," + ref(vertex_points_[key.first].second) + "," +
                          ref(vertex_points_[key.second].second) + "," + ref(line) + ",.T.)");
        edges_.emplace(key, e);
        return e;
    }

    int face(const Solid& s, const std::vector<std::vector<uint32_t>>& loops, const Eigen::Vector3d& normal) {
        // The outer bound encloses the others: the largest area about the normal.
        std::vector<double> area(loops.size(), 0);
        for (size_t l = 0; l < loops.size(); ++l)
            for (size_t k = 0; k < loops[l].size(); ++k)
                area[l] += normal.dot(s.vertices[loops[l][k]].cross(s.vertices[loops[l][(k + 1) % loops[l].size()]]));
        const size_t outer = size_t(std::max_element(area.begin(), area.end()) - area.begin());
        std::string bounds;
        for (size_t l = 0; l < loops.size(); ++l) {
            std::string oriented;
            for (size_t k = 0; k < loops[l].size(); ++k) {
                bool same = true;
                const int e = edge(s, loops[l][k], loops[l][(k + 1) % loops[l].size()], same);
                oriented += (k ? ",#" : "#") + std::to_string(add("ORIENTED_EDGE('',*,*," + ref(e) + (same ? ",.T.)" : ",.F.)")));
            }
            const int loop = add("EDGE_LOOP('',(" + oriented + "))");
            const int bound = add(std::string(l == outer ? "FACE_OUTER_BOUND" : "FACE_BOUND") + "(''," + ref(loop) + ",.T.)");
            bounds += (l ? ",#" : "#") + std::to_string(bound);
        }
        const Eigen::Vector3d on = s.vertices[loops[outer][0]];
        const Eigen::Vector3d x = (s.vertices[loops[outer][1]] - on).normalized();
        const int plane = add("PLANE(''," + ref(axis_placement(on, normal, x)) + ")");
        return add("ADVANCED_FACE('',(" + bounds + ")," + ref(plane) + ",.T.)");
    }

    int solid(const Solid& s, size_t index) {
        edges_.clear();
        vertex_points_.clear();
        for (const Eigen::Vector3d& v : s.vertices) {
            const int p = point(v);
            vertex_points_.push_back({p, add("VERTEX_POINT(''," + ref(p) + ")")});
        }
        // Connected coplanar triangles make one face.
        const size_t n = s.triangles.size();
        std::vector<Eigen::Vector3d> normal(n);
        std::vector<double> offset(n);
        double size = 0;
        for (const Eigen::Vector3d& v : s.vertices) size = std::max(size, v.cwiseAbs().maxCoeff());
        for (size_t t = 0; t < n; ++t) {
            const auto& tri = s.triangles[t];
            normal[t] = (s.vertices[tri[1]] - s.vertices[tri[0]]).cross(s.vertices[tri[2]] - s.vertices[tri[0]]).normalized();
            offset[t] = normal[t].dot(s.vertices[tri[0]]);
        }
        std::vector<size_t> group(n);
        std::iota(group.begin(), group.end(), 0);
        auto root = [&](size_t t) {
            while (group[t] != t) t = group[t] = group[group[t]];
            return t;
        };
        std::map<std::pair<uint32_t, uint32_t>, size_t> by_edge;
        for (size_t t = 0; t < n; ++t)
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = s.triangles[t][size_t(k)], b = s.triangles[t][size_t((k + 1) % 3)];
                auto other = by_edge.find({b, a});
                if (other != by_edge.end() && normal[t].dot(normal[other->second]) > 1 - 1e-12 &&
                    std::abs(offset[t] - offset[other->second]) < 1e-12 * std::max(size, 1e-3))
                    group[root(t)] = root(other->second);
                by_edge[{a, b}] = t;
            }
        std::map<size_t, std::vector<int>> faces;
        for (size_t t = 0; t < n; ++t) faces[root(t)].push_back(int(t));
        std::string list;
        for (const auto& [first, triangles] : faces) {
            std::vector<std::vector<uint32_t>> loops = loops_of(s, triangles);
            if (loops.empty()) {
                for (int t : triangles) {
                    const auto& tri = s.triangles[size_t(t)];
                    list += (list.empty() ? "#" : ",#") + std::to_string(face(s, {{tri[0], tri[1], tri[2]}}, normal[size_t(t)]));
                }
                continue;
            }
            list += (list.empty() ? "#" : ",#") + std::to_string(face(s, loops, normal[first]));
        }
        const int shell = add("CLOSED_SHELL('',(" + list + "))");
        return add("MANIFOLD_SOLID_BREP(" + quoted(name_ + (index ? "_" + std::to_string(index + 1) : "")) + "," + ref(shell) + ")");
    }

    std::string name_;
    StepLengthUnit unit_;
    std::string data_;
    int next_ = 1;
    std::map<std::pair<uint32_t, uint32_t>, int> edges_;
    std::vector<std::pair<int, int>> vertex_points_;  // CARTESIAN_POINT, VERTEX_POINT
};

}  // namespace

std::string step_part(const std::string& product_name, const std::vector<Solid>& solids, const StepLengthUnit& unit) {
    return Writer(product_name, unit).run(solids);
}

void write_step_part(const std::string& path, const std::string& product_name, const std::vector<Solid>& solids,
                     const StepLengthUnit& unit) {
    write_whole_file(path, step_part(product_name, solids, unit));
}

}  // namespace mbx_samples
