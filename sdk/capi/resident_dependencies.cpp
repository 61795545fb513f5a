// libmbx can be unloaded and loaded again by its host (dlclose, then dlopen;
// tests/integration/plugin_reload_test.cpp), but three of the libraries it
// brings in through Ceres must not go with it:
//  - gflags keeps its flag registry in memory it never frees: unloading it
//    loses that memory on every cycle;
//  - glog registers its flags in that registry when it loads: loaded again
//    into a registry that survived, gflags takes the second registration for
//    a flag linked twice and ends the process;
//  - libgomp keeps its thread-pool state the same way.
// So when libmbx loads, these (if the process holds them) are made resident
// (RTLD_NODELETE on the copy already loaded): they stay when libmbx goes, and
// a later load finds them as they were. libmbx itself and everything else it
// loaded are unmapped. The cost is their pages (about 2 MB) after an unload.
#include <dlfcn.h>
#include <link.h>

#include <cstring>
#include <initializer_list>

namespace {

bool keeps_process_state(const char* path) {
    const char* base = std::strrchr(path, '/');
    base = base ? base + 1 : path;
    for (const char* stem : {"libgflags.so", "libglog.so", "libgomp.so"})
        if (std::strncmp(base, stem, std::strlen(stem)) == 0) return true;
    return false;
}

int make_resident(dl_phdr_info* info, size_t, void*) {
    if (info->dlpi_name && *info->dlpi_name && keeps_process_state(info->dlpi_name)) {
        // A second reference, never closed, on the copy already loaded.
        if (void* handle = dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE)) (void)handle;
    }
    return 0;
}

struct ResidentDependencies {
    ResidentDependencies() { dl_iterate_phdr(make_resident, nullptr); }
} resident_dependencies;

}  // namespace
