// Texture files read without OpenImageIO: a process that reads only these never loads the
// ~260 libraries OpenImageIO brings (0.2 s of a textured scene's serial load, docs/performance.md).
// Each gives exactly the floats OpenImageIO's reader gives for the same file (texture tests hold
// them to it), so images do not depend on which reader read a texture:
// - TGA without a colour map, 8-bit grey or 24-bit colour, not run-length encoded (stb_image;
//   a stored alpha channel goes to OpenImageIO, which premultiplies it, and so do run-length
//   encoded files, whose truncation stb_image would not notice);
// - PFM, colour or grey (rayproc's own reader).
// Anything else, or a file these readers refuse, goes to OpenImageIO as before.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace rayproc {

// A decoded file: width x height x channels floats, row 0 on top.
struct RawPixels {
    int width = 0, height = 0, channels = 0;
    int alphaChannel = -1; // -1: none named
    bool isFloat = false;  // floating-point samples (linear), else integers (encoded)
    std::vector<float> pixels;
    // Or 8-bit samples kept as the decoder's bytes (the TGA reader; `pixels` then empty):
    // each is byteSample(b), so a decode is a table of 256.
    std::shared_ptr<const unsigned char> bytes;
};

// An 8-bit sample as OpenImageIO converts it to float: v times the reciprocal of 255.
inline float byteSample(unsigned char v) { return float(v) * (1.0f / 255.0f); }

// Reads `path` when it is one of the formats above: true with out filled, false when the file
// is not one of them (or is one these readers cannot read), for OpenImageIO to read.
bool readWithoutOiio(const std::string& path, RawPixels& out);

} // namespace rayproc
