// Scene files: JSON (docs/scene-format.md) in, the hierarchical Scene of scene.h out.
//
// Every mistake in a scene file is an InputError "<file>: <location>: <problem>", where the
// location is the JSON pointer of the offending value (e.g. "/nodes/2/children/0/radius") or,
// for syntax errors, "line L, column C". The loader checks types, unknown keys, ranges, names
// and references up front, so that nothing downstream sees a malformed scene.
#pragma once

#include "scene/scene.h"

#include <memory>
#include <string>

namespace rayproc {

// The largest image a scene file (JSON or pbrt) or the command line may ask for: each side
// 1..16384 and at most 2^26 pixels (67 M; the film alone then holds several GiB).
constexpr long long kMaxImageSide = 16384;
constexpr long long kMaxImagePixels = 1LL << 26;

// Reads and validates a scene file, then computes the bounds of every node.
std::unique_ptr<Scene> loadScene(const std::string& path);

// The same from text already in memory; `path` names the file in messages and is where
// relative OBJ paths resolve from (its directory).
std::unique_ptr<Scene> loadSceneFromString(const std::string& text, const std::string& path);

} // namespace rayproc
