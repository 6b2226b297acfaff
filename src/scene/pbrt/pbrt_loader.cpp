#include "scene/pbrt/pbrt_loader.h"

#include "core/error.h"
#include "scene/pbrt/mapped_file.h"
#include "scene/pbrt/pbrt_parser.h"

#include <cctype>
#include <cstdio>

namespace rayproc {

namespace {

std::unique_ptr<Scene> load(std::string_view text, const std::string& path,
                            std::vector<std::string>* warningsOut) {
    pbrt::Warnings warnings;
    auto report = [&] {
        std::vector<std::string> lines = warnings.lines();
        if (warningsOut)
            *warningsOut = lines;
        else
            for (const std::string& l : lines) std::fprintf(stderr, "%s\n", l.c_str());
    };
    auto scene = std::make_unique<Scene>();
    std::deque<std::string> names; // outlives every SourceLoc of this load
    try {
        pbrt::SceneBuilder builder(*scene, warnings, path);
        try {
            pbrt::parsePbrt(text, path, builder, names);
        } catch (...) {
            builder.joinLoads(); // a PLY file before the parser's error fails first
            throw;
        }
        builder.finish();
    } catch (...) {
        report(); // what was understood before the error may explain it
        throw;
    }
    report();
    return scene;
}

} // namespace

bool isPbrtPath(const std::string& path) {
    if (path.size() < 5) return false;
    std::string ext = path.substr(path.size() - 5);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".pbrt";
}

std::unique_ptr<Scene> loadPbrtScene(const std::string& path, std::vector<std::string>* warnings) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw InputError(path + ": is a directory, not a scene file");
    if (!std::filesystem::exists(path, ec))
        throw InputError(path + ": cannot open the scene file (missing or unreadable)");
    pbrt::MappedFile file(path);
    return load(file.data(), path, warnings);
}

std::unique_ptr<Scene> loadPbrtSceneFromString(const std::string& text, const std::string& path,
                                               std::vector<std::string>* warnings) {
    return load(text, path, warnings);
}

} // namespace rayproc
