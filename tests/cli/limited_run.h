// Runs the rayproc binary under resource limits: RLIMIT_AS (an address-space cap that turns
// any unbounded allocation into a failure) and RLIMIT_FSIZE with SIGXFSZ ignored (writes past
// the cap fail with EFBIG, as on a full disk). posix_spawn cannot set limits, so this forks;
// the child only makes async-signal-safe calls between fork and exec.
#pragma once

#include "test_util.h"

#include <sys/resource.h>

#include <csignal>

namespace rayproc::test {

struct Limits {
    rlim_t addressSpace = RLIM_INFINITY; // bytes of virtual memory
    rlim_t fileSize = RLIM_INFINITY;     // bytes per written file
};

// AddressSanitizer reserves terabytes of shadow address space at start-up, so an address-space
// limit cannot apply to a sanitizer build; tests that rely on it skip themselves there.
constexpr bool kAddressSpaceLimitWorks =
#if defined(__SANITIZE_ADDRESS__)
    false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
    false;
#else
    true;
#endif
#else
    true;
#endif

inline RunResult runLimited(const std::vector<std::string>& args, const TempDir& dir,
                            const Limits& limits, double timeoutSeconds = 60) {
    static std::atomic<int> counter{0};
    int n = counter++;
    std::string outFile = dir.file("limited-stdout" + std::to_string(n) + ".txt");
    std::string errFile = dir.file("limited-stderr" + std::to_string(n) + ".txt");
    std::vector<std::string> all{rayprocBinary()};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);

    auto start = std::chrono::steady_clock::now();
    pid_t pid = ::fork();
    if (pid == 0) {
        int in = ::open("/dev/null", O_RDONLY);
        int out = ::open(outFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int err = ::open(errFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (in < 0 || out < 0 || err < 0) ::_exit(126);
        ::dup2(in, STDIN_FILENO);
        ::dup2(out, STDOUT_FILENO);
        ::dup2(err, STDERR_FILENO);
        struct sigaction ignore {};
        ignore.sa_handler = SIG_IGN;
        ::sigaction(SIGXFSZ, &ignore, nullptr); // an ignored signal stays ignored across exec
        struct sigaction deflt {};
        deflt.sa_handler = SIG_DFL;
        ::sigaction(SIGINT, &deflt, nullptr);
        sigset_t none;
        sigemptyset(&none);
        ::sigprocmask(SIG_SETMASK, &none, nullptr);
        rlimit as{limits.addressSpace, limits.addressSpace};
        rlimit fs{limits.fileSize, limits.fileSize};
        if (::setrlimit(RLIMIT_AS, &as) != 0 || ::setrlimit(RLIMIT_FSIZE, &fs) != 0) ::_exit(125);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    RunResult r;
    if (pid < 0) return r;
    auto deadline = start + std::chrono::duration<double>(timeoutSeconds);
    int st = 0;
    for (;;) {
        pid_t w = ::waitpid(pid, &st, WNOHANG);
        if (w == pid) {
            r.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
            break;
        }
        if (std::chrono::steady_clock::now() > deadline) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &st, 0);
            r.status = -1;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.out = readText(outFile);
    r.err = readText(errFile);
    return r;
}

} // namespace rayproc::test
