#include "host_adapters/step/assembly.h"

#include <algorithm>
#include <map>
#include <memory>
#include <set>

#include "host_adapters/step/geometry.h"
#include "host_adapters/step/units.h"

namespace mbx_step {

namespace {


std::string trimmed(std::string_view s) {
    const size_t first = s.find_first_not_of(" \t");
    if (first == std::string_view::npos) return {};
    return std::string(s.substr(first, s.find_last_not_of(" \t") - first + 1));
}

// A placement as the motion taking its frame's coordinates to its context's.
Eigen::Isometry3d motion(const Placement& p) {
    Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
    m.linear().col(0) = p.x;
    m.linear().col(1) = p.y;
    m.linear().col(2) = p.z;
    m.translation() = p.origin;
    return m;
}

class AssemblyReader {
public:
    AssemblyReader(const File& f, const Brep& b) : f_(f), b_(b) {
        for (uint32_t s = 0; s < b.solids.size(); ++s) solid_of_[b.solids[s].entity] = s;
        index_representations();
        index_products();
        index_links();
    }

    Assembly run() {
        std::set<uint32_t> placed;
        for (uint32_t rep : roots()) {
            std::vector<uint32_t> path;
            walk(rep, Eigen::Isometry3d::Identity(), "", path);
        }
        for (const PlacedSolid& p : out_.solids) placed.insert(p.solid);
        // Solids no root reaches: where they are, named by their own product.
        for (uint32_t s = 0; s < b_.solids.size(); ++s)
            if (!placed.count(s)) {
                PlacedSolid p;
                p.solid = s;
                auto it = holder_.find(b_.solids[s].entity);
                if (it != holder_.end()) p.product = product_of(it->second);
                out_.solids.push_back(p);
            }
        return std::move(out_);
    }

private:
    struct Child {
        uint32_t rep = kUnresolved;
        Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // child's coordinates to the parent's
        std::string occurrence;                                  // empty for a mapped item or a plain link
    };

    void problem(uint32_t entity, const std::string& message) {
        out_.problems.push_back({int(f_.instances[entity].line), f_.instances[entity].id, message});
    }

    // Representations: (name, items, context) whose context carries units.
    void index_representations() {
        const uint32_t units = f_.type_id("GLOBAL_UNIT_ASSIGNED_CONTEXT");
        const uint32_t mapped = f_.type_id("MAPPED_ITEM");
        for (uint32_t k = 0; k < f_.instances.size(); ++k) {
            const Instance& in = f_.instances[k];
            if (in.record_count != 1) continue;
            const Record& r = f_.first_record(in);
            if (r.count != 3 || f_.attribute(r, 1).kind != Kind::List) continue;
            // Shape representations only: a DRAUGHTING_MODEL maps the same
            // shapes again for their colours, which places nothing.
            const std::string& type = f_.type_name(r.type);
            static const std::string kShape = "SHAPE_REPRESENTATION";
            if (type.size() < kShape.size() || type.compare(type.size() - kShape.size(), kShape.size(), kShape) != 0) continue;
            const uint32_t context = ref(f_.attribute(r, 2));
            if (context == kUnresolved || !f_.record(context, units)) continue;
            context_[k] = context;
            const Value& items = f_.attribute(r, 1);
            for (uint32_t i = 0; i < uint32_t(items.count); ++i) {
                const uint32_t item = ref(f_.element(items, i));
                if (item == kUnresolved) continue;
                if (solid_of_.count(item)) {
                    solids_[k].push_back(solid_of_[item]);
                    holder_.emplace(item, k);
                } else if (mapped != File::kNoType && f_.record(item, mapped)) {
                    mapped_items_[k].push_back(item);
                }
            }
        }
    }

    // Each representation's product: SHAPE_DEFINITION_REPRESENTATION(definition
    // -> PRODUCT_DEFINITION_SHAPE -> PRODUCT_DEFINITION -> formation -> PRODUCT).
    void index_products() {
        const uint32_t sdr = f_.type_id("SHAPE_DEFINITION_REPRESENTATION");
        const uint32_t pds = f_.type_id("PRODUCT_DEFINITION_SHAPE");
        const uint32_t pd = f_.type_id("PRODUCT_DEFINITION");
        if (sdr == File::kNoType) return;
        for (uint32_t k = 0; k < f_.instances.size(); ++k) {
            const Record* r = f_.record(k, sdr);
            if (!r || r->count < 2) continue;
            const uint32_t shape = ref(f_.attribute(*r, 0)), rep = ref(f_.attribute(*r, 1));
            if (shape == kUnresolved || rep == kUnresolved) continue;
            const Record* s = f_.record(shape, pds);
            if (!s || s->count < 3) continue;
            const uint32_t definition = ref(f_.attribute(*s, 2));
            if (definition == kUnresolved || !f_.record(definition, pd)) continue;
            rep_of_definition_[definition] = rep;
            product_[rep] = product_name(definition);
        }
    }

