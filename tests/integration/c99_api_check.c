/*
 * mbx.h must be usable from strict C99 (built with -std=c99 -Wall -Wextra
 * -pedantic -Werror): this file includes it, touches its types and macros,
 * and loads the plugin the way a C host would.
 * Usage: mbx_c99_api_check <path to libmbx.so>. Exit 0 on success.
 */
#define _POSIX_C_SOURCE 200809L

#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

#include <mbx/mbx.h>

/* Compile-time checks, C99 style (no _Static_assert). */
typedef char check_host_v1_smaller[(MBX_HOST_V1_SIZE < sizeof(mbx_host)) ? 1 : -1];
typedef char check_struct_size_first[(offsetof(mbx_body_desc, struct_size) == 0) ? 1 : -1];
typedef char check_abi_version[(MBX_ABI_VERSION >= 2u) ? 1 : -1];

static int count_bodies(void *user_data, size_t *out_count) {
    (void)user_data;
    *out_count = 0;
    return 0;
}

int main(int argc, char **argv) {
    void *library;
    void *symbol;
    mbx_plugin_api_fn entry;
    const mbx_api *api;
    const char *version;
    mbx_host host;
    mbx_body_desc body;
    mbx_units units = {1e-3, 1e-3, 0.0};
    mbx_context *context = NULL;
    size_t count = 1;

    if (argc != 2) {
        fprintf(stderr, "usage: %s <libmbx.so>\n", argv[0]);
        return 2;
    }
    library = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        return 1;
    }
    symbol = dlsym(library, MBX_PLUGIN_ENTRY_NAME);
    if (!symbol) {
        fprintf(stderr, "no %s\n", MBX_PLUGIN_ENTRY_NAME);
        return 1;
    }
    /* ISO C has no object-to-function pointer conversion; copy the bits. */
    memcpy(&entry, &symbol, sizeof entry);
    api = entry(MBX_ABI_VERSION);
    if (!api || api->struct_size < offsetof(mbx_api, abi_version_fn)) {
        fprintf(stderr, "no usable API table\n");
        return 1;
    }
    version = api->version();
    if (!version || !*version) {
        fprintf(stderr, "empty mbx_version\n");
        return 1;
    }

    memset(&body, 0, sizeof body);
    body.struct_size = (uint32_t)offsetof(mbx_body_desc, mass);
    body.units = units;
    if (MBX_FIELD_FITS(&body, mbx_body_desc, mass) || !MBX_FIELD_FITS(&body, mbx_body_desc, units)) {
        fprintf(stderr, "MBX_FIELD_FITS is wrong\n");
        return 1;
    }

    memset(&host, 0, sizeof host);
    host.struct_size = sizeof host;
    host.abi_version = MBX_HOST_ABI_VERSION;
    host.body_count = count_bodies;
    if (!MBX_FIELD_FITS(&host, mbx_host, describe_assembly) || host.body_count(NULL, &count) != 0 || count != 0) {
        fprintf(stderr, "host table checks failed\n");
        return 1;
    }
    if (api->context_create(&context) != MBX_OK || !context) {
        fprintf(stderr, "context_create failed\n");
        return 1;
    }
    if (api->translate(context, NULL, NULL, NULL) != MBX_ERROR_INVALID_ARGUMENT) {
        fprintf(stderr, "NULL arguments were not refused\n");
        api->context_destroy(context);
        return 1;
    }
    api->context_destroy(context);
    printf("mbx %s (%s) from C99\n", version, api->status_name(MBX_OK));
    dlclose(library);
    return 0;
}
