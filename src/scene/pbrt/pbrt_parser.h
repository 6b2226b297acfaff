// The syntactic half of the pbrt reader: reads directives, their positional arguments and
// parameter lists from a file and the files it Includes / Imports, and calls the SceneBuilder
// once per directive. Unknown directives and malformed arguments are InputErrors
// "file:line:column: problem".
#pragma once

#include "scene/pbrt/pbrt_builder.h"

#include <deque>
#include <string>
#include <string_view>

namespace rayproc::pbrt {

// Parses `text` (the contents of `path`) into `builder`. `names` stores the name of every file
// read; locations point into it, so it must outlive the builder's use of them.
void parsePbrt(std::string_view text, const std::string& path, SceneBuilder& builder,
               std::deque<std::string>& names);

} // namespace rayproc::pbrt
