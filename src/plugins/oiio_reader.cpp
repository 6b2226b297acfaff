// The image reader module librayproc_oiio.so: OpenImageIO behind three C functions, so that
// only processes that read a texture image load OpenImageIO and the ~260 libraries it brings
// (texture/oiio_module.h loads this module; texture/texture_image.cpp decodes what it reads).
#include "texture/oiio_module.h"

#include <OpenImageIO/imageio.h>

#include <cstring>
#include <memory>
#include <string>

namespace {

void setError(char* error, std::size_t size, const std::string& message) {
    if (!error || size == 0) return;
    std::size_t n = std::min(size - 1, message.size());
    std::memcpy(error, message.data(), n);
    error[n] = '\0';
}

} // namespace

extern "C" {

__attribute__((visibility("default"))) void*
rayproc_oiio_open(const char* path, RayprocOiioInfo* info, char* error, std::size_t errorSize) {
    try {
        std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
        if (!in) {
            setError(error, errorSize, OIIO::geterror());
            return nullptr;
        }
        const OIIO::ImageSpec& spec = in->spec();
        info->width = spec.width;
        info->height = spec.height;
        info->channels = spec.nchannels;
        info->alphaChannel = spec.alpha_channel;
        info->isFloat = spec.format.basetype == OIIO::TypeDesc::FLOAT ||
                        spec.format.basetype == OIIO::TypeDesc::HALF ||
                        spec.format.basetype == OIIO::TypeDesc::DOUBLE;
        return in.release();
    } catch (const std::exception& e) { // nothing may cross the C boundary
        setError(error, errorSize, e.what());
        return nullptr;
    }
}

__attribute__((visibility("default"))) int rayproc_oiio_read(void* handle, float* pixels,
                                                             char* error, std::size_t errorSize) {
    auto* in = static_cast<OIIO::ImageInput*>(handle);
    try {
        const OIIO::ImageSpec& spec = in->spec();
        if (spec.tile_width > 0) {
            if (in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels)) return 1;
        } else {
            // Scanline files one row at a time: read_image converts them in chunks of many rows
            // whatever the image's height, and a 291-byte Radiance file claiming 200,000 x 3
            // pixels made it allocate 614 MB (the image fuzzer, stop 28).
            const std::size_t row = std::size_t(spec.width) * std::size_t(spec.nchannels);
            bool ok = true;
            for (int y = 0; ok && y < spec.height; ++y)
                ok = in->read_scanline(spec.y + y, spec.z, OIIO::TypeDesc::FLOAT,
                                       pixels + std::size_t(y) * row);
            if (ok) return 1;
        }
        setError(error, errorSize, in->geterror());
    } catch (const std::exception& e) {
        setError(error, errorSize, e.what());
    }
    return 0;
}

__attribute__((visibility("default"))) void rayproc_oiio_close(void* handle) {
    delete static_cast<OIIO::ImageInput*>(handle);
}

} // extern "C"
