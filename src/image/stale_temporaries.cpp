// Temporary files a killed writer left: AtomicFileWriter (file_io.cpp) names them
// "<path>.tmp.<pid>.<counter>" and removes them itself on every failure it lives through, but
// not after kill -9. A later writer of the same path removes those whose process is gone.
#include "image/image.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <string>

namespace rayproc {

std::size_t removeStaleTemporaries(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path target(path);
    const std::string prefix = target.filename().string() + ".tmp.";
    fs::path dir = target.parent_path();
    if (dir.empty()) dir = ".";
    std::size_t removed = 0;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.compare(0, prefix.size(), prefix) != 0) continue;
        // "<pid>.<counter>", both decimal, as AtomicFileWriter names them.
        const std::string rest = name.substr(prefix.size());
        const std::size_t dot = rest.find('.');
        if (dot == 0 || dot == std::string::npos || dot + 1 == rest.size() ||
            rest.find_first_not_of("0123456789.") != std::string::npos ||
            rest.find('.', dot + 1) != std::string::npos || dot > 9)
            continue;
        const long pid = std::stol(rest.substr(0, dot));
        if (pid <= 0 || pid == long(::getpid())) continue;
        if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue; // alive, or not ours to know
        if (!it->is_regular_file(ec)) continue;
        std::error_code removeError;
        if (fs::remove(it->path(), removeError)) ++removed;
    }
    return removed;
}

} // namespace rayproc
