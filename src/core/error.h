// The three kinds of errors (STYLE.md §7): user input errors carry where the input was wrong;
// invariants are CHECKs; everything is caught at the CLI boundary and turned into a message.
#pragma once

#include <stdexcept>
#include <string>

namespace rayproc {

// Bad user input: a scene file, an image, a command-line value. what() is the full message,
// "<file>: <location>: <problem>", ready to print.
class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
    // location is a JSON path such as "/nodes/3/material" or "line 4, column 17".
    InputError(const std::string& file, const std::string& location, const std::string& problem)
        : std::runtime_error(file + ": " + location + ": " + problem) {}
};

[[noreturn]] void checkFailed(const char* expr, const char* file, int line);

} // namespace rayproc

// Invariant checks stay on in release builds: a renderer that silently continues past a broken
// invariant produces wrong images that nobody notices.
#define RAYPROC_CHECK(expr)                                                                    \
    do {                                                                                       \
        if (!(expr)) ::rayproc::checkFailed(#expr, __FILE__, __LINE__);                        \
    } while (0)
