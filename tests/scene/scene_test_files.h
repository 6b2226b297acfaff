// Scene files for the loader tests: written into a per-process temporary folder, loaded, and
// their InputError messages checked for the file, the location and the cause.
#pragma once

#include "core/error.h"
#include "scene/scene_loader.h"

#include <catch2/catch.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace rayproc::test {

// A folder of this process's test files, removed when the process ends.
struct SceneTestDir {
    std::filesystem::path path = std::filesystem::temp_directory_path() /
                                 ("rayproc-scene-tests-" + std::to_string(::getpid()));
    SceneTestDir() { std::filesystem::create_directories(path / "meshes"); }
    ~SceneTestDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

inline const std::filesystem::path& sceneTestDir() {
    static SceneTestDir dir;
    return dir.path;
}

// Writes `text` to `name` (relative to the test folder) and returns the full path.
inline std::string writeTestFile(const std::string& name, const std::string& text) {
    std::filesystem::path p = sceneTestDir() / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
}

inline std::filesystem::path sourceScenes() {
    return std::filesystem::path(RAYPROC_SOURCE_DIR) / "scenes";
}

// Loads a scene that must fail and returns the message; a scene that loads fails the test.
inline std::string loadErrorOf(const std::string& path) {
    try {
        loadScene(path);
    } catch (const InputError& e) {
        return e.what();
    }
    FAIL("expected an InputError from " << path);
    return {};
}

// The message must be "<file>: <location>: <problem>" with `cause` somewhere in the problem.
inline void checkLoadError(const std::string& name, const std::string& text,
                           const std::string& location, const std::string& cause) {
    std::string path = writeTestFile(name, text);
    std::string message = loadErrorOf(path);
    INFO("message: " << message);
    CHECK(message.rfind(path + ": " + location + ": ", 0) == 0);
    CHECK_THAT(message, Catch::Matchers::Contains(cause));
}

// A valid node list, for scenes whose mistake is elsewhere.
inline const char* kOneSphere =
    R"("nodes": [{"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 1}])";
inline const char* kOneMaterial = R"("materials": {"m": {"type": "diffuse"}})";

} // namespace rayproc::test
