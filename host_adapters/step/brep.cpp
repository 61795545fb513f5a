#include "host_adapters/step/brep.h"

#include <map>
#include <memory>

namespace mbx_step {

namespace {

bool flag(const File& f, const Value& v) { return !(v.kind == Kind::Enumeration && f.text(v) == "F"); }

class BrepReader {
public:
    explicit BrepReader(const File& f) : f_(f) {
        for (const char* name : {"MANIFOLD_SOLID_BREP", "BREP_WITH_VOIDS", "FACETED_BREP", "SHELL_BASED_SURFACE_MODEL",
                                 "TESSELLATED_SOLID", "TESSELLATED_SHELL"})
            solid_types_.push_back(f.type_id(name));
        closed_shell_ = f.type_id("CLOSED_SHELL");
        open_shell_ = f.type_id("OPEN_SHELL");
        oriented_closed_shell_ = f.type_id("ORIENTED_CLOSED_SHELL");
        advanced_face_ = f.type_id("ADVANCED_FACE");
        face_surface_ = f.type_id("FACE_SURFACE");
        outer_bound_ = f.type_id("FACE_OUTER_BOUND");
        bound_ = f.type_id("FACE_BOUND");
        edge_loop_ = f.type_id("EDGE_LOOP");
        vertex_loop_ = f.type_id("VERTEX_LOOP");
        poly_loop_ = f.type_id("POLY_LOOP");
        oriented_edge_ = f.type_id("ORIENTED_EDGE");
        edge_curve_ = f.type_id("EDGE_CURVE");
        vertex_point_ = f.type_id("VERTEX_POINT");
        map_contexts();
        edge_of_.assign(f.instances.size(), kUnresolved);
        vertex_of_.assign(f.instances.size(), kUnresolved);
    }

    Brep run() {
        for (uint32_t k = 0; k < f_.instances.size(); ++k) {
            const Instance& in = f_.instances[k];
            if (in.record_count != 1) continue;
            const Record& r = f_.first_record(in);
            for (size_t t = 0; t < solid_types_.size(); ++t)
                if (r.type == solid_types_[t] && solid_types_[t] != File::kNoType) solid(k, r);
        }
        out_.path = f_.path;
        out_.problems.insert(out_.problems.begin(), f_.problems.begin(), f_.problems.end());
        out_.problems.insert(out_.problems.end(), problems_.begin(), problems_.end());
        return std::move(out_);
    }

private:
    void problem(uint32_t entity, const std::string& message) {
        if (entity < f_.instances.size())
            problems_.push_back({int(f_.instances[entity].line), f_.instances[entity].id, message});
        else
            problems_.push_back({0, 0, message});
    }

    // Each solid's representation context: the shape representation listing
    // it among its items (name, items, context_of_items).
    void map_contexts() {
        context_of_.assign(f_.instances.size(), kUnresolved);
        const uint32_t units = f_.type_id("GLOBAL_UNIT_ASSIGNED_CONTEXT");
        for (uint32_t k = 0; k < f_.instances.size(); ++k) {
            const Instance& in = f_.instances[k];
            if (in.record_count != 1) continue;
            const Record& r = f_.first_record(in);
            if (r.count != 3 || f_.attribute(r, 1).kind != Kind::List) continue;
            const uint32_t context = ref(f_.attribute(r, 2));
            if (context == kUnresolved || !f_.record(context, units)) continue;
            const Value& items = f_.attribute(r, 1);
            for (uint32_t i = 0; i < uint32_t(items.count); ++i) {
                const uint32_t item = ref(f_.element(items, i));
                if (item != kUnresolved) context_of_[item] = context;
            }
            if (fallback_context_ == kUnresolved) fallback_context_ = context;
        }
    }

    GeometryReader& geometry(uint32_t context, ContextUnits& units) {
        auto it = readers_.find(context);
        if (it == readers_.end()) {
            auto entry = std::make_unique<Entry>();
            entry->units = context == kUnresolved ? ContextUnits{} : context_units(f_, context, problems_);
            entry->reader = std::make_unique<GeometryReader>(f_, entry->units, problems_);
            it = readers_.emplace(context, std::move(entry)).first;
        }
        units = it->second->units;
        return *it->second->reader;
    }

