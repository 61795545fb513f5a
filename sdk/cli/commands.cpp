#include "commands.h"

#include <sys/stat.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

#include "file_adapter.h"
#include "mbx/mbx.h"
#include "stub_assembly.h"

namespace mbx_cli {
namespace {

const char* kTranslateUsage =
    "usage: mbx translate <input> -o <dir> [--shapes <file.wrl>] [--mesh-dir <dir>]... [--no-mass-check]\n"
    "                     [--strict] [--progress] [--length-tolerance <m>]\n"
    "                     [--format <list>] [--mesh-format stl|obj|gltf] [--name <model>] [--stop-time <s>]\n"
    "                     [--library <file.xml>]... [--drives <file.xml>]\n"
    "\n"
    "  <input>     a SimMechanics first-generation XML export (*.xml), or a built-in assembly ('mbx list')\n"
    "  -o <dir>    output directory (created if missing)\n"
    "  --shapes <file.wrl>  VRML97 scene of the assembly: its shapes are matched to the XML's bodies by\n"
    "              pose (bodies whose XML names a mesh file keep that mesh)\n"
    "  --mesh-dir <dir>  also look here for the mesh files the XML names, after the XML's own directory\n"
    "              (file names match ignoring case; repeatable)\n"
    "  --no-mass-check  for XML inputs, skip comparing each closed mesh's centroid with the CAD centre of\n"
    "              mass (done by default; reported per part)\n"
    "  --strict    exit with code 3 when the report holds errors\n"
    "  --progress  print translation stages to stderr\n"
    "  --length-tolerance <m>  distance under which joint frames coincide (default: automatic)\n"
    "  --format <list>  comma-separated exports: modelica, mjcf, urdf, meshes, all (default) or none\n"
    "              (modelica/<Name>/, mjcf/<name>.xml, urdf/<name>.urdf, meshes/ and scene.glb)\n"
    "  --mesh-format stl|obj|gltf  format of meshes/ (default stl; gltf is written as binary .glb;\n"
    "              MJCF and URDF use STL unless obj)\n"
    "  --name <model>  model name in the exports (default: the input's file name or built-in name)\n"
    "  --stop-time <s>  Modelica experiment stop time (default 10)\n"
    "  --library <file.xml>  an object library of motors and transmissions (repeatable; a drive file may\n"
    "              also name its libraries)\n"
    "  --drives <file.xml>  drives, controllers and motion targets keyed by the CAD joints' ids\n"
    "              (docs/mechatronics.md); every export then includes them\n"
    "\n"
    "An XML or VRML file that cannot be read is reported as 'mbx: <file>:<line>: <message>' (exit code 1);\n"
    "nothing is written then. Missing mesh files and unmatched shapes are findings in the report.\n";

int progress_to_stderr(void*, const char* stage, double fraction) {
    if (fraction == 0.0) std::fprintf(stderr, "mbx: %s...\n", stage);
    return 0;
}

struct Context {
    mbx_context* ctx = nullptr;
    mbx_mechanism* mech = nullptr;
    mbx_mechatronics* mechatronics = nullptr;
    ~Context() {
        mbx_mechatronics_destroy(mechatronics);
        mbx_mechanism_destroy(mech);
        mbx_context_destroy(ctx);
    }
};

int fail(const Context& c, mbx_status status, const char* what) {
    std::fprintf(stderr, "mbx: %s failed (%s): %s\n", what, mbx_status_name(status), mbx_context_last_error(c.ctx));
    return 1;
}

// A library or drive file with problems: its message already lists them
// with file and line, one per line.
int fail_input(const Context& c) {
    std::fprintf(stderr, "mbx: %s\n", mbx_context_last_error(c.ctx));
    return 1;
}

bool is_file(const std::string& path) {
    struct stat st;
    return stat(path.c_str(), &st) == 0;
}

bool is_xml_path(const std::string& path) {
    if (path.size() < 4) return false;
    std::string ext = path.substr(path.size() - 4);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".xml";
}

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

// File name without directory and extension ("a/b/Robot.xml" -> "Robot").
std::string stem_of(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    const size_t dot = name.find_last_of('.');
    if (dot != std::string::npos && dot > 0) name.resize(dot);
    return name;
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

int run_translate(const std::vector<std::string>& args) {
    std::string input, out_dir;
    mbx_files::FileAdapterOptions file_options;
    bool strict = false, progress = false, mass_check = true;
    double length_tolerance = 0;
    uint32_t formats = MBX_EXPORT_ALL;
    mbx_export_options export_options{};
    export_options.struct_size = sizeof export_options;
    std::string model_name, drives_path;
    std::vector<std::string> libraries;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-h" || a == "--help") {
            std::fputs(kTranslateUsage, stdout);
            return 0;
        } else if ((a == "-o" || a == "--output") && i + 1 < args.size()) {
            out_dir = args[++i];
        } else if (a == "--shapes" && i + 1 < args.size()) {
            file_options.shapes_path = args[++i];
        } else if (a == "--mesh-dir" && i + 1 < args.size()) {
            file_options.mesh_dirs.push_back(args[++i]);
        } else if (a == "--no-mass-check") {
            mass_check = false;
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
        } else if (a == "--library" && i + 1 < args.size()) {
            libraries.push_back(args[++i]);
        } else if (a == "--drives" && i + 1 < args.size()) {
            if (!drives_path.empty()) {
                std::fprintf(stderr, "mbx translate: --drives is given twice\n");
                return 2;
            }
            drives_path = args[++i];
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

    const bool file_input = is_xml_path(input);
    if (!file_input && (!file_options.shapes_path.empty() || !file_options.mesh_dirs.empty())) {
        std::fprintf(stderr, "mbx translate: --shapes and --mesh-dir apply to XML inputs only\n");
        return 2;
    }
    // Declared before the context: the host must outlive the mechanism.
    std::unique_ptr<mbx_files::FileAdapter> adapter;
    std::unique_ptr<mbx_stub::Host> stub_host;
    const mbx_host* table = nullptr;
    if (file_input) {
        try {
            adapter = mbx_files::FileAdapter::open(input, file_options);
        } catch (const mbx_files::FileError& e) {
            std::fprintf(stderr, "mbx: %s:%d: %s\n", e.file().c_str(), e.line(), e.message().c_str());
            return 1;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "mbx: %s: %s\n", input.c_str(), e.what());
            return 1;
        }
        table = adapter->table();
    } else {
        mbx_stub::Assembly assembly;
        const std::string builtin = input.rfind("builtin:", 0) == 0 ? input.substr(8) : input;
        if (!mbx_stub::builtin_assembly(builtin, assembly)) {
            if (is_file(input))
                std::fprintf(stderr,
                             "mbx translate: '%s' is neither an XML file (*.xml) nor a built-in assembly\n",
                             input.c_str());
            else
                std::fprintf(stderr, "mbx translate: no built-in assembly named '%s' (see 'mbx list')\n",
                             input.c_str());
            return 1;
        }
        stub_host = std::make_unique<mbx_stub::Host>(assembly);
        table = stub_host->table();
    }

    Context c;
    if (mbx_context_create(&c.ctx) != MBX_OK) {
        std::fprintf(stderr, "mbx: cannot create a context\n");
        return 1;
    }
    if (progress) mbx_context_set_progress(c.ctx, progress_to_stderr, nullptr);
    mbx_translate_options options{};
    options.struct_size = sizeof options;
    options.length_tolerance = length_tolerance;
    if (file_input && mass_check) options.flags = MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES;
    // Libraries and drives are read before translating, so a typo in them
    // costs no translation time.
    if (!libraries.empty() || !drives_path.empty()) {
        if (mbx_mechatronics_create(c.ctx, &c.mechatronics) != MBX_OK) return fail(c, MBX_ERROR_OUT_OF_MEMORY, "setup");
        for (const std::string& lib : libraries)
            if (mbx_mechatronics_load_library(c.ctx, c.mechatronics, lib.c_str()) != MBX_OK) return fail_input(c);
        if (!drives_path.empty() && mbx_mechatronics_load_drives(c.ctx, c.mechatronics, drives_path.c_str()) != MBX_OK)
            return fail_input(c);
    }
    mbx_status status = mbx_translate(c.ctx, table, &options, &c.mech);
    if (status != MBX_OK) return fail(c, status, "translation");
    if (c.mechatronics && mbx_mechanism_set_mechatronics(c.ctx, c.mech, c.mechatronics) != MBX_OK)
        return fail_input(c);
    // Export before the report, so what a format could not express is in it.
    if (formats) {
        if (model_name.empty()) model_name = file_input ? stem_of(input) : stem_of(input.substr(input.rfind(':') + 1));
        export_options.formats = formats;
        export_options.model_name = model_name.c_str();
        status = mbx_mechanism_export(c.ctx, c.mech, &export_options, out_dir.c_str());
        if (status != MBX_OK) return fail(c, status, "export");
    }
    status = mbx_mechanism_write_report(c.ctx, c.mech, out_dir.c_str());
    if (status != MBX_OK) return fail(c, status, "writing the report");
    // Mesh files that broke only when loaded came after the report's host
    // diagnostics were taken; say so here rather than not at all.
    if (adapter)
        for (const mbx_memory::Diagnostic& d : adapter->late_diagnostics())
            std::fprintf(stderr, "mbx: warning: %s:%d: %s\n", d.file.c_str(), d.line, d.message.c_str());

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

}  // namespace mbx_cli
