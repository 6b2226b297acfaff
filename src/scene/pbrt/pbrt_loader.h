// pbrt-v4 scene files (.pbrt) into rayproc's Scene. What is supported, approximated and ignored
// is in docs/pbrt-import.md; in short: the transform and attribute directives, object
// instancing, perspective cameras, trianglemesh / plymesh / bilinearmesh / sphere / disk shapes,
// diffuse / conductor / dielectric / coateddiffuse materials, point / spot / distant / infinite
// lights and diffuse area lights.
//
// Malformed input is an InputError "file:line:column: problem". Anything valid but unsupported
// is a warning "file:line: warning: ..." (listed once, with a count if it recurs), and loading
// goes on with a documented fallback.
#pragma once

#include "scene/scene.h"

#include <memory>
#include <string>
#include <vector>

namespace rayproc {

// True if `path` ends in ".pbrt" (any case).
bool isPbrtPath(const std::string& path);

// Reads a pbrt scene. With `warnings` null, each warning is printed to stderr as one line;
// otherwise they are returned there (and nothing is printed).
std::unique_ptr<Scene> loadPbrtScene(const std::string& path,
                                     std::vector<std::string>* warnings = nullptr);

// The same from text in memory; `path` names the file in messages, and relative Include and
// PLY paths resolve from its directory.
std::unique_ptr<Scene> loadPbrtSceneFromString(const std::string& text, const std::string& path,
                                               std::vector<std::string>* warnings = nullptr);

} // namespace rayproc
