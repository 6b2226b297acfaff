// libFuzzer target for the command line: the real `rayproc` parser (src/cli/app.cpp: every
// subcommand, option, validator and range check) on arbitrary argument vectors. The input is
// split at NUL and newline bytes into arguments after "rayproc"; the commands are not run.
//
// The contract under test: parsing either succeeds or throws CLI::ParseError (which main()
// turns into a usage message and status 1, or 2 for diff). Any other exception
// (std::invalid_argument from a validator, say), a crash, a sanitizer report or a hang is a
// finding.
#include "cli/commands.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<std::string> args{"rayproc"};
    std::string current;
    for (std::size_t i = 0; i < size; ++i) {
        char c = char(data[i]);
        if (c == '\0' || c == '\n') {
            args.push_back(current);
            current.clear();
        } else {
            current.push_back(c);
        }
    }
    if (!current.empty()) args.push_back(current);
    if (args.size() > 64) return 0; // long vectors add nothing but time
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());

    rayproc::cli::Commands commands;
    std::unique_ptr<CLI::App> app = rayproc::cli::makeApp(commands);
    try {
        app->parse(int(argv.size()), argv.data());
    } catch (const CLI::ParseError&) {
        // Help, version and usage errors: main() prints them and exits 0, 1 or 2.
    }
    return 0;
}
