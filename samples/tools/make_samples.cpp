// mbx_make_samples <samples directory>: regenerates every sample folder. The
// output is deterministic (no clock, no randomness), so a rerun changes no
// committed file unless the tools changed.
#include <sys/stat.h>

#include <cstdio>
#include <exception>
#include <string>

#include "samples.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: mbx_make_samples <samples directory>\n");
        return 2;
    }
    const std::string root = argv[1];
    const struct {
        const char* name;
        void (*make)(const std::string&);
    } samples[] = {{"fourbar_imperial", mbx_samples::make_fourbar_imperial},
                   {"double_cardan", mbx_samples::make_double_cardan},
                   {"five_axis_arm", mbx_samples::make_five_axis_arm},
                   {"joints_showcase", mbx_samples::make_joints_showcase},
                   {"emps_axis", mbx_samples::make_emps_axis},
                   {"double_pendulum_simscape", mbx_samples::make_double_pendulum_simscape}};
    try {
        for (const auto& s : samples) {
            const std::string dir = root + "/" + s.name;
            mkdir(dir.c_str(), 0755);
            s.make(dir);
            std::printf("wrote %s\n", dir.c_str());
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mbx_make_samples: %s\n", e.what());
        return 1;
    }
    return 0;
}
