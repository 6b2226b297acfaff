// The rayproc command line: one function per subcommand, each returning the process status.
#pragma once

#include "core/option_checks.h"

#include <CLI/CLI.hpp>

#include <functional>
#include <memory>
#include <string>

namespace rayproc::cli {

// What each subcommand runs once the command line is parsed.
struct Commands {
    std::function<int()> render, info, diff, bench, serve;
};
// The whole command line (main() and the command-line fuzzer parse with the same app).
std::unique_ptr<CLI::App> makeApp(Commands& commands);
// The process status for a CLI::ParseError whose CLI11 status (app.exit()) is cliStatus.
int usageStatus(const CLI::App& app, int cliStatus);

// Registers a subcommand on the app; the returned function runs it after parsing.
std::function<int()> addRenderCommand(CLI::App& app);
std::function<int()> addInfoCommand(CLI::App& app);
// Its function catches its own errors: 0 within limits, 1 a limit exceeded, 2 an error.
std::function<int()> addDiffCommand(CLI::App& app);
std::function<int()> addBenchCommand(CLI::App& app);
std::function<int()> addServeCommand(CLI::App& app);

// finiteNumber and finiteFloat, the float options' checks: core/option_checks.h.

// Prints "rayproc: <message>" to stderr.
void printError(const std::string& message);

} // namespace rayproc::cli