    std::string product_name(uint32_t definition) const {
        const Record* d = f_.record(definition, f_.type_id("PRODUCT_DEFINITION"));
        if (!d || d->count < 3) return {};
        const uint32_t formation = ref(f_.attribute(*d, 2));
        if (formation == kUnresolved) return {};
        const Record& pf = f_.first_record(f_.instances[formation]);
        if (pf.count < 3) return {};
        const uint32_t product = ref(f_.attribute(pf, 2));
        if (product == kUnresolved) return {};
        const Record* p = f_.record(product, f_.type_id("PRODUCT"));
        if (!p || p->count < 2) return {};
        for (uint32_t a : {1u, 0u})
            if (f_.attribute(*p, a).kind == Kind::String && !trimmed(f_.text(f_.attribute(*p, a))).empty())
                return trimmed(f_.text(f_.attribute(*p, a)));
        return {};
    }

    std::string product_of(uint32_t rep) const {
        auto it = product_.find(rep);
        if (it != product_.end()) return it->second;
        // (an ADVANCED_BREP_SHAPE_REPRESENTATION is usually linked to the
        // product's SHAPE_REPRESENTATION without a product of its own)
        auto link = plain_.find(rep);
        if (link != plain_.end())
            for (uint32_t other : link->second)
                if (auto p = product_.find(other); p != product_.end()) return p->second;
        return {};
    }

