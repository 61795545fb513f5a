#include "commands.h"

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "mbx/mbx.h"
#include "stub_assembly.h"

namespace mbx_cli {
namespace {

const char* kTranslateUsage =
    "usage: mbx translate <input> -o <dir> [--strict] [--progress] [--length-tolerance <m>]\n"
    "\n"
    "  <input>     a built-in assembly ('mbx list'); PMXML files arrive with the file adapter\n"
    "  -o <dir>    output directory (created if missing)\n"
    "  --strict    exit with code 3 when the report holds errors\n"
    "  --progress  print translation stages to stderr\n"
    "  --length-tolerance <m>  distance under which joint frames coincide (default: automatic)\n";

int progress_to_stderr(void*, const char* stage, double fraction) {
    if (fraction == 0.0) std::fprintf(stderr, "mbx: %s...\n", stage);
    return 0;
}

struct Context {
    mbx_context* ctx = nullptr;
    mbx_mechanism* mech = nullptr;
    ~Context() {
        mbx_mechanism_destroy(mech);
        mbx_context_destroy(ctx);
    }
};

int fail(const Context& c, mbx_status status, const char* what) {
    std::fprintf(stderr, "mbx: %s failed (%s): %s\n", what, mbx_status_name(status), mbx_context_last_error(c.ctx));
    return 1;
}

bool is_file(const std::string& path) {
    struct stat st;
    return stat(path.c_str(), &st) == 0;
}

}  // namespace

int run_list(const std::vector<std::string>& args) {
    if (!args.empty()) {
        std::fputs("usage: mbx list\n", args[0] == "--help" || args[0] == "-h" ? stdout : stderr);
        return args[0] == "--help" || args[0] == "-h" ? 0 : 2;
    }
    for (const std::string& name : mbx_stub::builtin_names()) std::printf("%s\n", name.c_str());
    return 0;
}

int run_translate(const std::vector<std::string>& args) {
    std::string input, out_dir;
    bool strict = false, progress = false;
    double length_tolerance = 0;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-h" || a == "--help") {
            std::fputs(kTranslateUsage, stdout);
            return 0;
        } else if ((a == "-o" || a == "--output") && i + 1 < args.size()) {
            out_dir = args[++i];
        } else if (a == "--strict") {
            strict = true;
        } else if (a == "--progress") {
            progress = true;
        } else if (a == "--length-tolerance" && i + 1 < args.size()) {
            char* end = nullptr;
            length_tolerance = std::strtod(args[++i].c_str(), &end);
            if (!end || *end || !(length_tolerance > 0)) {
                std::fprintf(stderr, "mbx translate: --length-tolerance needs a positive number of metres\n");
                return 2;
            }
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "mbx translate: unknown or incomplete option '%s'\n\n%s", a.c_str(), kTranslateUsage);
            return 2;
        } else if (input.empty()) {
            input = a;
        } else {
            std::fprintf(stderr, "mbx translate: more than one input ('%s', '%s')\n", input.c_str(), a.c_str());
            return 2;
        }
    }
    if (input.empty() || out_dir.empty()) {
        std::fputs(kTranslateUsage, stderr);
        return 2;
    }

    mbx_stub::Assembly assembly;
    const std::string builtin = input.rfind("builtin:", 0) == 0 ? input.substr(8) : input;
    if (!mbx_stub::builtin_assembly(builtin, assembly)) {
        if (is_file(input))
            std::fprintf(stderr, "mbx translate: '%s' is a file; file inputs (PMXML + VRML) are not supported yet\n",
                         input.c_str());
        else
            std::fprintf(stderr, "mbx translate: no built-in assembly named '%s' (see 'mbx list')\n", input.c_str());
        return 1;
    }
    mbx_stub::Host host(assembly);

    Context c;
    if (mbx_context_create(&c.ctx) != MBX_OK) {
        std::fprintf(stderr, "mbx: cannot create a context\n");
        return 1;
    }
    if (progress) mbx_context_set_progress(c.ctx, progress_to_stderr, nullptr);
    mbx_translate_options options{};
    options.struct_size = sizeof options;
    options.length_tolerance = length_tolerance;
    mbx_status status = mbx_translate(c.ctx, host.table(), &options, &c.mech);
    if (status != MBX_OK) return fail(c, status, "translation");
    status = mbx_mechanism_write_report(c.ctx, c.mech, out_dir.c_str());
    if (status != MBX_OK) return fail(c, status, "writing the report");

    mbx_mechanism_summary s{};
    s.struct_size = sizeof s;
    mbx_mechanism_get_summary(c.mech, &s);
    std::printf("%s: %u parts -> %u rigid bodies, %u joints (%u cut), %u loops (%u planar), %d DoF "
                "(Gruebler %d), %u warnings, %u errors\n",
                input.c_str(), s.part_count, s.rigid_body_count, s.joint_count, s.cut_joint_count, s.loop_count,
                s.planar_loop_count, s.dof, s.gruebler_dof, s.warning_count, s.error_count);
    std::printf("report: %s/report.json\nreport: %s/report.txt\n", out_dir.c_str(), out_dir.c_str());
    return strict && s.error_count > 0 ? 3 : 0;
}

}  // namespace mbx_cli
