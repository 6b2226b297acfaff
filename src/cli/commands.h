// The rayproc command line: one function per subcommand, each returning the process status.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace rayproc::cli {

// Registers a subcommand on the app; the returned function runs it after parsing.
std::function<int()> addRenderCommand(CLI::App& app);
std::function<int()> addInfoCommand(CLI::App& app);
// Its function catches its own errors: 0 within limits, 1 a limit exceeded, 2 an error.
std::function<int()> addDiffCommand(CLI::App& app);
std::function<int()> addBenchCommand(CLI::App& app);

// Prints "rayproc: <message>" to stderr.
void printError(const std::string& message);

} // namespace rayproc::cli
