// rayproc: a global-illumination renderer built as a data-parallel ray processor.
#include "cli/commands.h"
#include "core/error.h"
#include "image/image.h"

#include <cstdio>
#include <exception>
#include <memory>

int main(int argc, char** argv) {
    rayproc::cli::Commands commands;
    std::unique_ptr<CLI::App> app = rayproc::cli::makeApp(commands);
    try {
        app->parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rayproc::cli::usageStatus(*app, app->exit(e));
    }
    // Every error that escapes a command ends here as one clear line and a non-zero status.
    try {
        if (app->got_subcommand("render")) return commands.render();
        if (app->got_subcommand("info")) return commands.info();
        if (app->got_subcommand("diff")) return commands.diff();
        if (app->got_subcommand("bench")) return commands.bench();
    } catch (const rayproc::InputError& e) {
        rayproc::cli::printError(e.what());
    } catch (const rayproc::ImageIoError& e) {
        rayproc::cli::printError(e.what());
    } catch (const std::bad_alloc&) {
        rayproc::cli::printError("out of memory (lower --width/--height, or --photons and "
                                 "--caustic-photons in gi mode)");
    } catch (const std::exception& e) {
        rayproc::cli::printError(std::string("error: ") + e.what());
    }
    return 1;
}
