// Checks on the files a command will write, made before any work: a render that cannot save
// its image fails in a second, not after an hour; no output overwrites an input or another
// output.
#pragma once

#include <string>
#include <vector>

namespace rayproc::cli {

// Throws ImageIoError "<option> <path>: <problem>" unless `path` can be written atomically
// (a temporary file in its directory renamed over it): its directory exists and accepts a new
// file (tried, so read-only file systems and permissions are caught, for root too), and the
// path is not a directory or another non-regular file (a device, a FIFO). Empty: no check.
void checkOutputFile(const std::string& option, const std::string& path);

struct NamedPath {
    std::string option; // as the user wrote it: "-o", "--stats-json", "scene", ...
    std::string path;   // empty: not given, ignored
    bool output = false;
};
// Throws InputError when an output names the same file as an input or another output (also
// through another spelling, a symbolic or a hard link).
void checkDistinctFiles(const std::vector<NamedPath>& paths);

} // namespace rayproc::cli
