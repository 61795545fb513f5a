// `mbx simulate` with contact from the description file, end to end through
// the CLI on the EMPS sample: the carriage (9.42 kg) slides under a gravity
// of 2 m/s^2 along its rail into a wall 1 cm ahead, a plane of the world, and
// must come to rest pressed into it by m g / k, in the fixed-step and the
// accurate mode.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <doctest/doctest.h>

#include "adapter_test_support.h"
#include "cli_support.h"

namespace MBX_UNITY_ID {

namespace {

const std::string kEmps = std::string(MBX_SAMPLES_DIR) + "/emps_axis/emps_axis.xml";

// The last row's value of column `name` in trajectory.csv.
double last_value(const std::string& csv, const std::string& name) {
    std::istringstream in(csv);
    std::string header, line, last;
    std::getline(in, header);
    while (std::getline(in, line))
        if (!line.empty()) last = line;
    std::istringstream h(header), row(last);
    std::string column, cell;
    while (std::getline(h, column, ',') && std::getline(row, cell, ','))
        if (column == name) return std::stod(cell);
    FAIL("no column " << name);
    return 0;
}

}  // namespace

TEST_CASE("cli simulate: the EMPS carriage runs into a wall of the description file and rests at m g / k") {
    const double mass = 9.42, g = 2, k = 1e5, radius = 0.02, gap = 0.01;
    atest::TempDir dir("mbx_cli_contact");
    // A ball on the carriage (its frame is at the world's (0, 0, 0.05)); the
    // wall's solid is x >= radius + gap: the plane's +z turned to -x.
    std::ofstream(dir.file("contact.xml"))
        << "<mechatronics version=\"1\">\n"
           "  <collision body=\"41\" shape=\"sphere\" radius=\"20\" unit=\"mm\"/>\n"
           "  <collision body=\"world\" shape=\"plane\" xyz=\"" << radius + gap << " 0 0.05\" rpy=\"0 -90 0\" unit=\"deg\"/>\n"
           "  <contact normal=\"spring_damper\" stiffness=\"1e5\" damping=\"" << 2 * std::sqrt(k * mass) << "\" mu=\"0.3\"/>\n"
           "</mechatronics>\n";
    for (const char* integrator : {"rk4", "accurate"}) {
        CAPTURE(integrator);
        const std::string out = dir.file(std::string("out_") + integrator);
        const atest::CliRun r = atest::run_cli(dir, "simulate '" + kEmps + "' --drives '" + dir.file("contact.xml") +
                                                        "' --gravity 2,0,0 --stop-time 1.5 --integrator " + integrator +
                                                        " -o '" + out + "'");
        INFO(r.err);
        REQUIRE(r.code == 0);
        CHECK(r.out.find("contact: 2 collision shapes") != std::string::npos);
        const std::string csv = atest::read_file(out + "/trajectory.csv");
        const double q = last_value(csv, "BED--CARRIAGE.q"), qd = last_value(csv, "BED--CARRIAGE.qd");
        const double depth = q - gap;
        MESSAGE(std::string(integrator) << ": the carriage presses into the wall by " << depth << " m (m g / k = " << mass * g / k << ")");
        CHECK(std::abs(depth / (mass * g / k) - 1) < 0.01);
        CHECK(std::abs(qd) < 1e-6);
    }
}
}  // namespace MBX_UNITY_ID
