// The rayproc command line: one function per subcommand, each returning the process status.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <functional>
#include <limits>
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

// Refuses NaN and infinities in a floating-point option: CLI11 reads "nan" and "inf" as
// numbers, and its Range and PositiveNumber checks let NaN through (every comparison with NaN
// is false). Attached to every float option of every command. With `floatRange`, also
// magnitudes beyond float's range (3.4e38), finite as text and in double but infinite once
// stored in a float.
inline CLI::Validator finiteNumber(bool floatRange = false) {
    return CLI::Validator(
        [floatRange](std::string& text) -> std::string {
            try {
                std::size_t used = 0;
                double v = std::stod(text, &used);
                if (!std::isfinite(v)) return "must be a finite number, got " + text;
                if (floatRange && std::abs(v) > double(std::numeric_limits<float>::max()))
                    return "must be at most 3.4e38 in magnitude (a float), got " + text;
            } catch (const std::exception&) {
                return {}; // not a number at all: the option's own conversion says so
            }
            return {};
        },
        "");
}

// finiteNumber for an option stored as a float.
inline CLI::Validator finiteFloat() { return finiteNumber(true); }

// Prints "rayproc: <message>" to stderr.
void printError(const std::string& message);

} // namespace rayproc::cli
