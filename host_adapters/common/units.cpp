#include "units.h"

#include <cctype>
#include <charconv>

#include "numbers.h"
#include "host_adapters/common/text.h"

namespace mbx_files {
namespace {

struct BaseUnit {
    const char* names[6];  // spellings; unused slots are null
    double factor;
    int mass_power;  // 1 for masses, 0 for lengths
};

// Exact definitions: the inch and the pound by the 1959 agreement, the slug as
// one lbf*s^2/ft (standard gravity 9.80665 m/s^2).
constexpr BaseUnit kUnits[] = {
    {{"m", "meter", "meters", "metre", "metres"}, 1.0, 0},
    {{"cm", "centimeter", "centimeters", "centimetre", "centimetres"}, 0.01, 0},
    {{"mm", "millimeter", "millimeters", "millimetre", "millimetres"}, 0.001, 0},
    {{"in", "inch", "inches"}, 0.0254, 0},
    {{"ft", "foot", "feet"}, 0.3048, 0},
    {{"kg", "kilogram", "kilograms"}, 1.0, 1},
    {{"g", "gram", "grams"}, 0.001, 1},
    {{"lbm", "lb", "pound", "pounds"}, 0.45359237, 1},
    {{"slug", "slugs"}, 14.59390294, 1},
};

const BaseUnit* find_unit(std::string_view name) {
    for (const BaseUnit& u : kUnits)
        for (const char* spelling : u.names)
            if (spelling && name == spelling) return &u;
    return nullptr;
}

struct Dimension {
    int mass = 0, length = 0;
};

Dimension expected(Quantity q) {
    switch (q) {
        case Quantity::length:
            return {0, 1};
        case Quantity::mass:
            return {1, 0};
        case Quantity::area:
            return {0, 2};
        case Quantity::volume:
            return {0, 3};
        case Quantity::inertia:
            return {1, 2};
    }
    return {};
}

}  // namespace

const char* quantity_name(Quantity quantity) {
    switch (quantity) {
        case Quantity::length:
            return "length";
        case Quantity::mass:
            return "mass";
        case Quantity::area:
            return "area";
        case Quantity::volume:
            return "volume";
        case Quantity::inertia:
            return "inertia";
    }
    return "?";
}

double unit_to_si(std::string_view unit, Quantity quantity) {
    const std::string quoted = "'" + std::string(unit) + "'";
    const std::string text = lower_case(trim(unit));
    if (text.empty()) throw UnitError("empty " + std::string(quantity_name(quantity)) + " unit");
    double factor = 1.0;
    Dimension dim;
    std::string_view rest = text;
    while (true) {
        const size_t star = rest.find('*');
        std::string_view term = trim(rest.substr(0, star));
        int power = 1;
        const size_t caret = term.find('^');
        if (caret != std::string_view::npos) {
            std::string_view exponent = trim(term.substr(caret + 1));
            if (!exponent.empty() && exponent[0] == '+') exponent.remove_prefix(1);
            const auto [ptr, ec] = std::from_chars(exponent.data(), exponent.data() + exponent.size(), power);
            if (ec != std::errc() || ptr != exponent.data() + exponent.size() || exponent.empty() || power < -4 ||
                power > 4)
                throw UnitError("unit " + quoted + " has an unreadable exponent");
            term = trim(term.substr(0, caret));
        }
        const BaseUnit* base = find_unit(term);
        if (!base) throw UnitError("unknown unit " + quoted + " (for a " + quantity_name(quantity) + ")");
        for (int k = 0; k < (power < 0 ? -power : power); ++k)
            factor = power < 0 ? factor / base->factor : factor * base->factor;
        (base->mass_power ? dim.mass : dim.length) += power;
        if (star == std::string_view::npos) break;
        rest.remove_prefix(star + 1);
    }
    const Dimension want = expected(quantity);
    if (dim.mass != want.mass || dim.length != want.length)
        throw UnitError("unit " + quoted + " is not a unit of " + std::string(quantity_name(quantity)));
    return factor;
}

}  // namespace mbx_files
