// The EMPS rig's recorded runs (../shared/data/measured/emps/*.csv: t, q_ref,
// q, u, force per 1 ms sample) and the relative error the rig's authors
// report, shared by the tests that close the rig's loop in MuJoCo and in
// mbx's own simulator.
#pragma once
#include <charconv>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

namespace mbx_test {

struct EmpsRecord {
    std::vector<double> t, q_ref, q, u, force;
};

inline EmpsRecord read_emps(const std::string& path) {
    std::ifstream in(path);
    REQUIRE(in);
    std::string line;
    std::getline(in, line);  // header: t, q_ref, q, u, force
    EmpsRecord r;
    int bad_line = 0, line_number = 1;
    while (std::getline(in, line)) {
        ++line_number;
        double v[5];
        const char* p = line.data();
        const char* end = p + line.size();
        for (double& x : v) {
            const auto res = std::from_chars(p, end, x);
            if (res.ec != std::errc() && !bad_line) bad_line = line_number;
            p = res.ptr < end ? res.ptr + 1 : end;
        }
        r.t.push_back(v[0]), r.q_ref.push_back(v[1]), r.q.push_back(v[2]), r.u.push_back(v[3]), r.force.push_back(v[4]);
    }
    INFO(path << ":" << bad_line);
    REQUIRE(bad_line == 0);  // one check, not one per number: the tests run under ASan too
    return r;
}

// 100 ||y - y_hat|| / ||y||, percent.
inline double relative_error(const std::vector<double>& y, const std::vector<double>& y_hat) {
    double num = 0, den = 0;
    for (size_t i = 0; i < y.size(); ++i) num += (y[i] - y_hat[i]) * (y[i] - y_hat[i]), den += y[i] * y[i];
    return 100 * std::sqrt(num / den);
}

}  // namespace mbx_test
