// rayproc serve SCENE [--port P]: the interactive multi-mode page (docs/serve.md).
#include "cli/commands.h"
#include "engine/cancel.h"
#include "serve/server.h"
#include "serve/session.h"

#include <chrono>
#include <cstdio>
#include <thread>

namespace rayproc::cli {

namespace {

struct ServeArgs {
    std::string scene;
    int port = 8080;
    int threads = 0;
    int previewSize = 512;
    bool previewSizeGiven = false;
};

int runServe(const ServeArgs& a) {
    serve::Session::Options options;
    options.threads = a.threads;
    options.previewMaxSide = a.previewSize;
    serve::Session session(a.scene, options);
    // The preview is never larger than the scene's resolution: a size asked for above it is
    // said, not silently capped (the default is capped without a word).
    if (a.previewSizeGiven) {
        std::string note = session.previewSizeNote(a.previewSize);
        if (!note.empty()) std::fprintf(stderr, "rayproc serve: warning: %s\n", note.c_str());
    }
    // Ctrl-C (or SIGTERM, SIGHUP) stops the server; a render's cancel is not a signal. The
    // handler's own words are about partial images, which serve does not write.
    installInterruptHandler();
    quietInterruptMessages();
    serve::Server server(session, a.port);
    std::fprintf(stderr, "rayproc serve %s: open http://127.0.0.1:%d/ (Ctrl-C stops)\n",
                 a.scene.c_str(), server.port());
    std::printf("http://127.0.0.1:%d/\n", server.port());
    std::fflush(stdout);
    while (interruptSignal() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::fprintf(stderr, "rayproc serve: stopping\n");
    // The worker first (a render in progress is cancelled; it sends nothing more), then the
    // server (declared last, destroyed first) while the session still exists for its threads.
    session.stop();
    return 0;
}

} // namespace

std::function<int()> addServeCommand(CLI::App& app) {
    auto args = std::make_shared<ServeArgs>();
    CLI::App* cmd = app.add_subcommand(
        "serve", "Interactive page: live preview, scene editing, renders in every mode");
    cmd->add_option("scene", args->scene,
                    "Scene file: JSON scenes can be edited and saved; pbrt-v4 scenes can be "
                    "viewed and rendered")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--port", args->port,
                    "Port on 127.0.0.1 (default 8080; 0: the first free one from 8080 up)")
        ->check(CLI::Range(0, 65535));
    cmd->add_option("--threads", args->threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    CLI::Option* previewSize =
        cmd->add_option("--preview-size", args->previewSize,
                        "The live preview's longer side in pixels (default 512; renders in the "
                        "other modes use the scene's resolution); at most the scene's resolution: "
                        "a larger size is capped with a warning")
            ->check(CLI::Range(16, 4096));
    cmd->footer("The page is served from the binary itself; nothing is fetched from elsewhere. "
                "It listens on 127.0.0.1 only. Exit status: 0 after Ctrl-C, 1 bad input or a "
                "port in use.");
    return [args, previewSize] {
        args->previewSizeGiven = previewSize->count() > 0;
        return runServe(*args);
    };
}

} // namespace rayproc::cli
