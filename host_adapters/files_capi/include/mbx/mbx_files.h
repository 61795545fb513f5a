/*
 * mbx_files: the file hosts as a C library (libmbx_files.so).
 *
 * libmbx only translates what an mbx_host serves. A CAD plugin serves its own
 * assembly; a script or a test that starts from files (a CAD export with the
 * mesh files or scene it names) needs the same readers the `mbx` CLI uses.
 * This library is those readers behind a C interface, so C hosts and the
 * Python package (over ctypes) can use them. The format of an input is told
 * from its root element or extension, as `mbx formats` lists: today
 * SimMechanics first-generation Physical Modeling XML (*.xml) with its mesh
 * files or a VRML97 scene. It does not link libmbx: it only fills an mbx_host
 * table.
 *
 *   mbx_file_host *files = NULL;
 *   mbx_files_error err = { sizeof err };
 *   if (mbx_files_open("arm.xml", NULL, &files, &err) != 0) { report err.file, err.line, err.message }
 *   mbx_translate(ctx, mbx_files_host(files), NULL, &mechanism);
 *   ... mbx_mechanism_release_host(mechanism) or mbx_mechanism_destroy(mechanism) ...
 *   mbx_files_close(files);
 *
 * ABI rules as in mbx.h: structs start with struct_size and only grow.
 */
#ifndef MBX_FILES_H
#define MBX_FILES_H

#include <mbx/mbx.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mbx_file_host mbx_file_host;

typedef struct mbx_files_options {
    uint32_t struct_size;
    const char *shapes;            /* VRML97 scene matched to the bodies by pose; NULL or "": none */
    const char *const *mesh_dirs;  /* searched for the mesh files an input names after its own folder */
    uint32_t mesh_dir_count;
    /* --- since URDF input (a caller's smaller struct_size leaves these out) --- */
    const char *const *package_paths; /* "name=dir" each: a URDF's package://name/... (docs/urdf.md) */
    uint32_t package_path_count;
    int32_t floating_base;            /* 1: a URDF's root link moves freely */
} mbx_files_options;

/* The struct as the first callers knew it: any struct_size from this on is accepted. */
#define MBX_FILES_OPTIONS_V1_SIZE (offsetof(mbx_files_options, mesh_dir_count) + sizeof(uint32_t))

/* Why a file could not be opened. Strings stay valid until the next
 * mbx_files_open call on this thread. */
typedef struct mbx_files_error {
    uint32_t struct_size;
    const char *file;    /* the input, scene or mesh file at fault */
    int32_t line;        /* 1-based, 0 when the file as a whole is at fault */
    const char *message; /* without the file and line */
} mbx_files_error;

/* Reads the input (and the VRML scene) and checks the mesh files it names;
 * meshes load lazily, when the SDK first asks for a body's shapes. Returns
 * 0 and *out on success; non-zero and fills *error (may be NULL) for an
 * unreadable or unusable file. `options` may be NULL. */
MBX_API int mbx_files_open(const char *path, const mbx_files_options *options, mbx_file_host **out,
                           mbx_files_error *error);
/* The host table; valid until mbx_files_close. A mechanism translated from
 * it must be destroyed, or must release the host, before the close. */
MBX_API const mbx_host *mbx_files_host(const mbx_file_host *files);
MBX_API void mbx_files_close(mbx_file_host *files);
/* What the input says beyond the assembly (a URDF's joint dynamics and
 * collision shapes) as a description file's text, for
 * mbx_mechatronics_load_drives_text before the user's own description; ""
 * when nothing. Valid until mbx_files_close. */
MBX_API const char *mbx_files_description(const mbx_file_host *files);

#ifdef __cplusplus
}
#endif

#endif /* MBX_FILES_H */
