// rayproc: a global-illumination renderer built as a data-parallel ray processor.
#include "cli/commands.h"
#include "cluster/cluster.h"
#include "core/error.h"
#include "image/image.h"

#include <cstdio>
#include <exception>
#include <memory>
#include <sstream>

namespace {

// The command's status; errors become one clear line and status 1.
int runCommand(CLI::App& app, rayproc::cli::Commands& commands) {
    try {
        const rayproc::Cluster& cluster = rayproc::Cluster::world();
        if (cluster.distributed() && !app.got_subcommand("render"))
            throw rayproc::InputError("only 'render' runs across MPI ranks; run '" +
                                      std::string(app.get_subcommands().empty()
                                                      ? "rayproc"
                                                      : app.get_subcommands().front()->get_name()) +
                                      "' as one process (without mpirun)");
        if (app.got_subcommand("render")) return commands.render();
        if (app.got_subcommand("info")) return commands.info();
        if (app.got_subcommand("diff")) return commands.diff();
        if (app.got_subcommand("bench")) return commands.bench();
        if (app.got_subcommand("serve")) return commands.serve();
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

} // namespace

int main(int argc, char** argv) {
    // Under mpirun or srun every process is a rank of one render (docs/distributed.md).
    rayproc::Cluster::start(argc, argv);
    const rayproc::Cluster& cluster = rayproc::Cluster::world();
    rayproc::cli::Commands commands;
    std::unique_ptr<CLI::App> app = rayproc::cli::makeApp(commands);
    try {
        app->parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // Every rank parses the same arguments: rank 0 alone prints help and usage errors.
        std::ostringstream discard;
        int cliStatus = cluster.root() ? app->exit(e) : app->exit(e, discard, discard);
        int status = rayproc::cli::usageStatus(*app, cliStatus);
        rayproc::Cluster::finish();
        return status;
    }
    int status = runCommand(*app, commands);
    // A failed rank ends the whole job: the others may be waiting for it in a collective.
    // (Interrupted renders are not failures: every rank wrote or sent its share.)
    if (status == 1 && cluster.distributed()) rayproc::Cluster::abort(status);
    rayproc::Cluster::finish();
    return status;
}
