// A whole file, read-only, as one string_view: memory-mapped (large PLY meshes are parsed
// straight from the page cache, without a copy), or read into memory where mapping fails.
#pragma once

#include <string>
#include <string_view>

namespace rayproc::pbrt {

class MappedFile {
public:
    // Throws InputError "<path>: <problem>" if the file is missing, a directory or unreadable.
    explicit MappedFile(const std::string& path);
    ~MappedFile();
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    std::string_view data() const { return m_view; }

private:
    void* m_map = nullptr;
    std::size_t m_size = 0;
    std::string m_copy; // when the file could not be mapped
    std::string_view m_view;
};

} // namespace rayproc::pbrt
