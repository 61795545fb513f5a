// mbx_generate_pmxml <parts> <outdir> [--seed N] [--subsystem-size N]
//                    [--inline-geometry] [--digits N] [--name NAME]
// Writes a synthetic PMXML + VRML assembly and prints its exact counts.
#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "generate_pmxml.h"

namespace {

int usage() {
    std::fprintf(stderr,
                 "usage: mbx_generate_pmxml <parts> <outdir> [--seed N] [--subsystem-size N] [--inline-geometry]\n"
                 "                          [--digits N] [--name NAME]\n");
    return 2;
}

bool to_number(const char* text, unsigned long& out) {
    char* end = nullptr;
    out = std::strtoul(text, &end, 10);
    return end != text && *end == '\0';
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) return usage();
    mbx_samples::GeneratorOptions options;
    std::string name = "generated";
    unsigned long value = 0;
    if (!to_number(argv[1], value) || value == 0) return usage();
    options.parts = value;
    const std::string directory = argv[2];
    for (int i = 3; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool has_value = i + 1 < argc;
        if (arg == "--inline-geometry") {
            options.inline_geometry = true;
        } else if (arg == "--name" && has_value) {
            name = argv[++i];
        } else if ((arg == "--seed" || arg == "--subsystem-size" || arg == "--digits") && has_value &&
                   to_number(argv[i + 1], value)) {
            ++i;
            if (arg == "--seed") options.seed = uint32_t(value);
            else if (arg == "--subsystem-size") options.subsystem_size = value;
            else options.digits = int(value);
        } else {
            return usage();
        }
    }
    mkdir(directory.c_str(), 0755);
    try {
        const mbx_samples::GeneratedCounts c = mbx_samples::generate_pmxml(directory, name, options);
        std::printf("%s\n%s\n", c.xml_path.c_str(), c.wrl_path.c_str());
        std::printf("parts %zu, root parts %zu, subsystems %zu, simple joints %zu (welds %zu, revolutes %zu)\n", c.parts,
                    c.root_parts, c.subsystems, c.simple_joints, c.welds, c.revolutes);
        std::printf("expected: rigid bodies %zu, loops %zu, dof %d, redundant %d; VRML transforms %zu\n",
                    c.rigid_bodies, c.loops, c.dof, c.redundant, c.vrml_nodes);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mbx_generate_pmxml: %s\n", e.what());
        return 1;
    }
    return 0;
}
