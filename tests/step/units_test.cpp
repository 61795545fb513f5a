// Units per representation context: SI prefixes, conversion-based units
// (inch, degree, Onshape's 'METRE'), the uncertainty, and the defects.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "host_adapters/step/part21.h"
#include "host_adapters/step/units.h"
#include "tests/common/near.h"
#include "tests/common/shared_data.h"
#include "tests/step/step_test_support.h"

namespace MBX_UNITY_ID {

using namespace mbx_step;

namespace {

using step_test::wrap;

// A context (#100) whose units are `units` (instances #1.. given in `data`).
ContextUnits units_of(const std::string& data, const std::string& units, std::vector<Problem>& problems) {
    const File f = read_part21(
        wrap(data + "#100=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#90))"
                    "GLOBAL_UNIT_ASSIGNED_CONTEXT((" + units + "))REPRESENTATION_CONTEXT('',''));\n"),
        "u.stp");
    return context_units(f, f.index_of(100), problems);
}

const std::string kSi =
    "#1=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n#2=(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));\n"
    "#3=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT($,.METRE.));\n";

}  // namespace

TEST_CASE("step units: millimetres, metres, inches and Onshape's 'METRE' give one length in metres") {
    std::vector<Problem> p;
    const std::string uncertainty_mm = "#90=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-05),#1,'distance_accuracy_value','');\n";
    const ContextUnits mm = units_of(kSi + uncertainty_mm, "#1,#2", p);
    CHECK(mm.length == mbx_test::relative(1e-3, 1e-15));
    CHECK(mm.length_name == "MILLI METRE");
    CHECK(mm.uncertainty == mbx_test::relative(1e-5, 1e-12));
    const ContextUnits m = units_of(kSi + uncertainty_mm, "#3,#2", p);
    CHECK(m.length == 1.0);
    CHECK(m.uncertainty == mbx_test::relative(1e-8, 1e-12));  // 1e-5 mm in metres
    const ContextUnits inch = units_of(
        kSi + uncertainty_mm + "#4=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#1);\n"
                               "#5=(CONVERSION_BASED_UNIT('INCH',#4)LENGTH_UNIT()NAMED_UNIT(#6));\n#6=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n",
        "#5,#2", p);
    CHECK(inch.length == mbx_test::relative(0.0254, 1e-15));
    CHECK(inch.length_name == "INCH");
    CHECK(inch.uncertainty == mbx_test::relative(1e-5 / 25.4, 1e-12));
    const ContextUnits onshape = units_of(
        kSi + uncertainty_mm + "#4=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.),#3);\n"
                               "#5=(CONVERSION_BASED_UNIT('METRE',#4)LENGTH_UNIT()NAMED_UNIT(#6));\n#6=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n",
        "#5,#2", p);
    CHECK(onshape.length == 1.0);
    CHECK(p.empty());
}

TEST_CASE("step units: a plane angle in degrees reads as its radians") {
    std::vector<Problem> p;
    const ContextUnits deg = units_of(
        kSi + "#4=PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(0.0174532925199433),#2);\n"
              "#5=(CONVERSION_BASED_UNIT('DEGREE',#4)NAMED_UNIT(#6)PLANE_ANGLE_UNIT());\n#6=DIMENSIONAL_EXPONENTS(0.,0.,0.,0.,0.,0.,0.);\n",
        "#1,#5", p);
    CHECK(deg.plane_angle == mbx_test::relative(M_PI / 180, 1e-14));
    CHECK(deg.angle_name == "DEGREE");
    CHECK(deg.length == mbx_test::relative(1e-3, 1e-15));
    CHECK(std::isnan(deg.uncertainty));  // #90 is not in this file: no uncertainty, and no fault of the units
    CHECK(p.empty());
}

TEST_CASE("step units: a context without a length unit, a conversion that loops or dangles: problems, defaults kept") {
    std::vector<Problem> p;
    const ContextUnits none = units_of(kSi, "#2", p);
    CHECK(none.length == mbx_test::relative(1e-3, 1e-15));
    REQUIRE(p.size() == 1);
    CHECK(p[0].entity == 100);
    CHECK(p[0].message.find("no length unit") != std::string::npos);
    p.clear();
    const ContextUnits loop = units_of(
        kSi + "#4=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(2.),#5);\n#5=(CONVERSION_BASED_UNIT('LOOP',#4)LENGTH_UNIT()NAMED_UNIT(*));\n",
        "#5,#2", p);
    CHECK(loop.length == mbx_test::relative(1e-3, 1e-15));
    REQUIRE(!p.empty());
    CHECK(p[0].entity == 5);
    CHECK(p[0].message.find("'LOOP'") != std::string::npos);
    p.clear();
    const ContextUnits dangling = units_of(kSi + "#5=(CONVERSION_BASED_UNIT('FOOT',#44)LENGTH_UNIT()NAMED_UNIT(*));\n", "#5,#2", p);
    CHECK(dangling.length == mbx_test::relative(1e-3, 1e-15));
    REQUIRE(!p.empty());
    CHECK(p[0].message.find("'FOOT' does not resolve") != std::string::npos);
}

TEST_CASE("step units: every context of the real files is in millimetres and radians, with the uncertainty written") {
    for (const std::string& path : {mbx_test::shared_data("step/dfki_double_pendulum/lever_200.STEP"),
                                    mbx_test::shared_data("step/dfki_double_pendulum/double_pendulum.STEP"),
                                    mbx_test::shared_data("step/nist_ctc_02/nist_ctc_02_asme1_ap242-1.stp")}) {
        CAPTURE(path);
        const File f = read_part21_file(path);
        const uint32_t units = f.type_id("GLOBAL_UNIT_ASSIGNED_CONTEXT");
        int contexts = 0;
        for (uint32_t k = 0; k < f.instances.size(); ++k) {
            if (!f.record(k, units)) continue;
            ++contexts;
            std::vector<Problem> p;
            const ContextUnits u = context_units(f, k, p);
            CHECK(p.empty());
            CHECK(u.length == mbx_test::relative(1e-3, 1e-15));
            CHECK(u.plane_angle == 1.0);
            CHECK(u.uncertainty > 0);
            CHECK(u.uncertainty < 0.01);
        }
        CHECK(contexts >= 1);
    }
}

}  // namespace MBX_UNITY_ID
