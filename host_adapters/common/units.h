// Unit strings of CAD exports to SI factors, one quantity at a time: exports
// mix systems freely (lengths in mm, inertia in kg*m^2, FOURBAR in lbm and
// lbm*in^2), so every value is converted with its own unit string.
#pragma once
#include <stdexcept>
#include <string>
#include <string_view>

namespace mbx_files {

enum class Quantity { length, mass, area, volume, inertia };

const char* quantity_name(Quantity quantity);  // "length", ..., "inertia"

// The unit string cannot be read, or measures another quantity. The message
// names the string; readers add the file and line.
class UnitError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// SI factor of `unit` for `quantity`: value_in_SI = value * factor.
// Accepts m, cm, mm, in, ft and kg, g, lbm, slug (with the spelled-out
// forms "meter", "millimeter", "inch", "foot", "kilogram", ...), and
// products of powers of them: "kg*m^2", "lbm*in^2", "slug*ft^2", "g*mm^2",
// "mm^3", "in^2". Case-insensitive; surrounding whitespace is ignored.
// Throws UnitError for anything else.
double unit_to_si(std::string_view unit, Quantity quantity);

}  // namespace mbx_files
