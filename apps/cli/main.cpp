#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "commands.h"
#include "mbx/mbx.h"

namespace {

const char* kUsage =
    "usage: mbx <command> [options]\n"
    "\n"
    "commands:\n"
    "  translate <input> -o <dir>   translate an assembly; writes the report and the exports to <dir>\n"
    "  simulate <input> -o <dir>    simulate an assembly; writes trajectory.csv and simulation.json to <dir>\n"
    "  calibrate <input> --experiment <file.xml> -o <dir>\n"
    "                               name and fit what the model misses in measured data; writes\n"
    "                               calibration.json, calibration.html and description.xml to <dir>\n"
    "  excite <input> -o <dir>      design the motion of a calibration record within the joints' limits;\n"
    "                               writes excitation.csv, experiment.xml and excitation.html to <dir>\n"
    "  view <input> -o <dir>        write view.html to <dir>: the assembly in a browser, offline, playing\n"
    "                               <dir>/trajectory.csv when a simulation left one there\n"
    "  geometry <file.step> [-o <dir>]\n"
    "                               print each solid of a STEP file (volume, centroid, inertia, mesh\n"
    "                               closure); writes its meshes (STL, OBJ or glTF) to <dir>\n"
    "  list                         list the built-in assemblies usable as <input>\n"
    "  formats                      list the file formats usable as <input>\n"
    "  library <file.xml>...        check object library files and show derived drive quantities\n"
    "\n"
    "options:\n"
    "  -h, --help      this help (also: mbx <command> --help)\n"
    "  --version       print the version\n";

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty()) {
        std::fputs(kUsage, stderr);
        return 2;
    }
    const std::string& command = args[0];
    std::vector<std::string> rest(args.begin() + 1, args.end());
    if (command == "-h" || command == "--help" || command == "help") {
        std::fputs(kUsage, stdout);
        return 0;
    }
    if (command == "--version" || command == "version") {
        std::printf("mbx %s (ABI %u)\n", mbx_version(), mbx_abi_version());
        return 0;
    }
    if (command == "translate") return mbx_cli::run_translate(rest);
    if (command == "simulate") return mbx_cli::run_simulate(rest);
    if (command == "calibrate") return mbx_cli::run_calibrate(rest);
    if (command == "excite") return mbx_cli::run_excite(rest);
    if (command == "view") return mbx_cli::run_view(rest);
    if (command == "geometry") return mbx_cli::run_geometry(rest);
    if (command == "list") return mbx_cli::run_list(rest);
    if (command == "formats") return mbx_cli::run_formats(rest);
    if (command == "library") return mbx_cli::run_library(rest);
    std::fprintf(stderr, "mbx: unknown command '%s'\n\n%s", command.c_str(), kUsage);
    return 2;
}