    // Representation relationships: with a transformation (an occurrence's
    // placement) they make parent -> child edges; without one they join two
    // representations of the same shape.
    void index_links() {
        const uint32_t rr = f_.type_id("REPRESENTATION_RELATIONSHIP");
        const uint32_t srr = f_.type_id("SHAPE_REPRESENTATION_RELATIONSHIP");
        const uint32_t with = f_.type_id("REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION");
        const uint32_t cdsr = f_.type_id("CONTEXT_DEPENDENT_SHAPE_REPRESENTATION");
        const uint32_t idt = f_.type_id("ITEM_DEFINED_TRANSFORMATION");
        const uint32_t pds = f_.type_id("PRODUCT_DEFINITION_SHAPE");
        const uint32_t nauo = f_.type_id("NEXT_ASSEMBLY_USAGE_OCCURRENCE");
        // The occurrence each transformed relationship places.
        std::map<uint32_t, uint32_t> occurrence_of;
        for (uint32_t k = 0; cdsr != File::kNoType && k < f_.instances.size(); ++k) {
            const Record* c = f_.record(k, cdsr);
            if (!c || c->count < 2) continue;
            const uint32_t relation = ref(f_.attribute(*c, 0)), shape = ref(f_.attribute(*c, 1));
            const Record* s = shape == kUnresolved ? nullptr : f_.record(shape, pds);
            if (relation == kUnresolved || !s || s->count < 3) continue;
            const uint32_t occurrence = ref(f_.attribute(*s, 2));
            if (occurrence != kUnresolved && f_.record(occurrence, nauo)) occurrence_of[relation] = occurrence;
        }
        // (two passes: the plain links first, which the placed ones consult)
        for (int pass = 0; pass < 2; ++pass)
        for (uint32_t k = 0; k < f_.instances.size(); ++k) {
            const Record* r = rr == File::kNoType ? nullptr : f_.record(k, rr);
            if (!r && srr != File::kNoType && f_.instances[k].record_count == 1) r = f_.record(k, srr);
            if (!r || r->count < 4) continue;
            const uint32_t rep_1 = ref(f_.attribute(*r, 2)), rep_2 = ref(f_.attribute(*r, 3));
            if (!context_.count(rep_1) || !context_.count(rep_2)) continue;
            const Record* w = with == File::kNoType ? nullptr : f_.record(k, with);
            if ((pass == 0) != !w) continue;
            if (!w) {
                plain_[rep_1].push_back(rep_2);
                plain_[rep_2].push_back(rep_1);
                continue;
            }
            const uint32_t op = w->count >= 1 ? ref(f_.attribute(*w, 0)) : kUnresolved;
            const Record* t = op == kUnresolved ? nullptr : f_.record(op, idt);
            if (!t || t->count < 4) {
                problem(k, "a placed representation whose transformation is not an ITEM_DEFINED_TRANSFORMATION: left out");
                continue;
            }
            const uint32_t item_1 = ref(f_.attribute(*t, 2)), item_2 = ref(f_.attribute(*t, 3));
            // The occurrence's parent is the assembly whose definition relates
            // it; the child's representation holds the item placed. Exporters
            // write rep_1 as the child (the standard's reading), some the other
            // way round: the one holding item_1 is the child here.
            // The occurrence says which is which (its related definition is the
            // child's); without one, the standard's reading.
            uint32_t child = rep_1, parent = rep_2;
            auto occ = occurrence_of.find(k);
            if (occ != occurrence_of.end()) {
                const Record& n = f_.first_record(f_.instances[occ->second]);
                const uint32_t related = n.count >= 5 ? ref(f_.attribute(n, 4)) : kUnresolved;
                auto child_rep = rep_of_definition_.find(related);
                if (child_rep != rep_of_definition_.end() && same_shape(child_rep->second, rep_2) &&
                    !same_shape(child_rep->second, rep_1))
                    std::swap(child, parent);
            }
            // And each item belongs to one of the two (the one holding it).
            uint32_t child_item = item_1, parent_item = item_2;
            if (holds(parent, item_1) && !holds(parent, item_2)) std::swap(child_item, parent_item);
            const Eigen::Isometry3d in_parent = placement(parent, parent_item, k);
            const Eigen::Isometry3d in_child = placement(child, child_item, k);
            Child edge;
            edge.rep = child;
            edge.pose = in_parent * in_child.inverse();
            if (occ != occurrence_of.end()) {
                const Record& n = f_.first_record(f_.instances[occ->second]);
                // Its name, or its id where the name is blank (SolidWorks writes ' ').
                for (uint32_t a : {1u, 0u})
                    if (edge.occurrence.empty() && n.count > a && f_.attribute(n, a).kind == Kind::String)
                        edge.occurrence = trimmed(f_.text(f_.attribute(n, a)));
                if (edge.occurrence.empty()) edge.occurrence = "#" + std::to_string(f_.instances[occ->second].id);
            } else {
                edge.occurrence = "#" + std::to_string(f_.instances[k].id);
            }
            children_[parent].push_back(edge);
            is_child_.insert(child);
        }
        // Mapped items: the source representation placed at the target.
        const uint32_t map = f_.type_id("REPRESENTATION_MAP");
        for (const auto& [rep, items] : mapped_items_)
            for (uint32_t item : items) {
                const Record& m = f_.first_record(f_.instances[item]);
                if (m.count < 3) continue;
                const uint32_t source = ref(f_.attribute(m, 1)), target = ref(f_.attribute(m, 2));
                const Record* rm = source == kUnresolved ? nullptr : f_.record(source, map);
                if (!rm || rm->count < 2) continue;
                const uint32_t origin = ref(f_.attribute(*rm, 0)), mapped = ref(f_.attribute(*rm, 1));
                if (!context_.count(mapped)) continue;
                Child edge;
                edge.rep = mapped;
                edge.pose = placement(rep, target, item) * placement(mapped, origin, item).inverse();
                children_[rep].push_back(edge);
                is_child_.insert(mapped);
            }
    }

    // Whether two representations are one shape (the same, or plainly linked).
    bool same_shape(uint32_t a, uint32_t b) const {
        if (a == b) return true;
        auto link = plain_.find(a);
        return link != plain_.end() && std::find(link->second.begin(), link->second.end(), b) != link->second.end();
    }

    bool holds(uint32_t rep, uint32_t item) const {
        const Record& r = f_.first_record(f_.instances[rep]);
        const Value& items = f_.attribute(r, 1);
        for (uint32_t i = 0; i < uint32_t(items.count); ++i)
            if (ref(f_.element(items, i)) == item) return true;
        return false;
    }

    // An AXIS2_PLACEMENT_3D in the units of the representation it belongs to.
    Eigen::Isometry3d placement(uint32_t rep, uint32_t item, uint32_t at) {
        if (item == kUnresolved || !f_.record(item, f_.type_id("AXIS2_PLACEMENT_3D"))) {
            problem(at, "a transformation whose item is not an AXIS2_PLACEMENT_3D: taken as the identity");
            return Eigen::Isometry3d::Identity();
        }
        const uint32_t context = context_.count(rep) ? context_.at(rep) : kUnresolved;
        auto it = readers_.find(context);
        if (it == readers_.end()) {
            auto entry = std::make_unique<Entry>();
            entry->units = context == kUnresolved ? ContextUnits{} : context_units(f_, context, entry->problems);
            entry->reader = std::make_unique<GeometryReader>(f_, entry->units, entry->problems);
            it = readers_.emplace(context, std::move(entry)).first;
        }
        const Placement p = it->second->reader->placement(item);
        if (!p.origin.allFinite() || !p.x.allFinite() || !p.z.allFinite()) {
            problem(at, "a transformation whose placement does not resolve: taken as the identity");
            return Eigen::Isometry3d::Identity();
        }
        return motion(p);
    }

