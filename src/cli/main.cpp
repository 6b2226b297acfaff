// rayproc: a global-illumination renderer built as a data-parallel ray processor.
#include "cli/commands.h"
#include "core/error.h"
#include "image/image.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    CLI::App app{"rayproc " RAYPROC_VERSION
                 " - a multi-mode global-illumination renderer (ray-processor architecture).\n"
                 "Run 'rayproc COMMAND --help' for the options of a command.",
                 "rayproc"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "rayproc " RAYPROC_VERSION);
    auto render = rayproc::cli::addRenderCommand(app);
    auto info = rayproc::cli::addInfoCommand(app);
    auto diff = rayproc::cli::addDiffCommand(app);
    auto bench = rayproc::cli::addBenchCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int status = app.exit(e);
        // --help and --version are 0. Usage errors are 1, as --help says, not CLI11's own codes
        // (105, 106, ...); diff's status 1 means "a limit was exceeded", so its usage errors are 2.
        if (status == 0) return 0;
        return app.got_subcommand("diff") ? 2 : 1;
    }
    // Every error that escapes a command ends here as one clear line and a non-zero status.
    try {
        if (app.got_subcommand("render")) return render();
        if (app.got_subcommand("info")) return info();
        if (app.got_subcommand("diff")) return diff();
        if (app.got_subcommand("bench")) return bench();
    } catch (const rayproc::InputError& e) {
        rayproc::cli::printError(e.what());
    } catch (const rayproc::ImageIoError& e) {
        rayproc::cli::printError(e.what());
    } catch (const std::bad_alloc&) {
        rayproc::cli::printError("out of memory");
    } catch (const std::exception& e) {
        rayproc::cli::printError(std::string("error: ") + e.what());
    }
    return 1;
}
