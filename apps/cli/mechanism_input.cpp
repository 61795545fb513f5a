#include "mechanism_input.h"

#include "host_adapters/common/file_error.h"

#include <sys/stat.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <exception>

namespace mbx_cli {
namespace {

int progress_to_stderr(void*, const char* stage, double fraction) {
    if (fraction == 0.0) std::fprintf(stderr, "mbx: %s...\n", stage);
    return 0;
}

// A library or drive file with problems: its message already lists them
// with file and line, one per line.
int fail_input(const OpenedInput& in) {
    std::fprintf(stderr, "mbx: %s\n", mbx_context_last_error(in.ctx));
    return 1;
}

bool is_file(const std::string& path) {
    struct stat st;
    return stat(path.c_str(), &st) == 0;
}


}  // namespace

const char* kInputOptionsHelp =
    "  <input>     a CAD export in a format mbx reads ('mbx formats'), or a built-in assembly ('mbx list')\n"
    "  --shapes <file.wrl>  VRML97 scene of the assembly: its shapes are matched to the XML's bodies by\n"
    "              pose (bodies whose XML names a mesh file keep that mesh)\n"
    "  --mesh-dir <dir>  also look here for the mesh files the XML names, after the XML's own directory\n"
    "              (file names match ignoring case; repeatable)\n"
    "  --package-path <name>=<dir>  a URDF's package://<name>/... paths are in <dir> (repeatable; <name> may\n"
    "              hold several path segments; then ROS_PACKAGE_PATH is searched)\n"
    "  --floating-base  a URDF's root link moves freely (six freedoms) instead of being fixed to the world\n"
    "  --no-mass-check  for file inputs, skip comparing each closed mesh's centroid with the CAD centre of\n"
    "              mass (done by default; reported per part)\n"
    "  --progress  print stages to stderr\n"
    "  --length-tolerance <m>  distance under which joint frames coincide (default: automatic)\n"
    "  --library <file.xml>  an object library of motors and transmissions (repeatable; a drive file may\n"
    "              also name its libraries)\n"
    "  --drives <file.xml>  drives, controllers and motion targets keyed by the CAD joints' ids\n"
    "              (docs/mechatronics.md)\n"
    "  --collision hulls  a convex hull of every moving part's mesh as its collision shape, unless the\n"
    "              description file gives that body shapes of its own (docs/contact.md)\n";

int parse_input_option(const std::vector<std::string>& args, size_t& i, InputOptions& o, const char* command) {
    const std::string& a = args[i];
    const bool has_value = i + 1 < args.size();
    if (a == "--shapes" && has_value) {
        o.file_options.shapes_path = args[++i];
    } else if (a == "--mesh-dir" && has_value) {
        o.file_options.mesh_dirs.push_back(args[++i]);
    } else if (a == "--package-path" && has_value) {
        const std::string& value = args[++i];
        const size_t equals = value.find('=');
        if (equals == std::string::npos || equals == 0 || equals + 1 == value.size()) {
            std::fprintf(stderr, "mbx %s: --package-path takes <name>=<dir>, not '%s'\n", command, value.c_str());
            return 2;
        }
        o.file_options.package_paths.push_back({value.substr(0, equals), value.substr(equals + 1)});
    } else if (a == "--floating-base") {
        o.file_options.floating_base = true;
    } else if (a == "--no-mass-check") {
        o.mass_check = false;
    } else if (a == "--progress") {
        o.progress = true;
    } else if (a == "--length-tolerance" && has_value) {
        char* end = nullptr;
        o.length_tolerance = std::strtod(args[++i].c_str(), &end);
        if (!end || *end || !(o.length_tolerance > 0)) {
            std::fprintf(stderr, "mbx %s: --length-tolerance needs a positive number of metres\n", command);
            return 2;
        }
    } else if (a == "--library" && has_value) {
        o.libraries.push_back(args[++i]);
    } else if (a == "--drives" && has_value) {
        if (!o.drives_path.empty()) {
            std::fprintf(stderr, "mbx %s: --drives is given twice\n", command);
            return 2;
        }
        o.drives_path = args[++i];
    } else if (a == "--collision" && has_value) {
        if (args[++i] != "hulls") {
            std::fprintf(stderr, "mbx %s: --collision takes 'hulls' (other shapes go in the description file)\n", command);
            return 2;
        }
        o.collision_hulls = true;
    } else {
        return 0;
    }
    return 1;
}

OpenedInput::~OpenedInput() {
    mbx_mechatronics_destroy(mechatronics);
    mbx_mechanism_destroy(mech);
    mbx_context_destroy(ctx);
}

int fail(const OpenedInput& in, mbx_status status, const char* what) {
    std::fprintf(stderr, "mbx: %s failed (%s): %s\n", what, mbx_status_name(status), mbx_context_last_error(in.ctx));
    return 1;
}

std::string stem_of(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    const size_t dot = name.find_last_of('.');
    if (dot != std::string::npos && dot > 0) name.resize(dot);
    return name;
}

namespace {

// The mechatronics of the input's own description (a URDF's joint dynamics
// and collision shapes) first, then the libraries, then `drives_path`,
// which refines it; none when there is nothing to load.
int load_description(const InputOptions& o, const std::string& drives_path, OpenedInput& out) {
    const std::string own_description = out.adapter ? out.adapter->description() : std::string();
    if (o.libraries.empty() && drives_path.empty() && !o.collision_hulls && own_description.empty()) return 0;
    if (mbx_mechatronics_create(out.ctx, &out.mechatronics) != MBX_OK) return fail(out, MBX_ERROR_OUT_OF_MEMORY, "setup");
    if (!own_description.empty() &&
        mbx_mechatronics_load_drives_text(out.ctx, out.mechatronics, own_description.c_str(), o.input.c_str()) != MBX_OK)
        return fail_input(out);
    for (const std::string& lib : o.libraries)
        if (mbx_mechatronics_load_library(out.ctx, out.mechatronics, lib.c_str()) != MBX_OK) return fail_input(out);
    if (!drives_path.empty() && mbx_mechatronics_load_drives(out.ctx, out.mechatronics, drives_path.c_str()) != MBX_OK)
        return fail_input(out);
    if (o.collision_hulls) {
        mbx_collision_shape_desc hulls{};
        hulls.struct_size = sizeof hulls;
        hulls.body_id = "*";
        hulls.kind = MBX_COLLISION_HULL;
        if (mbx_mechatronics_add_collision_shape(out.ctx, out.mechatronics, &hulls) != MBX_OK) return fail_input(out);
    }
    return 0;
}

}  // namespace

int open_input(const InputOptions& o, const char* command, OpenedInput& out) {
    const std::string& input = o.input;
    const mbx_files::InputFormat* format = mbx_files::input_format_of(input);
    out.file_input = format != nullptr;
    if (!out.file_input && (!o.file_options.shapes_path.empty() || !o.file_options.mesh_dirs.empty() ||
                            !o.file_options.package_paths.empty() || o.file_options.floating_base)) {
        std::fprintf(stderr, "mbx %s: --shapes, --mesh-dir, --package-path and --floating-base apply to file inputs only\n",
                     command);
        return 2;
    }
    if (format && !format->takes_scene && !o.file_options.shapes_path.empty()) {
        std::fprintf(stderr, "mbx %s: --shapes does not apply to %s inputs (their parts carry their own shapes)\n",
                     command, format->name);
        return 2;
    }
    const mbx_host* table = nullptr;
    if (out.file_input) {
        try {
            out.adapter = format->open(input, o.file_options);
        } catch (const mbx_files::FileError& e) {
            std::fprintf(stderr, "mbx: %s:%d: %s\n", e.file().c_str(), e.line(), e.message().c_str());
            return 1;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "mbx: %s: %s\n", input.c_str(), e.what());
            return 1;
        }
        table = out.adapter->table();
    } else {
        mbx_stub::Assembly assembly;
        const std::string builtin = input.rfind("builtin:", 0) == 0 ? input.substr(8) : input;
        if (!mbx_stub::builtin_assembly(builtin, assembly)) {
            if (is_file(input))
                std::fprintf(stderr, "mbx %s: '%s' is neither a file format mbx reads ('mbx formats') nor a built-in assembly\n",
                             command, input.c_str());
            else
                std::fprintf(stderr, "mbx %s: no built-in assembly named '%s' (see 'mbx list')\n", command,
                             input.c_str());
            return 1;
        }
        out.stub_host = std::make_unique<mbx_stub::Host>(assembly);
        table = out.stub_host->table();
    }

