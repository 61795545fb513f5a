// The object library (thesis 2.8.1): the bundled library reads cleanly and
// gives the derived motor constants worked out by hand; every kind of bad
// entry is an error naming file, line and object.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "core/mechatronics/drive_quantities.h"
#include "core/mechatronics/object_library.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// A one-class library around `objects` (and extra parameter declarations).
std::string library(const std::string& objects, const std::string& extra_decls = "") {
    return "<object_library>\n"                                                               // line 1
           "<object_folder name=\"Electromechanical\">\n"                                     // 2
           "<object_class name=\"DC\" kind=\"dc_motor\" modelica=\"X.DC\">\n"                  // 3
           "<parameter name=\"J_Rotor\" type=\"Real\" unit=\"kg.m2\" lower=\"0\"/>\n"          // 4
           "<parameter name=\"VaNominal\" type=\"Real\" unit=\"V\" lower=\"0\" upper=\"60\"/>\n" // 5
           "<parameter name=\"IaNominal\" type=\"Real\" unit=\"A\"/>\n"                        // 6
           "<parameter name=\"rpmNominal\" type=\"Real\" unit=\"rpm\"/>\n"                     // 7
           "<parameter name=\"Ra\" type=\"Real\" unit=\"Ohm\"/>\n" +                           // 8
           extra_decls + objects + "</object_class>\n</object_folder>\n</object_library>\n";
}

std::string motor(const std::string& id, const std::string& va = "8", const std::string& extra = "") {
    return "<object name=\"M\" ID=\"" + id +
           "\">\n"
           "<parameter name=\"J_Rotor\" value=\"1.2E-7\"/>\n"
           "<parameter name=\"VaNominal\" value=\"" + va + "\"/>\n"
           "<parameter name=\"IaNominal\" value=\"1.2\"/>\n"
           "<parameter name=\"rpmNominal\" value=\"8200\"/>\n"
           "<parameter name=\"Ra\" value=\"0.78\"/>\n" + extra + "</object>\n";
}

const std::string kId = "628F99AAAA7444D5A2A36A6FA1175594";

LibraryError only_error(const std::string& text) {
    ObjectLibrary lib;
    lib.load_text(text, "lib.xml");
    REQUIRE(lib.errors().size() == 1);
    return lib.errors().front();
}

}  // namespace

TEST_CASE("object library: the bundled library reads without errors and holds the thesis's Kondo motor") {
    ObjectLibrary lib;
    lib.load_file(std::string(MBX_SOURCE_DIR) + "/samples/library/mbx_object_library.xml");
    for (const LibraryError& e : lib.errors()) MESSAGE(e.text());
    REQUIRE(lib.ok());
    const ObjectLibrary::Found kondo = lib.find("628f99aaaa7444d5a2a36a6fa1175594");  // IDs ignore case
    REQUIRE(kondo.object);
    CHECK(kondo.object->name == "KRS-784ICS");
    CHECK(kondo.cls->modelica == "Modelica.Electrical.Machines.BasicMachines.DCMachines.DC_PermanentMagnet");
    CHECK(*lib.value_in_si(kondo, "rpmNominal") == mbx_test::relative(8200 * 2 * M_PI / 60, 1e-6));

    // By hand: k = (8 V - 0.78 Ohm * 1.2 A) / (8200 rpm = 858.70 rad/s) = 8.2264e-3 N m/A;
    // stall torque k * 8 / 0.78 = 0.084373 N m; no-load speed 8 / k = 972.48 rad/s;
    // rotor inertia through the 251:1 gear 1.2e-7 * 251^2 = 7.5601e-3 kg m^2.
    std::string error;
    const auto c = dc_motor_constants(lib, kondo, error);
    REQUIRE_MESSAGE(c, error);
    CHECK(c->torque_constant == mbx_test::relative(8.2264e-3, 1e-4));
    CHECK(c->stall_torque == mbx_test::relative(0.084373, 1e-4));
    CHECK(c->no_load_speed == mbx_test::relative(972.48, 1e-4));
    CHECK(c->reflected_inertia == mbx_test::relative(7.56012e-3, 1e-5));

    // The ball-screw-class motor: datasheet torque constant 60.3 mN m/A.
    const auto re40 = dc_motor_constants(lib, lib.find("5B0E3C1F7A2D4E8C9F61A4B2C3D5E7F9"), error);
    REQUIRE(re40);
    CHECK(re40->torque_constant == mbx_test::relative(0.0603, 0.02));

    // Ball screw 5 mm lead: 2 pi / 0.005 m = 1256.6 rad/m; its 4e-5 kg m^2 acts like 63.2 kg on the carriage.
    const auto screw = transmission_constants(lib, lib.find("3E8F2A1B6C4D4E9F8A7B0C1D2E3F4A5B"), error);
    REQUIRE(screw);
    CHECK(screw->linear);
    CHECK(screw->ratio == mbx_test::relative(1256.637, 1e-6));
    CHECK(screw->reflected_inertia == mbx_test::relative(63.165, 1e-4));
}