    void solid(uint32_t k, const Record& r) {
        Solid s;
        s.entity = k;
        s.type = f_.type_name(r.type);
        if (r.count >= 1 && f_.attribute(r, 0).kind == Kind::String) s.name = std::string(f_.text(f_.attribute(r, 0)));
        uint32_t context = context_of_[k];
        if (context == kUnresolved) {
            context = fallback_context_;
            problem(k, "a solid no shape representation holds: read in the file's first context's units");
        }
        GeometryReader& g = geometry(context, s.units);
        current_ = &g;
        if (s.type == "TESSELLATED_SOLID" || s.type == "TESSELLATED_SHELL") {
            tessellated(k, r, g, s.tessellated);
            if (s.tessellated.triangles.empty()) problem(k, "a tessellated solid without a triangle");
            out_.solids.push_back(std::move(s));
            return;
        }
        if (s.type == "SHELL_BASED_SURFACE_MODEL") {
            const Value& shells = r.count >= 2 ? f_.attribute(r, 1) : Value();
            for (uint32_t i = 0; shells.kind == Kind::List && i < uint32_t(shells.count); ++i)
                s.shells.push_back(shell(ref(f_.element(shells, i)), g));
        } else if (r.count >= 2) {
            s.shells.push_back(shell(ref(f_.attribute(r, 1)), g));
            if (s.type == "BREP_WITH_VOIDS" && r.count >= 3 && f_.attribute(r, 2).kind == Kind::List) {
                const Value& voids = f_.attribute(r, 2);
                for (uint32_t i = 0; i < uint32_t(voids.count); ++i) s.shells.push_back(shell(ref(f_.element(voids, i)), g));
            }
        }
        if (s.shells.empty()) problem(k, "a solid without a shell");
        out_.solids.push_back(std::move(s));
    }

    // TESSELLATED_SOLID / _SHELL(name, items, link): its TRIANGULATED_FACEs
    // (name, coordinates, pnmax, normals, geometric_link, pnindex, triangles)
    // and COMPLEX_TRIANGULATED_FACEs (..., pnindex, triangle_strips,
    // triangle_fans). Indices count from 1, into pnindex where it is given,
    // which counts into the coordinates; faces sharing a coordinates list share
    // its points, so a closed tessellated shell meshes closed.
    void tessellated(uint32_t k, const Record& r, GeometryReader& g, Triangles& out) {
        if (r.count < 2 || f_.attribute(r, 1).kind != Kind::List) return;
        const uint32_t plain = f_.type_id("TRIANGULATED_FACE"), complex = f_.type_id("COMPLEX_TRIANGULATED_FACE");
        std::map<uint32_t, uint32_t> base_of;  // coordinates list -> its first point in `out`
        const Value& items = f_.attribute(r, 1);
        for (uint32_t i = 0; i < uint32_t(items.count); ++i) {
            const uint32_t item = ref(f_.element(items, i));
            const Record* face = item == kUnresolved ? nullptr : f_.record(item, plain);
            const bool is_complex = !face && item != kUnresolved && (face = f_.record(item, complex)) != nullptr;
            if (!face || face->count < (is_complex ? 8u : 7u)) {
                problem(item == kUnresolved ? k : item, "a tessellated item that is not a TRIANGULATED_FACE: left out");
                continue;
            }
            const uint32_t coordinates = ref(f_.attribute(*face, 1));
            if (coordinates == kUnresolved) continue;
            auto found = base_of.find(coordinates);
            if (found == base_of.end()) {
                found = base_of.emplace(coordinates, uint32_t(out.points.size())).first;
                for (const Eigen::Vector3d& p : g.coordinates(coordinates)) out.points.push_back(p);
            }
            const uint32_t base = found->second;
            const size_t count = out.points.size() - base;  // (lists read later come after: bounded below by base)
            std::vector<int64_t> pnindex;
            const Value& pn = f_.attribute(*face, 5);
            for (uint32_t j = 0; pn.kind == Kind::List && j < uint32_t(pn.count); ++j)
                pnindex.push_back(f_.element(pn, j).kind == Kind::Integer ? f_.element(pn, j).integer : 0);
            bool bad = false;
            auto point = [&](const Value& v, uint32_t& to) {
                int64_t n = v.kind == Kind::Integer ? v.integer : 0;
                if (!pnindex.empty()) n = n >= 1 && size_t(n) <= pnindex.size() ? pnindex[size_t(n - 1)] : 0;
                if (n < 1 || size_t(n) > count) return bad = true, false;
                to = base + uint32_t(n - 1);
                return true;
            };
            // (a corner that is not a number was a problem of the coordinates list: its triangles are left out)
            auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
                if (a != b && b != c && a != c && out.points[a].allFinite() && out.points[b].allFinite() &&
                    out.points[c].allFinite())
                    out.triangles.push_back({a, b, c});
            };
            auto each_list = [&](const Value& lists, auto&& take) {
                for (uint32_t j = 0; lists.kind == Kind::List && j < uint32_t(lists.count); ++j) {
                    const Value& l = f_.element(lists, j);
                    std::vector<uint32_t> ids;
                    for (uint32_t m = 0; l.kind == Kind::List && m < uint32_t(l.count); ++m) {
                        uint32_t id = 0;
                        if (point(f_.element(l, m), id)) ids.push_back(id);
                    }
                    take(ids);
                }
            };
            if (!is_complex) {
                each_list(f_.attribute(*face, 6), [&](const std::vector<uint32_t>& t) {
                    if (t.size() == 3) add(t[0], t[1], t[2]);
                    else bad = true;
                });
            } else {
                // A strip turns its every other triangle; a fan pivots on its first point.
                each_list(f_.attribute(*face, 6), [&](const std::vector<uint32_t>& t) {
                    for (size_t m = 2; m < t.size(); ++m)
                        m % 2 == 0 ? add(t[m - 2], t[m - 1], t[m]) : add(t[m - 1], t[m - 2], t[m]);
                });
                each_list(f_.attribute(*face, 7), [&](const std::vector<uint32_t>& t) {
                    for (size_t m = 2; m < t.size(); ++m) add(t[0], t[m - 1], t[m]);
                });
            }
            if (bad) problem(item, "a triangle whose point index is outside its coordinates list: left out");
        }
    }

