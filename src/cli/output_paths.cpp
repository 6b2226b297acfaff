#include "cli/output_paths.h"

#include "core/error.h"
#include "image/image.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace rayproc::cli {

namespace fs = std::filesystem;

namespace {

// The same file: for two existing paths the file system decides (links, ".."), otherwise the
// normalised absolute paths.
bool sameFile(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec) && !ec;
    fs::path pa = fs::weakly_canonical(fs::absolute(a), ec);
    if (ec) pa = fs::absolute(a).lexically_normal();
    fs::path pb = fs::weakly_canonical(fs::absolute(b), ec);
    if (ec) pb = fs::absolute(b).lexically_normal();
    return pa == pb;
}

} // namespace

void checkOutputFile(const std::string& option, const std::string& path) {
    if (path.empty()) return;
    auto fail = [&](const std::string& problem) {
        throw ImageIoError(option + " " + path + ": " + problem);
    };
    std::error_code ec;
    fs::file_status st = fs::status(path, ec);
    if (fs::exists(st)) {
        if (fs::is_directory(st)) fail("is a directory; give a file name");
        if (!fs::is_regular_file(st))
            fail("is not a regular file (outputs are written to a temporary file renamed over "
                 "the path, which would replace a device or pipe)");
    }
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    if (!fs::is_directory(dir, ec)) fail("the directory " + dir.string() + " does not exist");
    // Try it: permissions, read-only mounts and ACLs all show in whether a file can be created.
    std::string probe = (dir / ".rayproc-write-check-XXXXXX").string();
    int fd = ::mkstemp(probe.data());
    if (fd < 0) {
        int err = errno;
        fail("the directory " + dir.string() + " does not accept new files (" +
             std::strerror(err) + ")");
    }
    ::close(fd);
    ::unlink(probe.c_str());
}

void checkDistinctFiles(const std::vector<NamedPath>& paths) {
    for (std::size_t i = 0; i < paths.size(); ++i) {
        for (std::size_t j = 0; j < i; ++j) {
            const NamedPath& a = paths[j];
            const NamedPath& b = paths[i];
            if (a.path.empty() || b.path.empty() || (!a.output && !b.output)) continue;
            if (!sameFile(a.path, b.path)) continue;
            const NamedPath& out = b.output ? b : a;
            const NamedPath& other = b.output ? a : b;
            throw InputError(out.option + " " + out.path + " is the same file as " +
                             other.option + " " + other.path +
                             (other.output ? " (another output): each output needs its own file"
                                           : " (an input): writing it would destroy the input"));
        }
    }
}

} // namespace rayproc::cli
