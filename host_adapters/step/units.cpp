#include "host_adapters/step/units.h"

#include <cstring>

namespace mbx_step {

namespace {

double prefix_factor(std::string_view prefix) {
    static const struct {
        const char* name;
        double factor;
    } prefixes[] = {{"EXA", 1e18},   {"PETA", 1e15}, {"TERA", 1e12}, {"GIGA", 1e9},   {"MEGA", 1e6},   {"KILO", 1e3},
                    {"HECTO", 1e2},  {"DECA", 1e1},  {"DECI", 1e-1}, {"CENTI", 1e-2}, {"MILLI", 1e-3}, {"MICRO", 1e-6},
                    {"NANO", 1e-9},  {"PICO", 1e-12}, {"FEMTO", 1e-15}, {"ATTO", 1e-18}};
    for (const auto& p : prefixes)
        if (prefix == p.name) return p.factor;
    return NAN;
}

enum class Quantity { Length, PlaneAngle, Other };

struct Unit {
    Quantity quantity = Quantity::Other;
    double factor = NAN;  // SI units per this unit
    std::string name;
};

// A typed or plain number (LENGTH_MEASURE(25.4), 25.4).
double number_of(const File& f, const Value& v) {
    const Value& x = v.kind == Kind::Typed ? f.values[v.a] : v;
    if (x.kind == Kind::Real) return x.real;
    if (x.kind == Kind::Integer) return double(x.integer);
    return NAN;
}

class UnitReader {
public:
    UnitReader(const File& f, std::vector<Problem>& problems) : f_(f), problems_(problems) {
        length_unit_ = f.type_id("LENGTH_UNIT");
        angle_unit_ = f.type_id("PLANE_ANGLE_UNIT");
        si_unit_ = f.type_id("SI_UNIT");
        conversion_ = f.type_id("CONVERSION_BASED_UNIT");
    }

    // The unit at instance index `k`, following conversion chains at most a
    // few deep (a cycle is a defect, not a hang).
    Unit unit(uint32_t k, int depth = 0) {
        Unit u;
        if (k == kUnresolved || k >= f_.instances.size()) return u;
        const Instance& in = f_.instances[k];
        if (f_.record(in, length_unit_)) u.quantity = Quantity::Length;
        if (f_.record(in, angle_unit_)) u.quantity = Quantity::PlaneAngle;
        if (const Record* si = f_.record(in, si_unit_); si && si->count >= 2) {
            const Value& prefix = f_.attribute(*si, 0);
            const Value& name = f_.attribute(*si, 1);
            const double scale = prefix.kind == Kind::Enumeration ? prefix_factor(f_.text(prefix)) : 1.0;
            if (name.kind == Kind::Enumeration) {
                u.name = (prefix.kind == Kind::Enumeration ? std::string(f_.text(prefix)) + " " : "") + std::string(f_.text(name));
                if (f_.text(name) == "METRE" || f_.text(name) == "RADIAN" || f_.text(name) == "STERADIAN") u.factor = scale;
            }
            if (std::isnan(u.factor)) problem(in, "a unit mbx cannot scale: SI_UNIT " + u.name);
            return u;
        }
        if (const Record* c = f_.record(in, conversion_); c && c->count >= 2) {
            if (f_.attribute(*c, 0).kind == Kind::String) u.name = std::string(f_.text(f_.attribute(*c, 0)));
            const Value& measure = f_.attribute(*c, 1);
            if (depth > 8 || measure.kind != Kind::Reference || measure.a == kUnresolved) {
                problem(in, "the conversion of unit '" + u.name + "' does not resolve");
                return u;
            }
            // MEASURE_WITH_UNIT (or a LENGTH_/PLANE_ANGLE_ subtype): value, unit.
            const Instance& m = f_.instances[measure.a];
            const Record& r = f_.first_record(m);
            if (m.record_count != 1 || r.count < 2 || f_.attribute(r, 1).kind != Kind::Reference) {
                problem(in, "the conversion of unit '" + u.name + "' is not a measure with a unit");
                return u;
            }
            const double value = number_of(f_, f_.attribute(r, 0));
            const Unit base = unit(f_.attribute(r, 1).a, depth + 1);
            u.factor = value * base.factor;
            if (u.quantity == Quantity::Other) u.quantity = base.quantity;
            if (!(std::isfinite(u.factor) && u.factor > 0)) {
                problem(in, "the conversion of unit '" + u.name + "' gives no positive factor");
                u.factor = NAN;
            }
            return u;
        }
        return u;
    }

private:
    void problem(const Instance& in, std::string message) { problems_.push_back({int(in.line), in.id, std::move(message)}); }

    const File& f_;
    std::vector<Problem>& problems_;
    uint32_t length_unit_, angle_unit_, si_unit_, conversion_;
};

}  // namespace

ContextUnits context_units(const File& f, uint32_t context, std::vector<Problem>& problems) {
    ContextUnits out;
    if (context == kUnresolved || context >= f.instances.size()) return out;
    const Instance& in = f.instances[context];
    UnitReader reader(f, problems);
    bool has_length = false;
    if (const Record* units = f.record(in, f.type_id("GLOBAL_UNIT_ASSIGNED_CONTEXT")); units && units->count >= 1) {
        const Value& list = f.attribute(*units, 0);
        for (uint32_t k = 0; list.kind == Kind::List && k < uint32_t(list.count); ++k) {
            const Value& ref = f.element(list, k);
            if (ref.kind != Kind::Reference) continue;
            const Unit u = reader.unit(ref.a);
            if (u.quantity == Quantity::Length && std::isfinite(u.factor)) {
                out.length = u.factor;
                out.length_name = u.name;
                has_length = true;
            } else if (u.quantity == Quantity::PlaneAngle && std::isfinite(u.factor)) {
                out.plane_angle = u.factor;
                out.angle_name = u.name;
            }
        }
    }
    if (!has_length)
        problems.push_back({int(in.line), in.id, "the representation context gives no length unit: read as millimetres"});
    if (const Record* u = f.record(in, f.type_id("GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT")); u && u->count >= 1) {
        const Value& list = f.attribute(*u, 0);
        for (uint32_t k = 0; list.kind == Kind::List && k < uint32_t(list.count); ++k) {
            const Value& ref = f.element(list, k);
            if (ref.kind != Kind::Reference || ref.a == kUnresolved) continue;
            const Record& m = f.first_record(f.instances[ref.a]);
            if (m.count < 2 || f.attribute(m, 1).kind != Kind::Reference) continue;
            const Unit unit = reader.unit(f.attribute(m, 1).a);
            const double value = number_of(f, f.attribute(m, 0));
            if (unit.quantity == Quantity::Length && std::isfinite(unit.factor) && std::isfinite(value) && value > 0) {
                const double metres = value * unit.factor;
                if (std::isnan(out.uncertainty) || metres / out.length < out.uncertainty) out.uncertainty = metres / out.length;
            }
        }
    }
    return out;
}

}  // namespace mbx_step