TEST_CASE("object library: a valid object with its values in the declared units") {
    ObjectLibrary lib;
    lib.load_text(library(motor(kId)), "lib.xml");
    REQUIRE(lib.ok());
    REQUIRE(lib.folders().size() == 1);
    REQUIRE(lib.folders()[0].classes[0].objects.size() == 1);
    CHECK(lib.folders()[0].classes[0].objects[0].line == 9);
}

TEST_CASE("object library: unknown parameter, naming file, line and object") {
    const LibraryError e = only_error(library(motor(kId, "8", "<parameter name=\"Kt\" value=\"1\"/>\n")));
    CHECK(e.file == "lib.xml");
    CHECK(e.line == 15);
    CHECK(e.object == "DC/M");
    CHECK(e.message.find("unknown parameter 'Kt'") != std::string::npos);
    CHECK(e.text().rfind("lib.xml:15: DC/M: ", 0) == 0);
}

TEST_CASE("object library: missing value") {
    std::string text = library(motor(kId));
    text.replace(text.find("<parameter name=\"Ra\" value=\"0.78\"/>\n"), 36, "");
    const LibraryError e = only_error(text);
    CHECK(e.line == 9);
    CHECK(e.message.find("missing value for parameter 'Ra'") != std::string::npos);
}

TEST_CASE("object library: value out of bounds, and a value that is no number") {
    LibraryError e = only_error(library(motor(kId, "72")));
    CHECK(e.line == 11);
    CHECK(e.message.find("'VaNominal' = 72 V is outside [0, 60]") != std::string::npos);
    e = only_error(library(motor(kId, "8 V")));
    CHECK(e.message.find("not a valid Real") != std::string::npos);
}

TEST_CASE("object library: duplicate ID, also across files, and malformed IDs") {
    ObjectLibrary lib;
    lib.load_text(library(motor(kId)), "a.xml");
    std::string other_class = library(motor(kId));
    other_class.replace(other_class.find("name=\"DC\""), 9, "name=\"DC2\"");
    lib.load_text(other_class, "b.xml");
    REQUIRE(lib.errors().size() == 1);
    CHECK(lib.errors()[0].file == "b.xml");
    CHECK(lib.errors()[0].object == "DC2/M");
    CHECK(lib.errors()[0].message.find("duplicate ID " + kId + " (first used at a.xml:9)") != std::string::npos);
    // Loading the same class again is refused as a whole.
    lib.load_text(library(motor(kId)), "c.xml");
    CHECK(lib.errors().back().message.find("class declared twice") != std::string::npos);

    ObjectLibrary same;
    same.load_text(library(motor(kId) + motor(kId)), "lib.xml");
    REQUIRE(same.errors().size() == 1);
    CHECK(same.errors()[0].line == 16);
    CHECK(same.errors()[0].message.find("duplicate ID " + kId + " (first used at lib.xml:9)") != std::string::npos);

    CHECK(only_error(library(motor("628F99AA"))).message.find("not 32 hexadecimal digits") != std::string::npos);
    CHECK(only_error(library(motor("G28F99AAAA7444D5A2A36A6FA1175594"))).message.find("not 32 hex") !=
          std::string::npos);
}

TEST_CASE("object library: bad unit, bad type, bad bounds in a class declaration") {
    LibraryError e = only_error(library(motor(kId), "<parameter name=\"x\" type=\"Real\" unit=\"furlong\"/>\n"));
    CHECK(e.line == 9);
    CHECK(e.object == "DC");
    CHECK(e.message.find("unknown unit 'furlong'") != std::string::npos);
    e = only_error(library(motor(kId), "<parameter name=\"x\" type=\"Complex\"/>\n"));
    CHECK(e.message.find("unknown type 'Complex'") != std::string::npos);
    e = only_error(library(motor(kId), "<parameter name=\"x\" lower=\"2\" upper=\"1\"/>\n"));
    CHECK(e.message.find("lower bound above upper bound") != std::string::npos);
    e = only_error(library(motor(kId), "<parameter name=\"Ra\"/>\n"));
    CHECK(e.message.find("'Ra' declared twice") != std::string::npos);
}

TEST_CASE("object library: unreadable files are errors, never crashes") {
    ObjectLibrary lib;
    lib.load_text("<object_library><object_folder name=\"x\">", "broken.xml");
    REQUIRE(lib.errors().size() == 1);
    CHECK(lib.errors()[0].message.find("not well-formed XML") != std::string::npos);
    ObjectLibrary other;
    other.load_text("<library/>", "wrong.xml");
    CHECK(other.errors().at(0).message.find("<object_library>") != std::string::npos);
    ObjectLibrary missing;
    missing.load_file("/nonexistent/lib.xml");
    CHECK(missing.errors().at(0).message.find("cannot open") != std::string::npos);
}

TEST_CASE("object library: a motor whose nominal values allow no back-EMF is refused with a reason") {
    ObjectLibrary lib;
    lib.load_text(library(motor(kId, "0.5")), "lib.xml");  // 0.5 V < Ra * Ia = 0.936 V
    REQUIRE(lib.ok());
    std::string error;
    CHECK_FALSE(dc_motor_constants(lib, lib.find(kId), error));
    CHECK(error.find("back-EMF") != std::string::npos);
}
}  // namespace MBX_UNITY_ID
