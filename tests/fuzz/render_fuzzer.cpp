// libFuzzer target for rendering what the scene readers accept: a scene that loads must render
// in every mode without a crash, an abort or an uncaught exception, and give finite images
// (render_one.h). scene_fuzzer covers the readers alone; this one follows their numbers into the
// engine, where light power beyond float's range once aborted gi and a Mitchell filter of
// B = 1e20 gave a black image. Seeds: tests/fuzz/render-seeds/ (scripts/fuzz).
#include "render_one.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    if (!rayproc::fuzz::allFinite(rayproc::fuzz::renderEveryMode(text))) std::abort();
    return 0;
}