    // The representations no occurrence or mapped item places: the roots
    // (a plain link's partner of a child is not a root either).
    std::vector<uint32_t> roots() const {
        std::vector<uint32_t> out;
        std::set<uint32_t> covered;
        for (uint32_t c : is_child_) {
            covered.insert(c);
            auto link = plain_.find(c);
            if (link != plain_.end()) covered.insert(link->second.begin(), link->second.end());
        }
        std::set<uint32_t> seen;
        for (const auto& [rep, context] : context_) {
            (void)context;
            if (covered.count(rep) || seen.count(rep)) continue;
            // One root per group of plainly linked representations, and only
            // a group that holds or places something.
            std::vector<uint32_t> group = {rep};
            seen.insert(rep);
            for (size_t g = 0; g < group.size(); ++g) {
                auto link = plain_.find(group[g]);
                if (link == plain_.end()) continue;
                for (uint32_t other : link->second)
                    if (seen.insert(other).second) group.push_back(other);
            }
            // Where the file has products, a root is a product's shape (other
            // shape representations hold the same solids for validation
            // properties); without products, any that holds or places something.
            bool useful = false;
            for (uint32_t g : group)
                useful = useful || (product_.empty() ? solids_.count(g) || children_.count(g) : product_.count(g) > 0);
            if (useful) out.push_back(rep);
        }
        return out;
    }

    void walk(uint32_t rep, const Eigen::Isometry3d& pose, const std::string& occurrence, std::vector<uint32_t>& path) {
        if (path.size() > 64) {
            problem(rep, "assembly nesting deeper than 64: the occurrences below are left out");
            return;
        }
        // The representation and those plainly linked to it: one shape.
        std::vector<uint32_t> group = {rep};
        for (size_t g = 0; g < group.size(); ++g) {
            auto link = plain_.find(group[g]);
            if (link == plain_.end()) continue;
            for (uint32_t other : link->second)
                if (std::find(group.begin(), group.end(), other) == group.end()) group.push_back(other);
        }
        for (uint32_t g : group)
            if (std::find(path.begin(), path.end(), g) != path.end()) {
                problem(rep, "an assembly that contains itself: the repeated occurrence is left out");
                return;
            }
        path.insert(path.end(), group.begin(), group.end());
        std::string product;
        for (uint32_t g : group)
            if (product.empty()) product = product_of(g);
        for (uint32_t g : group) {
            auto s = solids_.find(g);
            if (s != solids_.end())
                for (uint32_t solid : s->second) out_.solids.push_back({solid, pose, product, occurrence});
        }
        for (uint32_t g : group) {
            auto c = children_.find(g);
            if (c == children_.end()) continue;
            for (const Child& child : c->second) {
                std::string next = occurrence;
                if (!child.occurrence.empty()) next += (next.empty() ? "" : "/") + child.occurrence;
                walk(child.rep, pose * child.pose, next, path);
            }
        }
        path.resize(path.size() - group.size());
    }

    struct Entry {
        ContextUnits units;
        std::vector<Problem> problems;
        std::unique_ptr<GeometryReader> reader;
    };

    const File& f_;
    const Brep& b_;
    Assembly out_;
    std::map<uint32_t, uint32_t> solid_of_;                   // solid instance -> Brep::solids index
    std::map<uint32_t, uint32_t> context_;                    // representation -> its context
    std::map<uint32_t, std::vector<uint32_t>> solids_;        // representation -> solids it holds
    std::map<uint32_t, uint32_t> holder_;                     // solid instance -> representation
    std::map<uint32_t, std::vector<uint32_t>> mapped_items_;  // representation -> its mapped items
    std::map<uint32_t, uint32_t> rep_of_definition_;
    std::map<uint32_t, std::string> product_;                 // representation -> product name
    std::map<uint32_t, std::vector<uint32_t>> plain_;         // representations of one shape
    std::map<uint32_t, std::vector<Child>> children_;
    std::set<uint32_t> is_child_;
    std::map<uint32_t, std::unique_ptr<Entry>> readers_;
};

}  // namespace

Assembly place_solids(const File& f, const Brep& b) { return AssemblyReader(f, b).run(); }

}  // namespace mbx_step
