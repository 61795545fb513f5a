// Ceres' own log lines never reach the host's stderr: a residual that turns
// NaN (a diverging simulation window) makes Ceres log a WARNING through glog
// whatever the solver's logging_type; solve_quietly holds it back, leaves a
// host's glog level as it was, and says in the summary's words what failed.
// Compiled on its own (tests/calibration/CMakeLists.txt): Ceres' headers
// bring glog's CHECK macros, so doctest's go by their long names here.
#include <ceres/ceres.h>
#include <glog/logging.h>
#include <unistd.h>
#define DOCTEST_CONFIG_NO_SHORT_MACRO_NAMES
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>

#include "calibration/simulation/quiet_solve.h"
#include "temp_dir.h"

namespace {

using namespace mbx::calibration;

// A residual of x - 1 that is NaN once x leaves [-10, 10]: the first step of
// an undamped solve from x = 50 evaluates it there.
struct Diverging {
    template <class T>
    bool operator()(const T* x, T* r) const {
        using std::abs;
        r[0] = x[0] - T(1);
        if (x[0] > T(10) || x[0] < T(-10)) r[0] = T(std::numeric_limits<double>::quiet_NaN());
        return true;
    }
};

// What the process writes to file descriptor 2 while `run` runs.
std::string stderr_of(const std::function<void()>& run, const std::string& scratch) {
    std::fflush(stderr);
    const int saved = dup(2);
    FILE* f = std::fopen(scratch.c_str(), "w");
    DOCTEST_REQUIRE(f);
    dup2(fileno(f), 2);
    run();
    std::fflush(stderr);
    dup2(saved, 2);
    close(saved);
    std::fclose(f);
    std::ifstream in(scratch);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

ceres::Solver::Summary solve_nan(bool quietly) {
    double x = 50;
    ceres::Problem problem;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Diverging, 1, 1>(new Diverging), nullptr, &x);
    ceres::Solver::Options o;
    o.logging_type = ceres::SILENT;
    o.minimizer_progress_to_stdout = false;
    ceres::Solver::Summary s;
    if (quietly)
        solve_quietly(o, &problem, &s);
    else
        ceres::Solve(o, &problem, &s);
    return s;
}

DOCTEST_TEST_CASE("quiet solve: a NaN residual's glog WARNING is held back, the host's glog level kept, the failure put in words") {
    DOCTEST_REQUIRE_FALSE(google::IsGoogleLoggingInitialized());
    mbx_test::TempDir dir("mbx_quiet_solve");
    const int level = FLAGS_minloglevel;
    ceres::Solver::Summary quiet;
    const std::string held = stderr_of([&] { quiet = solve_nan(true); }, dir.file("quiet.txt"));
    DOCTEST_CHECK(held.empty());
    DOCTEST_CHECK(FLAGS_minloglevel == level);
    // The same solve through Ceres alone does print: the hold is what keeps
    // the lines back.
    const std::string raw = stderr_of([] { solve_nan(false); }, dir.file("raw.txt"));
    DOCTEST_MESSAGE(std::string("Ceres alone wrote: ") << raw.substr(0, 300));
    DOCTEST_CHECK(raw.find("WARNING") != std::string::npos);
    // The summary still says what went wrong, for the run's messages.
    DOCTEST_CHECK(quiet.termination_type != ceres::CONVERGENCE);
    const std::string note = solver_note(quiet, "the simulation fit");
    DOCTEST_CHECK(note.rfind("the simulation fit ", 0) == 0);
    ceres::Solver::Summary fine;
    fine.termination_type = ceres::CONVERGENCE;
    DOCTEST_CHECK(solver_note(fine, "the simulation fit").empty());
}

}  // namespace
