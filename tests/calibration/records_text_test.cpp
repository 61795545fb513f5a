// read_csv_text: the CSV reader on text in memory (what fuzz/fuzz_csv drives)
// must read exactly what read_csv reads from the file, and name the path it is
// given in its errors.
#include <doctest/doctest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "calibration/records/records.h"
#include "core/finding.h"
#include "tests/common/skip.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx::calibration;

TEST_CASE("read_csv_text reads what read_csv reads from the file, errors naming the given path") {
    const std::string path = mbx_test::shared_data("measured/emps/emps_train.csv");
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        MBX_SKIP("no " << path);
    }
    std::ostringstream text;
    text << file.rdbuf();
    const Table from_file = read_csv(path);
    const Table from_text = read_csv_text(text.str(), path);
    CHECK(from_text.header == from_file.header);
    CHECK(from_text.columns == from_file.columns);
    REQUIRE(from_text.column("t_s") == 0);
    CHECK(from_text.columns[0].size() > 1000);

    const Table small = read_csv_text("t, q\n0, +1.5\r\n\n0.001,2e-3\n", "mem.csv");
    CHECK(small.header == std::vector<std::string>{"t", "q"});
    CHECK(small.columns[1] == std::vector<double>{1.5, 2e-3});
    try {
        read_csv_text("t,q\n0,1\n0.001,inf\n", "mem.csv");
        FAIL("accepted a non-finite cell");
    } catch (const mbx::Error& e) {
        CHECK(e.file() == "mem.csv");
        CHECK(e.line() == 3);
    }
    CHECK_THROWS_AS(read_csv_text("", "empty.csv"), mbx::Error);
}

TEST_CASE("read_csv_text: a UTF-8 byte-order mark before the header (a spreadsheet's CSV UTF-8) is not part of the first name") {
    const Table t = read_csv_text("\xEF\xBB\xBFt,q\n0,1\n0.001,2\n", "bom.csv");
    CHECK(t.column("t") == 0);
    CHECK(t.column("q") == 1);
    CHECK(t.columns[0] == std::vector<double>{0, 0.001});
    // Only at the start: elsewhere the bytes stay in the name they are in.
    const Table u = read_csv_text("t,\xEF\xBB\xBFq\n0,1\n", "mid.csv");
    CHECK(u.column("q") == -1);
}
}  // namespace MBX_UNITY_ID
