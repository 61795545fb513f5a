// The C face of the file adapters (see include/mbx/mbx_files.h): the format
// of an input is chosen by the table in host_adapters/inputs/input_formats.h.
// Every exception stops here: a C caller gets a status and a message.
#include <mbx/mbx_files.h>

#include <exception>
#include <memory>
#include <new>
#include <string>

#include "host_adapters/common/file_error.h"
#include "host_adapters/inputs/input_formats.h"

struct mbx_file_host {
    std::unique_ptr<mbx_files::FileInput> adapter;
    std::string description;
};

namespace {

// Per thread, so concurrent opens on different threads do not share it.
thread_local std::string g_file, g_message;

int fail(mbx_files_error* error, std::string file, int line, std::string message) {
    g_file = std::move(file);
    g_message = std::move(message);
    if (error && error->struct_size >= sizeof(mbx_files_error)) {
        error->file = g_file.c_str();
        error->line = line;
        error->message = g_message.c_str();
    }
    return 1;
}

}  // namespace

extern "C" int mbx_files_open(const char* path, const mbx_files_options* options, mbx_file_host** out,
                              mbx_files_error* error) {
    if (!out) return fail(error, "", 0, "mbx_files_open: out is NULL");
    *out = nullptr;
    if (!path || !*path) return fail(error, "", 0, "mbx_files_open: no input file given");
    if (options && options->struct_size < MBX_FILES_OPTIONS_V1_SIZE)
        return fail(error, path, 0, "mbx_files_open: options.struct_size is too small");
    try {
        mbx_files::FileInputOptions o;
        if (options) {
            if (options->shapes) o.shapes_path = options->shapes;
            if (options->mesh_dir_count && !options->mesh_dirs)
                return fail(error, path, 0, "mbx_files_open: mesh_dir_count > 0 but mesh_dirs is NULL");
            for (uint32_t i = 0; i < options->mesh_dir_count; ++i)
                if (options->mesh_dirs[i]) o.mesh_dirs.emplace_back(options->mesh_dirs[i]);
            if (MBX_FIELD_FITS(options, mbx_files_options, floating_base)) {
                if (options->package_path_count && !options->package_paths)
                    return fail(error, path, 0, "mbx_files_open: package_path_count > 0 but package_paths is NULL");
                for (uint32_t i = 0; i < options->package_path_count; ++i) {
                    const std::string entry = options->package_paths[i] ? options->package_paths[i] : "";
                    const size_t equals = entry.find('=');
                    if (equals == std::string::npos || equals == 0 || equals + 1 == entry.size())
                        return fail(error, path, 0, "mbx_files_open: package path '" + entry + "' is not name=dir");
                    o.package_paths.push_back({entry.substr(0, equals), entry.substr(equals + 1)});
                }
                o.floating_base = options->floating_base != 0;
            }
        }
        auto files = std::make_unique<mbx_file_host>();
        files->adapter = mbx_files::open_input(path, o);
        files->description = files->adapter->description();
        *out = files.release();
        return 0;
    } catch (const mbx_files::FileError& e) {
        return fail(error, e.file(), e.line(), e.message());
    } catch (const std::bad_alloc&) {
        return fail(error, path, 0, "out of memory");
    } catch (const std::exception& e) {
        return fail(error, path, 0, e.what());
    }
}

extern "C" const mbx_host* mbx_files_host(const mbx_file_host* files) {
    return files && files->adapter ? files->adapter->table() : nullptr;
}

extern "C" void mbx_files_close(mbx_file_host* files) { delete files; }

extern "C" const char* mbx_files_description(const mbx_file_host* files) {
    return files ? files->description.c_str() : "";
}
