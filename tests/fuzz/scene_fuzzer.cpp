// libFuzzer target for the scene readers: the JSON loader (syntax, types, ranges, references,
// the node hierarchy), the pbrt-v4 importer (tokenizer, parameter lists, directives, shapes,
// materials, lights) and the PLY parser, on arbitrary bytes.
//
// One target serves all three so that one fuzz run covers them and the seed corpus can be the
// scene files as they are. The input picks its reader by its first bytes:
//   "ply"                                -> the PLY parser (what a pbrt plymesh reads)
//   first non-blank byte a letter or '#' -> the pbrt importer (directives or a comment)
//   anything else                        -> the JSON loader (a scene is an object: '{')
//
// The contract under test: every input either loads or throws rayproc::InputError. Any other
// exception (bad_alloc, length_error, a library's own exception), a crash, a sanitizer report,
// an allocation beyond libFuzzer's -malloc_limit_mb or a hang is a finding. Nothing is handed to
// Embree: the readers are what parses untrusted bytes, and executions stay fast.
//
// Relative file references (OBJ, PLY, Include) resolve against a directory that does not
// exist, so they exercise the "file not found" paths and never read the machine's files.
#include "core/error.h"
#include "scene/pbrt/pbrt_loader.h"
#include "scene/pbrt/ply_reader.h"
#include "scene/scene_loader.h"

#include <cctype>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace {

enum class Reader { Json, Pbrt, Ply };

Reader pickReader(const std::string& text) {
    if (text.compare(0, 3, "ply") == 0) return Reader::Ply;
    for (char c : text) {
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r') continue;
        return std::isalpha(static_cast<unsigned char>(c)) || c == '#' ? Reader::Pbrt
                                                                       : Reader::Json;
    }
    return Reader::Json;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        switch (pickReader(text)) {
        case Reader::Ply:
            rayproc::pbrt::parsePly(text, "/nonexistent/rayproc-fuzz/mesh.ply");
            break;
        case Reader::Pbrt: {
            std::vector<std::string> warnings; // collected, not printed
            rayproc::loadPbrtSceneFromString(text, "/nonexistent/rayproc-fuzz/scene.pbrt",
                                             &warnings);
            break;
        }
        case Reader::Json:
            rayproc::loadSceneFromString(text, "/nonexistent/rayproc-fuzz/scene.json");
            break;
        }
    } catch (const rayproc::InputError&) {
        // The expected outcome for malformed input: a clear error, nothing else.
    }
    return 0;
}