    Shell shell(uint32_t k, GeometryReader& g) {
        Shell sh;
        sh.entity = k;
        if (k == kUnresolved) return sh;
        // ORIENTED_CLOSED_SHELL(name, *, closed_shell_element, orientation)
        if (const Record* o = f_.record(k, oriented_closed_shell_); o && o->count >= 4) {
            Shell inner = shell(ref(f_.attribute(*o, 2)), g);
            inner.reversed = inner.reversed != !flag(f_, f_.attribute(*o, 3));
            inner.entity = k;
            return inner;
        }
        const Record* r = f_.record(k, closed_shell_);
        if (!r) {
            r = f_.record(k, open_shell_);
            sh.closed = false;
        }
        if (!r || r->count < 2 || f_.attribute(*r, 1).kind != Kind::List) {
            problem(k, "expected a CLOSED_SHELL or OPEN_SHELL");
            return sh;
        }
        const Value& faces = f_.attribute(*r, 1);
        for (uint32_t i = 0; i < uint32_t(faces.count); ++i) {
            const uint32_t face_entity = ref(f_.element(faces, i));
            if (face(face_entity, g)) sh.faces.push_back(uint32_t(out_.faces.size() - 1));
        }
        return sh;
    }

    bool face(uint32_t k, GeometryReader& g) {
        const Record* r = k == kUnresolved ? nullptr : f_.record(k, advanced_face_);
        if (!r && k != kUnresolved) r = f_.record(k, face_surface_);
        const bool faceted = !r && k != kUnresolved && f_.instances[k].record_count == 1 &&
                             f_.type_name(f_.first_record(f_.instances[k]).type) == "FACE";
        if (faceted) r = &f_.first_record(f_.instances[k]);
        if (!r || r->count < 2 || f_.attribute(*r, 1).kind != Kind::List) {
            problem(k, "expected a face (ADVANCED_FACE, FACE_SURFACE or FACE)");
            return false;
        }
        Face fc;
        fc.entity = k;
        fc.id = f_.instances[k].id;
        fc.line = int(f_.instances[k].line);
        const Value& bounds = f_.attribute(*r, 1);
        for (uint32_t i = 0; i < uint32_t(bounds.count); ++i) {
            Loop l;
            if (bound(ref(f_.element(bounds, i)), l)) fc.bounds.push_back(std::move(l));
        }
        if (!faceted && r->count >= 4) {
            fc.surface = g.surface(ref(f_.attribute(*r, 2)));
            fc.same_sense = flag(f_, f_.attribute(*r, 3));
        } else {
            fc.surface.kind = Surface::Kind::Plane;  // a faceted face lies in its polygon's plane
            fc.surface.type = "POLY_LOOP";
            fc.surface.entity = k;
        }
        if (fc.bounds.empty()) problem(k, "a face without a bound");
        out_.faces.push_back(std::move(fc));
        return true;
    }

