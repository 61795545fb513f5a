#include "plugin_loader.h"

#include <dlfcn.h>

#include <cstring>
#include <utility>

namespace mbx_stub {

Plugin::~Plugin() { unload(); }

Plugin::Plugin(Plugin&& other) noexcept
    : handle_(std::exchange(other.handle_, nullptr)),
      api_(std::exchange(other.api_, nullptr)),
      path_(std::move(other.path_)) {}

Plugin& Plugin::operator=(Plugin&& other) noexcept {
    if (this != &other) {
        unload();
        handle_ = std::exchange(other.handle_, nullptr);
        api_ = std::exchange(other.api_, nullptr);
        path_ = std::move(other.path_);
    }
    return *this;
}

void Plugin::unload() {
    api_ = nullptr;
    if (handle_) dlclose(handle_);
    handle_ = nullptr;
}

bool Plugin::load(const std::string& path, std::string* error) {
    unload();
    auto failed = [&](const std::string& why) {
        if (error) *error = why;
        unload();
        return false;
    };
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle_) {
        const char* why = dlerror();
        return failed("cannot load plugin '" + path + "': " + (why ? why : "unknown dlopen error"));
    }
    dlerror();
    void* symbol = dlsym(handle_, MBX_PLUGIN_ENTRY_NAME);
    if (!symbol) return failed("plugin '" + path + "' has no entry point " MBX_PLUGIN_ENTRY_NAME);
    // POSIX guarantees a data pointer from dlsym converts to a function pointer.
    mbx_plugin_api_fn entry;
    std::memcpy(&entry, &symbol, sizeof entry);
    const mbx_api* api = entry(MBX_ABI_VERSION);
    if (!api) return failed("plugin '" + path + "' refused host ABI version " + std::to_string(MBX_ABI_VERSION));
    if (api->struct_size < MBX_STUB_API_V1_SIZE)
        return failed("plugin '" + path + "' returned an API table of " + std::to_string(api->struct_size) +
                      " bytes, smaller than version 1 (" + std::to_string(MBX_STUB_API_V1_SIZE) + ")");
    if (api->abi_version < 1)
        return failed("plugin '" + path + "' reports ABI version " + std::to_string(api->abi_version));
    api_ = api;
    path_ = path;
    return true;
}

uint32_t Plugin::abi_version() const {
    if (!api_) return 0;
    if (MBX_FIELD_FITS(api_, mbx_api, abi_version_fn) && api_->abi_version_fn) return api_->abi_version_fn();
    return api_->abi_version;
}

}  // namespace mbx_stub
