// Loads the mbx plugin the way a CAD system does: dlopen() the shared
// library, dlsym() the one entry point, ask it for the API table and check
// the table is one this host can use. Shared by mbx_stub_host and the
// integration tests, so both exercise the real dynamic-loading path.
#pragma once

#include <string>

#include <mbx/mbx.h>

namespace mbx_stub {

// Size of the version-1 mbx_api table: the least this host can work with.
#define MBX_STUB_API_V1_SIZE (offsetof(mbx_api, abi_version_fn))

class Plugin {
public:
    Plugin() = default;
    ~Plugin();
    Plugin(Plugin&& other) noexcept;
    Plugin& operator=(Plugin&& other) noexcept;
    Plugin(const Plugin&) = delete;
    Plugin& operator=(const Plugin&) = delete;

    // dlopen(RTLD_NOW | RTLD_LOCAL) + dlsym(MBX_PLUGIN_ENTRY_NAME) + checks of
    // the table's struct_size and abi_version. On failure returns false and
    // says why in *error (if given); the Plugin stays unloaded.
    bool load(const std::string& path, std::string* error = nullptr);
    void unload();

    bool loaded() const { return api_ != nullptr; }
    const mbx_api* api() const { return api_; }
    // The library's ABI version: abi_version_fn() when the table has it
    // (version 2), else the table's abi_version field.
    uint32_t abi_version() const;
    const std::string& path() const { return path_; }

private:
    void* handle_ = nullptr;
    const mbx_api* api_ = nullptr;
    std::string path_;
};

}  // namespace mbx_stub