    if (mbx_context_create(&out.ctx) != MBX_OK) {
        std::fprintf(stderr, "mbx: cannot create a context\n");
        return 1;
    }
    if (o.progress) mbx_context_set_progress(out.ctx, progress_to_stderr, nullptr);
    mbx_translate_options options{};
    options.struct_size = sizeof options;
    options.length_tolerance = o.length_tolerance;
    if (out.file_input && o.mass_check) options.flags = MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES;
    // Libraries and drives are read before translating, so a typo in them
    // costs no translation time.
    if (const int code = load_description(o, o.drives_path, out)) return code;
    const mbx_status status = mbx_translate(out.ctx, table, &options, &out.mech);
    if (status != MBX_OK) return fail(out, status, "translation");
    if (out.mechatronics && mbx_mechanism_set_mechatronics(out.ctx, out.mech, out.mechatronics) != MBX_OK)
        return fail_input(out);
    return 0;
}

int attach_description(const InputOptions& o, const std::string& drives_path, OpenedInput& in) {
    mbx_mechatronics_destroy(in.mechatronics);
    in.mechatronics = nullptr;
    if (const int code = load_description(o, drives_path, in)) return code;
    if (in.mechatronics && mbx_mechanism_set_mechatronics(in.ctx, in.mech, in.mechatronics) != MBX_OK)
        return fail_input(in);
    return 0;
}

}  // namespace mbx_cli
