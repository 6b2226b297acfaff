// libFuzzer target for rayproc serve's message handler: Session::handle, which every WebSocket
// text frame reaches with its bytes as they came (src/serve/server.cpp). The input is split at
// newline bytes into up to 16 messages, sent in order to a fresh session on a small JSON scene
// (a sphere on a floor, a point light); after each one a pick sends one camera ray through
// Embree, so a camera or an edit that a message let through and Embree cannot trace is found
// here rather than by a page.
//
// The contract under test: handle never throws, and every reply is JSON text, an object with a
// "type" ("error" for whatever is refused). A crash (Embree's assertion on a ray out of its
// range), a sanitizer report, an escaping exception or a hang is a finding. The session's
// worker is not started (no preview renders: executions stay fast), and "save" writes only to
// a file of this process's temporary directory, whatever path the message names.
#include "serve/session.h"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using rayproc::serve::Json;

// This process's directory of the scene and saved files, removed when the process ends.
struct FuzzDir {
    std::filesystem::path path = std::filesystem::temp_directory_path() /
                                 ("rayproc-serve-fuzz-" + std::to_string(::getpid()));
    FuzzDir() {
        std::filesystem::create_directories(path);
        std::ofstream(path / "scene.json") << R"({
  "camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0], "resolution": [16, 12]},
  "materials": {"white": {"type": "diffuse", "color": [0.8, 0.8, 0.8]}},
  "lights": [{"type": "point", "name": "bulb", "position": [0, 2, 1], "intensity": [5, 5, 5]}],
  "nodes": [
    {"type": "quad", "name": "floor", "material": "white",
     "corners": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]},
    {"type": "sphere", "name": "ball", "material": "white", "center": [0, 0.5, 0], "radius": 0.5}
  ]
})";
    }
    ~FuzzDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

const std::filesystem::path& fuzzDir() {
    static const FuzzDir dir;
    return dir.path;
}

// A "save" goes to the temporary directory; every other message is passed on as it is.
std::string confined(const std::string& message) {
    Json m = Json::parse(message, nullptr, false);
    if (!m.is_object() || !m.contains("type") || m["type"] != "save") return message;
    if (m.contains("path") && m["path"].is_string())
        m["path"] = (fuzzDir() / "saved.json").string();
    return m.dump();
}

void checkReply(const std::string& reply) {
    Json r = Json::parse(reply, nullptr, false); // no exception: a discarded value if invalid
    if (r.is_discarded() || !r.is_object() || !r.contains("type") || !r["type"].is_string())
        std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<std::string> messages(1);
    for (std::size_t i = 0; i < size; ++i) {
        if (data[i] != '\n') {
            messages.back().push_back(char(data[i]));
        } else if (messages.size() < 16) {
            messages.emplace_back();
        }
    }
    rayproc::serve::Session session((fuzzDir() / "scene.json").string(), {1, 16});
    for (const std::string& m : messages) {
        checkReply(session.handle(confined(m), 1));
        checkReply(session.handle(R"({"type": "pick", "x": 0.5, "y": 0.5})", 1));
    }
    checkReply(session.handle(R"({"type": "state"})", 1));
    return 0;
}