    bool bound(uint32_t k, Loop& l) {
        const Record* r = k == kUnresolved ? nullptr : f_.record(k, outer_bound_);
        l.outer = r != nullptr;
        if (!r && k != kUnresolved) r = f_.record(k, bound_);
        if (!r || r->count < 3) {
            problem(k, "expected a FACE_BOUND or FACE_OUTER_BOUND");
            return false;
        }
        l.orientation = flag(f_, f_.attribute(*r, 2));
        const uint32_t loop = ref(f_.attribute(*r, 1));
        l.entity = loop;
        if (loop == kUnresolved) {
            problem(k, "a bound without a loop");
            return false;
        }
        if (const Record* e = f_.record(loop, edge_loop_); e && e->count >= 2 && f_.attribute(*e, 1).kind == Kind::List) {
            const Value& list = f_.attribute(*e, 1);
            for (uint32_t i = 0; i < uint32_t(list.count); ++i) {
                const uint32_t oe = ref(f_.element(list, i));
                const Record* o = oe == kUnresolved ? nullptr : f_.record(oe, oriented_edge_);
                if (!o || o->count < 5) {
                    problem(oe == kUnresolved ? loop : oe, "expected an ORIENTED_EDGE in the loop");
                    return false;
                }
                const uint32_t edge_index = edge(ref(f_.attribute(*o, 3)));
                if (edge_index == kUnresolved) {
                    problem(oe, "an ORIENTED_EDGE whose edge is no EDGE_CURVE with two vertices: its face's bound is left out");
                    return false;
                }
                l.edges.push_back({edge_index, flag(f_, f_.attribute(*o, 4))});
            }
            return true;
        }
        if (const Record* v = f_.record(loop, vertex_loop_); v && v->count >= 2) {
            l.kind = Loop::Kind::Vertex;
            l.vertex = vertex(ref(f_.attribute(*v, 1)));
            return l.vertex != kUnresolved;
        }
        if (const Record* p = f_.record(loop, poly_loop_); p && p->count >= 2 && f_.attribute(*p, 1).kind == Kind::List) {
            l.kind = Loop::Kind::Poly;
            const Value& pts = f_.attribute(*p, 1);
            GeometryReader& g = *current_;
            for (uint32_t i = 0; i < uint32_t(pts.count); ++i) l.polygon.push_back(g.point(ref(f_.element(pts, i))));
            return true;
        }
        problem(loop, "a loop that is neither an EDGE_LOOP, a VERTEX_LOOP nor a POLY_LOOP");
        return false;
    }

    uint32_t vertex(uint32_t k) {
        if (k == kUnresolved) return kUnresolved;
        if (vertex_of_[k] != kUnresolved) return vertex_of_[k];
        const Record* r = f_.record(k, vertex_point_);
        if (!r || r->count < 2) {
            problem(k, "expected a VERTEX_POINT");
            return kUnresolved;
        }
        Vertex v;
        v.entity = k;
        v.point = current_->point(ref(f_.attribute(*r, 1)));
        vertex_of_[k] = uint32_t(out_.vertices.size());
        out_.vertices.push_back(v);
        return vertex_of_[k];
    }

    uint32_t edge(uint32_t k) {
        if (k == kUnresolved) return kUnresolved;
        if (edge_of_[k] != kUnresolved) return edge_of_[k];
        const Record* r = f_.record(k, edge_curve_);
        if (!r || r->count < 5) {
            problem(k, "expected an EDGE_CURVE");
            return kUnresolved;
        }
        Edge e;
        e.entity = k;
        e.start = vertex(ref(f_.attribute(*r, 1)));
        e.end = vertex(ref(f_.attribute(*r, 2)));
        e.curve = current_->curve(ref(f_.attribute(*r, 3)));
        e.same_sense = flag(f_, f_.attribute(*r, 4));
        if (e.start == kUnresolved || e.end == kUnresolved) return kUnresolved;
        edge_of_[k] = uint32_t(out_.edges.size());
        out_.edges.push_back(std::move(e));
        return edge_of_[k];
    }

public:
    GeometryReader* current_ = nullptr;  // the reader of the solid being read (its units)

private:
    struct Entry {
        ContextUnits units;
        std::unique_ptr<GeometryReader> reader;
    };
    const File& f_;
    Brep out_;
    std::vector<Problem> problems_;
    std::vector<uint32_t> solid_types_;
    uint32_t closed_shell_, open_shell_, oriented_closed_shell_, advanced_face_, face_surface_, outer_bound_, bound_,
        edge_loop_, vertex_loop_, poly_loop_, oriented_edge_, edge_curve_, vertex_point_;
    std::vector<uint32_t> context_of_, edge_of_, vertex_of_;
    uint32_t fallback_context_ = kUnresolved;
    std::map<uint32_t, std::unique_ptr<Entry>> readers_;
};

}  // namespace

Brep read_breps(const File& f) { return BrepReader(f).run(); }

}  // namespace mbx_step
