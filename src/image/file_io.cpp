// Atomic writing and checked reading of image files (see image_io_detail.h).
//
// The atomic writer follows the classic recipe: create "<path>.tmp.<pid>.<counter>" next to the
// destination with O_EXCL (never clobbering anyone's file), write, fflush, fsync, fclose, rename.
// rename() within one directory atomically replaces the destination, so readers see either the
// old file or the complete new one. The directory is fsynced afterwards so the rename itself
// survives a crash (best effort: some file systems cannot sync directories).
#include "image/image_io_detail.h"

#include <atomic>
#include <cerrno>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace rayproc::image_detail {

namespace {

std::string quoted(const std::string& s) {
    return "\"" + s + "\"";
}

std::string parentDirectory(const std::string& path) {
    std::string::size_type slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

// Makes the rename durable; failures are ignored because the data itself is already safe.
void syncDirectory(const std::string& dir) {
    int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

} // namespace

void throwWriteError(const std::string& path, const std::string& reason) {
    throw ImageIoError("cannot write image " + quoted(path) + ": " + reason);
}

void throwReadError(const std::string& path, const std::string& reason) {
    throw ImageIoError("cannot read image " + quoted(path) + ": " + reason);
}

std::string errnoText(int err) {
    return std::generic_category().message(err);
}

std::uint64_t fileSize(const std::string& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 ? std::uint64_t(st.st_size) : 0;
}

bool checkInputFile(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return false;
    if (S_ISDIR(st.st_mode)) throwReadError(path, errnoText(EISDIR));
    if (!S_ISREG(st.st_mode)) {
        const char* kind = S_ISCHR(st.st_mode)    ? "a character device"
                           : S_ISBLK(st.st_mode)  ? "a block device"
                           : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                           : S_ISSOCK(st.st_mode) ? "a socket"
                                                  : "not a regular file";
        throwReadError(path, std::string("it is ") + kind +
                                 ", not a regular file; images are read from regular files only");
    }
    if (std::uint64_t(st.st_size) > kMaxImageFileBytes)
        throwReadError(path, "the file has " + std::to_string(st.st_size) +
                                 " bytes, more than the " +
                                 std::to_string(kMaxImageFileBytes >> 30) +
                                 " GiB an image file may have");
    return true;
}

void checkClaimedSize(const std::string& path, std::int64_t width, std::int64_t height,
                      std::uint64_t fileBytes) {
    double pixels = double(width) * double(height);
    if (pixels > kMaxPixelsPerFileByte * double(fileBytes) + 65536.0)
        throwReadError(path, "the header claims " + std::to_string(width) + "x" +
                                 std::to_string(height) + " pixels, more than a file of " +
                                 std::to_string(fileBytes) +
                                 " bytes can hold (corrupt or truncated file)");
}

// AtomicFileWriter ----------------------------------------------------------------------------

AtomicFileWriter::AtomicFileWriter(std::string path, std::string what)
    : m_path(std::move(path)), m_what(std::move(what)) {
    // pid + a process-wide counter keep concurrent writers (threads or processes) apart.
    static std::atomic<unsigned> counter{0};
    m_tempPath =
        m_path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter.fetch_add(1));
    int fd = ::open(m_tempPath.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
        int err = errno;
        std::string reason =
            "cannot create temporary file " + quoted(m_tempPath) + ": " + errnoText(err);
        m_tempPath.clear(); // never created: nothing to remove
        throwError(reason);
    }
    m_file = ::fdopen(fd, "wb");
    if (!m_file) {
        int err = errno;
        ::close(fd);
        ::unlink(m_tempPath.c_str());
        std::string reason =
            "cannot open temporary file " + quoted(m_tempPath) + ": " + errnoText(err);
        m_tempPath.clear();
        throwError(reason);
    }
}

AtomicFileWriter::~AtomicFileWriter() {
    discard();
}

void AtomicFileWriter::discard() {
    if (m_file) {
        std::fclose(m_file);
        m_file = nullptr;
    }
    if (!m_tempPath.empty()) {
        ::unlink(m_tempPath.c_str());
        m_tempPath.clear();
    }
}

void AtomicFileWriter::recordErrno(const char* what) {
    int err = errno;
    if (failed()) return; // keep the first cause: later ones are usually consequences
    m_error =
        std::string(what) + " temporary file " + quoted(m_tempPath) + " failed: " + errnoText(err);
}

void AtomicFileWriter::fail(const std::string& reason) {
    if (!failed()) m_error = reason;
}

bool AtomicFileWriter::write(const void* data, std::size_t size) {
    if (failed() || !m_file) return false;
    if (size == 0) return true;
    if (std::fwrite(data, 1, size, m_file) != size) {
        recordErrno("writing");
        return false;
    }
    return true;
}

bool AtomicFileWriter::seek(std::uint64_t offset) {
    if (failed() || !m_file) return false;
    if (::fseeko(m_file, static_cast<off_t>(offset), SEEK_SET) != 0) {
        recordErrno("seeking in");
        return false;
    }
    return true;
}

std::uint64_t AtomicFileWriter::tell() {
    if (!m_file) return 0;
    off_t pos = ::ftello(m_file);
    if (pos < 0) {
        recordErrno("querying position in");
        return 0;
    }
    return static_cast<std::uint64_t>(pos);
}

void AtomicFileWriter::commit() {
    // Flush and sync before closing: buffered data hits the disk here, so "disk full" and I/O
    // errors surface now rather than after the rename has published a truncated file.
    if (!failed() && std::fflush(m_file) != 0) recordErrno("flushing");
    if (!failed() && ::fsync(::fileno(m_file)) != 0) recordErrno("syncing");
    if (!failed()) {
        std::FILE* file = std::exchange(m_file, nullptr);
        if (std::fclose(file) != 0) recordErrno("closing");
    }
    if (!failed() && std::rename(m_tempPath.c_str(), m_path.c_str()) != 0) {
        int err = errno;
        m_error =
            "renaming temporary file " + quoted(m_tempPath) + " onto it failed: " + errnoText(err);
    }
    if (failed()) {
        std::string reason = m_error;
        discard();
        throwError(reason);
    }
    m_tempPath.clear(); // it has become the destination: nothing left to remove
    syncDirectory(parentDirectory(m_path));
}

void AtomicFileWriter::throwError(const std::string& reason) const {
    throw ImageIoError("cannot write " + m_what + quoted(m_path) + ": " + reason);
}

// FileReader ----------------------------------------------------------------------------------

FileReader::FileReader(std::string path) : m_path(std::move(path)) {
    m_file = std::fopen(m_path.c_str(), "rb");
    if (!m_file) {
        int err = errno;
        throwReadError(m_path, errnoText(err));
    }
    // fopen() happily opens a directory on Linux; say so instead of failing later on read().
    struct stat st {};
    if (::fstat(::fileno(m_file), &st) == 0 && S_ISDIR(st.st_mode)) {
        std::fclose(m_file);
        m_file = nullptr;
        throwReadError(m_path, errnoText(EISDIR));
    }
}

FileReader::~FileReader() {
    if (m_file) std::fclose(m_file);
}

std::uint64_t FileReader::remainingBytes() {
    struct stat st {};
    off_t pos = ::ftello(m_file);
    if (pos < 0 || ::fstat(::fileno(m_file), &st) != 0 || st.st_size < pos) return 0;
    return static_cast<std::uint64_t>(st.st_size - pos);
}

} // namespace rayproc::image_detail

namespace rayproc {

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    image_detail::AtomicFileWriter out(path, "");
    out.write(bytes.data(), bytes.size());
    out.commit();
}

} // namespace rayproc
