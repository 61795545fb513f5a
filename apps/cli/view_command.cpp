// `mbx view`: translate an input and write view.html into a directory: the
// assembly at its CAD pose and, when the directory holds the trajectory.csv
// of an `mbx simulate` run of the same input, that motion played in a loop.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.h"
#include "mechanism_input.h"

namespace mbx_cli {
namespace {

const std::string kViewUsage = std::string(
    "usage: mbx view <input> -o <dir> [--trajectory <file.csv> | --still]\n"
    "                [--shapes <file.wrl>] [--mesh-dir <dir>]... [--library <file.xml>]... [--drives <file.xml>]\n"
    "\n"
    "  -o <dir>    output directory: view.html (created if missing); a self-contained page that opens offline\n") +
    kInputOptionsHelp +
    "  --trajectory <file.csv>  the motion to play (default: <dir>/trajectory.csv when it exists, as\n"
    "              `mbx simulate <input> -o <dir>` writes it)\n"
    "  --still     show the CAD pose only, even if <dir>/trajectory.csv exists\n";

}  // namespace

int run_view(const std::vector<std::string>& args) {
    InputOptions in;
    std::string out_dir, trajectory;
    bool still = false;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const int input_option = parse_input_option(args, i, in, "view");
        if (input_option == 2) return 2;
        if (input_option == 1) continue;
        const bool has_value = i + 1 < args.size();
        if (a == "-h" || a == "--help") {
            std::fputs(kViewUsage.c_str(), stdout);
            return 0;
        } else if ((a == "-o" || a == "--output") && has_value) {
            out_dir = args[++i];
        } else if (a == "--trajectory" && has_value) {
            trajectory = args[++i];
        } else if (a == "--still") {
            still = true;
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "mbx view: unknown or incomplete option '%s'\n\n%s", a.c_str(), kViewUsage.c_str());
            return 2;
        } else if (in.input.empty()) {
            in.input = a;
        } else {
            std::fprintf(stderr, "mbx view: more than one input ('%s', '%s')\n", in.input.c_str(), a.c_str());
            return 2;
        }
    }
    if (in.input.empty() || out_dir.empty() || (still && !trajectory.empty())) {
        std::fputs(kViewUsage.c_str(), stderr);
        return 2;
    }
    if (!still && trajectory.empty()) {
        const std::string beside = out_dir + "/trajectory.csv";
        std::error_code ec;
        if (std::filesystem::is_regular_file(beside, ec)) trajectory = beside;
    }
    in.mass_check = false;
    OpenedInput c;
    if (const int code = open_input(in, "view", c)) return code;
    mbx_view_options options{};
    options.struct_size = sizeof options;
    options.trajectory = trajectory.empty() ? nullptr : trajectory.c_str();
    const std::string title = stem_of(in.input);
    options.title = title.c_str();
    const mbx_status status = mbx_mechanism_write_view(c.ctx, c.mech, &options, out_dir.c_str());
    if (status != MBX_OK) return fail(c, status, "writing the view");
    std::printf("view: %s/view.html%s%s\n", out_dir.c_str(), trajectory.empty() ? "" : " playing ",
                trajectory.c_str());
    return 0;
}

}  // namespace mbx_cli
