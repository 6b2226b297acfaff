// OpenImageIO, loaded when the first texture image is read. The library brings about 260 shared
// objects (OpenCV, FFmpeg, GDAL, ...) whose relocation took ~0.17 s at every start of a process
// that links it, textures or not (docs/dependencies.md). So rayproc does not link it: the
// module `librayproc_oiio.so` (src/plugins/oiio_reader.cpp) does, and exports the three C
// functions below; OiioModule dlopen()s it on first use.
//
// The module is looked for beside the running executable, then where this build put it
// (RAYPROC_OIIO_MODULE, the build tree's absolute path; the tests run from build/tests).
#pragma once

#include <cstddef>
#include <string>

extern "C" {
// What a file holds: its size, channel count, which channel is alpha (-1: none named), and
// whether its samples are floating point (half, float or double) rather than integers.
struct RayprocOiioInfo {
    int width;
    int height;
    int channels;
    int alphaChannel;
    int isFloat;
};
// Opens the file: a handle, or null with the reason in error (NUL-terminated, truncated to
// errorSize).
typedef void* (*RayprocOiioOpenFn)(const char* path, RayprocOiioInfo* info, char* error,
                                   std::size_t errorSize);
// Reads the whole first subimage as floats, width x height x channels, row 0 on top; 0 with the
// reason in error on failure.
typedef int (*RayprocOiioReadFn)(void* handle, float* pixels, char* error, std::size_t errorSize);
typedef void (*RayprocOiioCloseFn)(void* handle);
}

namespace rayproc {

class OiioModule {
public:
    // The loaded module (loaded once per process, thread-safe); throws ImageIoError when it
    // cannot be found or lacks the functions, naming where it looked.
    static const OiioModule& get();

    RayprocOiioOpenFn open = nullptr;
    RayprocOiioReadFn read = nullptr;
    RayprocOiioCloseFn close = nullptr;
    std::string path; // the file that was loaded
};

} // namespace rayproc
