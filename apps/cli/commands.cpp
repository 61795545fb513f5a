#include "commands.h"

#include <sys/stat.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

#include "mbx/mbx.h"
#include "mechanism_input.h"

namespace mbx_cli {
namespace {

const std::string kTranslateUsage = std::string(
    "usage: mbx translate <input> -o <dir> [--shapes <file.wrl>] [--mesh-dir <dir>]... [--no-mass-check]\n"
    "                     [--strict] [--progress] [--length-tolerance <m>]\n"
    "                     [--format <list>] [--mesh-format stl|obj|gltf] [--name <model>] [--stop-time <s>]\n"
    "                     [--library <file.xml>]... [--drives <file.xml>] [--collision hulls] [--scene-collision]\n"
    "\n"
    "  -o <dir>    output directory (created if missing)\n") + kInputOptionsHelp +
    "  --strict    exit with code 3 when the report holds errors\n"
    "  --format <list>  comma-separated exports: modelica, mjcf, urdf, meshes, all (default) or none\n"
    "              (modelica/<Name>/, mjcf/<name>.xml, urdf/<name>.urdf, meshes/ and scene.glb)\n"
    "  --scene-collision  scene.glb also draws the collision shapes (semi-transparent; see --collision)\n"
    "  --mesh-format stl|obj|gltf  format of meshes/ (default stl; gltf is written as binary .glb;\n"
    "              MJCF and URDF use STL unless obj)\n"
    "  --name <model>  model name in the exports (default: the input's file name or built-in name)\n"
    "  --stop-time <s>  Modelica experiment stop time (default 10)\n"
    "\n"
    "With --drives every export includes the drives. An XML or VRML file that cannot be read is reported as\n"
    "'mbx: <file>:<line>: <message>' (exit code 1); nothing is written then. Missing mesh files and\n"
    "unmatched shapes are findings in the report.\n";

// "modelica,mjcf" -> bits; false on an unknown name.
bool parse_formats(const std::string& list, uint32_t& bits) {
    bits = 0;
    size_t start = 0;
    while (start <= list.size()) {
        const size_t comma = list.find(',', start);
        const std::string name = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (name == "modelica") bits |= MBX_EXPORT_MODELICA;
        else if (name == "mjcf") bits |= MBX_EXPORT_MJCF;
        else if (name == "urdf") bits |= MBX_EXPORT_URDF;
        else if (name == "meshes") bits |= MBX_EXPORT_MESHES;
        else if (name == "all") bits |= MBX_EXPORT_ALL;
        else if (name != "none") return false;
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return true;
}

// One line per drive with what it amounts to at the joint.
void print_drives(const mbx_mechanism* mech) {
    const uint32_t n = mbx_mechanism_drive_count(mech);
    for (uint32_t i = 0; i < n; ++i) {
        mbx_drive_info d{};
        d.struct_size = sizeof d;
        if (mbx_mechanism_get_drive(mech, i, &d) != MBX_OK) continue;
        const char* effort = d.linear ? "N" : "N m";
        std::printf("drive %s: %s%s%s, ratio %.6g, armature %.4g %s, effort limit %.4g %s, speed limit %.4g %s\n", d.name,
                    d.motor_name, d.transmission_name[0] ? " + " : "", d.transmission_name, d.ratio, d.armature,
                    d.linear ? "kg" : "kg m^2", d.effort_limit, effort, d.velocity_limit, d.linear ? "m/s" : "rad/s");
    }
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

int run_formats(const std::vector<std::string>& args) {
    if (!args.empty()) {
        std::fputs("usage: mbx formats\n", args[0] == "--help" || args[0] == "-h" ? stdout : stderr);
        return args[0] == "--help" || args[0] == "-h" ? 0 : 2;
    }
    std::fputs(mbx_files::input_formats_help().c_str(), stdout);
    return 0;
}

int run_translate(const std::vector<std::string>& args) {
    InputOptions in;
    bool strict = false;
    uint32_t formats = MBX_EXPORT_ALL;
    mbx_export_options export_options{};
    export_options.struct_size = sizeof export_options;
    std::string out_dir, model_name;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const int input_option = parse_input_option(args, i, in, "translate");
        if (input_option == 2) return 2;
        if (input_option == 1) continue;
        if (a == "-h" || a == "--help") {
            std::fputs(kTranslateUsage.c_str(), stdout);
            return 0;
        } else if ((a == "-o" || a == "--output") && i + 1 < args.size()) {
            out_dir = args[++i];
        } else if (a == "--strict") {
            strict = true;
        } else if (a == "--scene-collision") {
            export_options.formats |= MBX_EXPORT_SCENE_COLLISION;
        } else if (a == "--format" && i + 1 < args.size()) {
            if (!parse_formats(args[++i], formats)) {
                std::fprintf(stderr, "mbx translate: --format takes modelica, mjcf, urdf, meshes, all or none, "
                                     "comma-separated (got '%s')\n", args[i].c_str());
                return 2;
            }
        } else if (a == "--mesh-format" && i + 1 < args.size()) {
            const std::string f = args[++i];
            if (f == "stl") export_options.mesh_format = MBX_MESH_STL;
            else if (f == "obj") export_options.mesh_format = MBX_MESH_OBJ;
            else if (f == "gltf") export_options.mesh_format = MBX_MESH_GLTF;
            else {
                std::fprintf(stderr, "mbx translate: --mesh-format takes stl, obj or gltf (got '%s')\n", f.c_str());
                return 2;
            }
        } else if (a == "--name" && i + 1 < args.size()) {
            model_name = args[++i];
        } else if (a == "--stop-time" && i + 1 < args.size()) {
            char* end = nullptr;
            export_options.stop_time = std::strtod(args[++i].c_str(), &end);
            if (!end || *end || !(export_options.stop_time > 0)) {
                std::fprintf(stderr, "mbx translate: --stop-time needs a positive number of seconds\n");
                return 2;
            }
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "mbx translate: unknown or incomplete option '%s'\n\n%s", a.c_str(), kTranslateUsage.c_str());
            return 2;
        } else if (in.input.empty()) {
            in.input = a;
        } else {
            std::fprintf(stderr, "mbx translate: more than one input ('%s', '%s')\n", in.input.c_str(), a.c_str());
            return 2;
        }
    }
    if (in.input.empty() || out_dir.empty()) {
        std::fputs(kTranslateUsage.c_str(), stderr);
        return 2;
    }
    const std::string& input = in.input;
    OpenedInput c;
    if (const int code = open_input(in, "translate", c)) return code;
    // Export before the report, so what a format could not express is in it.
    mbx_status status;
    if (formats) {
        if (model_name.empty()) model_name = c.file_input ? stem_of(input) : stem_of(input.substr(input.rfind(':') + 1));
        export_options.formats |= formats;
        export_options.model_name = model_name.c_str();
        status = mbx_mechanism_export(c.ctx, c.mech, &export_options, out_dir.c_str());
        if (status != MBX_OK) return fail(c, status, "export");
    }
    status = mbx_mechanism_write_report(c.ctx, c.mech, out_dir.c_str());
    if (status != MBX_OK) return fail(c, status, "writing the report");

    mbx_mechanism_summary s{};
    s.struct_size = sizeof s;
    mbx_mechanism_get_summary(c.mech, &s);
    std::printf("%s: %u parts -> %u rigid bodies, %u joints (%u cut), %u loops (%u planar), %d DoF "
                "(Gruebler %d), %u warnings, %u errors\n",
                input.c_str(), s.cad_part_count, s.rigid_body_count, s.joint_count, s.cut_joint_count, s.loop_count,
                s.planar_loop_count, s.dof, s.gruebler_dof, s.warning_count, s.error_count);
    std::printf("report: %s/report.json\nreport: %s/report.txt\n", out_dir.c_str(), out_dir.c_str());
    if (formats & MBX_EXPORT_MODELICA) std::printf("modelica: %s/modelica/\n", out_dir.c_str());
    if (formats & MBX_EXPORT_MJCF) std::printf("mjcf: %s/mjcf/\n", out_dir.c_str());
    if (formats & MBX_EXPORT_URDF) std::printf("urdf: %s/urdf/\n", out_dir.c_str());
    if (formats & MBX_EXPORT_MESHES) std::printf("meshes: %s/meshes/ and %s/scene.glb\n", out_dir.c_str(), out_dir.c_str());
    print_drives(c.mech);
    return strict && s.error_count > 0 ? 3 : 0;
}

bool parse_number(const std::string& text, double& out) {
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return end && !*end && !text.empty() && std::isfinite(out);
}

}  // namespace mbx_cli
