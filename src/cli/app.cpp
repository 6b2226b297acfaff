#include "cli/commands.h"

namespace rayproc::cli {

std::unique_ptr<CLI::App> makeApp(Commands& commands) {
    auto app = std::make_unique<CLI::App>(
        "rayproc " RAYPROC_VERSION
        " - a multi-mode global-illumination renderer (ray-processor architecture).\n"
        "Run 'rayproc COMMAND --help' for the options of a command.",
        "rayproc");
    app->require_subcommand(1);
    app->set_version_flag("--version", "rayproc " RAYPROC_VERSION);
    commands.render = addRenderCommand(*app);
    commands.info = addInfoCommand(*app);
    commands.diff = addDiffCommand(*app);
    commands.bench = addBenchCommand(*app);
    commands.serve = addServeCommand(*app);
    return app;
}

int usageStatus(const CLI::App& app, int cliStatus) {
    // --help and --version are 0. Usage errors are 1, as --help says, not CLI11's own codes
    // (105, 106, ...); diff's status 1 means "a limit was exceeded", so its usage errors are 2.
    if (cliStatus == 0) return 0;
    return app.got_subcommand("diff") ? 2 : 1;
}

} // namespace rayproc::cli
