// Unit strings and locale-independent numbers.
#include <clocale>
#include <string>

#include <doctest/doctest.h>

#include "host_adapters/common/numbers.h"
#include "host_adapters/common/units.h"
#include "tests/common/near.h"
#include "tests/common/skip.h"

namespace MBX_UNITY_ID {

using mbx_files::parse_number;
using mbx_files::parse_number_list;
using mbx_files::Quantity;
using mbx_files::unit_to_si;
using mbx_files::UnitError;

TEST_CASE("units: every length unit and its spellings") {
    CHECK(unit_to_si("m", Quantity::length) == 1.0);
    CHECK(unit_to_si("meter", Quantity::length) == 1.0);
    CHECK(unit_to_si("metre", Quantity::length) == 1.0);
    CHECK(unit_to_si("cm", Quantity::length) == mbx_test::relative(0.01, 1e-15));
    CHECK(unit_to_si("mm", Quantity::length) == mbx_test::relative(0.001, 1e-15));
    CHECK(unit_to_si("millimeter", Quantity::length) == mbx_test::relative(0.001, 1e-15));
    CHECK(unit_to_si("in", Quantity::length) == mbx_test::relative(0.0254, 1e-15));
    CHECK(unit_to_si("inch", Quantity::length) == mbx_test::relative(0.0254, 1e-15));
    CHECK(unit_to_si("ft", Quantity::length) == mbx_test::relative(0.3048, 1e-15));
    CHECK(unit_to_si(" MM ", Quantity::length) == mbx_test::relative(0.001, 1e-15));
}

TEST_CASE("units: every mass unit") {
    CHECK(unit_to_si("kg", Quantity::mass) == 1.0);
    CHECK(unit_to_si("g", Quantity::mass) == mbx_test::relative(0.001, 1e-15));
    CHECK(unit_to_si("lbm", Quantity::mass) == mbx_test::relative(0.45359237, 1e-15));
    CHECK(unit_to_si("slug", Quantity::mass) == mbx_test::relative(14.59390294, 1e-15));
}

TEST_CASE("units: composites for inertia, area and volume") {
    CHECK(unit_to_si("kg*m^2", Quantity::inertia) == 1.0);
    CHECK(unit_to_si("lbm*in^2", Quantity::inertia) == mbx_test::relative(0.45359237 * 0.0254 * 0.0254, 1e-14));
    CHECK(unit_to_si("slug*ft^2", Quantity::inertia) == mbx_test::relative(14.59390294 * 0.3048 * 0.3048, 1e-14));
    CHECK(unit_to_si("g*mm^2", Quantity::inertia) == mbx_test::relative(1e-9, 1e-14));
    CHECK(unit_to_si("slug*in^2", Quantity::inertia) == mbx_test::relative(0.009415402, 1e-6));
    CHECK(unit_to_si("m^2*kg", Quantity::inertia) == 1.0);
    CHECK(unit_to_si("mm^3", Quantity::volume) == mbx_test::relative(1e-9, 1e-14));
    CHECK(unit_to_si("in^3", Quantity::volume) == mbx_test::relative(0.0254 * 0.0254 * 0.0254, 1e-14));
    CHECK(unit_to_si("in^2", Quantity::area) == mbx_test::relative(0.0254 * 0.0254, 1e-14));
    CHECK(unit_to_si("mm^2", Quantity::area) == mbx_test::relative(1e-6, 1e-14));
}

TEST_CASE("units: unknown or mismatched units name the string") {
    auto message = [](const char* unit, Quantity q) -> std::string {
        try {
            unit_to_si(unit, q);
        } catch (const UnitError& e) {
            return e.what();
        }
        return "no error";
    };
    CHECK(message("furlong", Quantity::length).find("'furlong'") != std::string::npos);
    CHECK(message("kg*furlong^2", Quantity::inertia).find("'kg*furlong^2'") != std::string::npos);
    CHECK(message("kg", Quantity::length).find("not a unit of length") != std::string::npos);
    CHECK(message("kg*m", Quantity::inertia).find("not a unit of inertia") != std::string::npos);
    CHECK(message("mm^x", Quantity::volume).find("exponent") != std::string::npos);
    CHECK(message("", Quantity::mass).find("empty") != std::string::npos);
    CHECK_THROWS_AS(unit_to_si("kg*", Quantity::mass), UnitError);
}

TEST_CASE("numbers: Windows exponents, signs and garbage") {
    CHECK(*parse_number("1.5e-006") == 1.5e-6);
    CHECK(*parse_number("-9.03775e-016") == -9.03775e-16);
    CHECK(*parse_number("1.2401e+007") == 1.2401e7);
    CHECK(*parse_number(" +2.5 ") == 2.5);
    CHECK(*parse_number("-0") == 0.0);
    CHECK_FALSE(parse_number(""));
    CHECK_FALSE(parse_number("1,5"));
    CHECK_FALSE(parse_number("1.5x"));
    CHECK_FALSE(parse_number("nan"));
    CHECK_FALSE(parse_number("inf"));
    CHECK_FALSE(parse_number("1e999"));
    CHECK_FALSE(parse_number("+-1"));
    double v[3];
    CHECK(parse_number_list("-122.558,14.7511,2.5e-006", v, 3));
    CHECK(v[0] == -122.558);
    CHECK(v[2] == 2.5e-6);
    CHECK(parse_number_list(" 1 , 2 ,3 ", v, 3));
    CHECK_FALSE(parse_number_list("1,2", v, 3));
    CHECK_FALSE(parse_number_list("1,2,3,4", v, 3));
    CHECK_FALSE(parse_number_list("1,,3", v, 3));
}

TEST_CASE("numbers: a German locale does not change how numbers read") {
    const char* previous = std::setlocale(LC_ALL, nullptr);
    const std::string saved = previous ? previous : "C";
    const char* german = nullptr;
    for (const char* name : {"de_DE.UTF-8", "de_DE.utf8", "de_DE"})
        if (std::setlocale(LC_ALL, name)) {
            german = name;
            break;
        }
    if (!german) MBX_SKIP_PART("no de_DE locale installed: checked under the current locale only");
    CHECK(*parse_number("1.5e-006") == 1.5e-6);
    CHECK(*parse_number("0.70323") == 0.70323);
    CHECK_FALSE(parse_number("0,70323"));
    double v[3];
    CHECK(parse_number_list("1.25,-2.5,3.75", v, 3));
    CHECK(v[0] == 1.25);
    CHECK(unit_to_si("mm", Quantity::length) == 0.001);
    std::setlocale(LC_ALL, saved.c_str());
}
}  // namespace MBX_UNITY_ID
