// libFuzzer target for the OBJ reader: rayproc's strict statement check, then tinyobjloader's
// parse and triangulation, then the index validation and vertex merging, on arbitrary bytes.
//
// The contract under test: every input either loads or throws rayproc::InputError; a loaded
// mesh's indices all name one of its vertices and its positions are finite. Any other
// exception, a crash, a sanitizer report, an allocation beyond -malloc_limit_mb or a hang is a
// finding.
#include "core/error.h"
#include "scene/obj_loader.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string text(reinterpret_cast<const char*>(data), size);
    try {
        rayproc::TriangleMesh mesh = rayproc::parseObjMesh(std::move(text), "fuzz.obj");
        for (std::uint32_t i : mesh.indices)
            if (i >= mesh.positions.size()) std::abort();
        for (const rayproc::Vec3& p : mesh.positions)
            if (!rayproc::isFinite(p)) std::abort();
    } catch (const rayproc::InputError&) {
        // The expected outcome for malformed input.
    }
    return 0;
}
