#include "texture/oiio_module.h"

#include "image/image.h"

#include <dlfcn.h>

#include <filesystem>
#include <mutex>
#include <optional>
#include <vector>

namespace rayproc {

namespace {

constexpr const char* kModuleName = "librayproc_oiio.so";

std::vector<std::string> candidatePaths() {
    std::vector<std::string> paths;
    std::error_code ec;
    std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) paths.push_back((exe.parent_path() / kModuleName).string());
#ifdef RAYPROC_OIIO_MODULE
    if (paths.empty() || paths.front() != RAYPROC_OIIO_MODULE) paths.push_back(RAYPROC_OIIO_MODULE);
#endif
    return paths;
}

// Loads the first candidate that exists; the message lists every place and why it failed.
OiioModule load() {
    std::string tried;
    auto failed = [&](const std::string& path, const std::string& why) {
        tried += (tried.empty() ? "" : "; ") + path + ": " + why;
    };
    for (const std::string& path : candidatePaths()) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
            failed(path, "no such file");
            continue;
        }
        // RTLD_LOCAL: OpenImageIO's symbols stay the module's; RTLD_NOW: a broken install
        // fails here, once, not in the middle of a read.
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = dlerror();
            failed(path, why ? why : "dlopen failed");
            continue;
        }
        OiioModule m;
        m.open = reinterpret_cast<RayprocOiioOpenFn>(dlsym(handle, "rayproc_oiio_open"));
        m.read = reinterpret_cast<RayprocOiioReadFn>(dlsym(handle, "rayproc_oiio_read"));
        m.close = reinterpret_cast<RayprocOiioCloseFn>(dlsym(handle, "rayproc_oiio_close"));
        if (!m.open || !m.read || !m.close) {
            failed(path, "not a rayproc image module (no rayproc_oiio_* functions)");
            dlclose(handle);
            continue;
        }
        m.path = path; // the handle stays open for the process's life
        return m;
    }
    throw ImageIoError(std::string("the image reader module ") + kModuleName +
                       " (OpenImageIO) could not be loaded (" + tried + ")");
}

} // namespace

const OiioModule& OiioModule::get() {
    static std::mutex mutex;
    static std::optional<OiioModule> module;
    std::lock_guard<std::mutex> lock(mutex);
    if (!module) module = load(); // a failure is not kept: the next texture tries again
    return *module;
}

} // namespace rayproc
