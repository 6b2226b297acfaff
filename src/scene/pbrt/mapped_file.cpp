#include "scene/pbrt/mapped_file.h"

#include "core/error.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace rayproc::pbrt {

MappedFile::MappedFile(const std::string& path) {
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw InputError(path + ": cannot open the file: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || S_ISDIR(st.st_mode)) {
        ::close(fd);
        throw InputError(path + ": is a directory, not a file");
    }
    m_size = std::size_t(st.st_size);
    if (m_size > 0) {
        // MAP_POPULATE maps every page at once: one call instead of a fault per page.
        void* p = ::mmap(nullptr, m_size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
        if (p != MAP_FAILED) {
            m_map = p;
            ::madvise(p, m_size, MADV_SEQUENTIAL);
            m_view = std::string_view(static_cast<const char*>(p), m_size);
        } else {
            // Not mappable (a pipe, a special file system): read it instead.
            m_copy.resize(m_size);
            std::size_t got = 0;
            while (got < m_size) {
                ssize_t r = ::read(fd, m_copy.data() + got, m_size - got);
                if (r < 0 && errno == EINTR) continue;
                if (r <= 0) {
                    ::close(fd);
                    throw InputError(path + ": cannot read the file");
                }
                got += std::size_t(r);
            }
            m_view = m_copy;
        }
    }
    ::close(fd);
}

MappedFile::~MappedFile() {
    if (m_map) ::munmap(m_map, m_size);
}

} // namespace rayproc::pbrt
