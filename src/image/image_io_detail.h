// Internal to src/image: the atomic file writer, the checked file reader and the per-format
// codecs that image.cpp dispatches to. Not part of the public API.
#pragma once

#include "image/image.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace rayproc::image_detail {

// "cannot write image "<path>": <reason>" / "cannot read image ...", as an ImageIoError.
[[noreturn]] void throwWriteError(const std::string& path, const std::string& reason);
[[noreturn]] void throwReadError(const std::string& path, const std::string& reason);
// The text of an errno value, e.g. "No such file or directory".
std::string errnoText(int err);

// No codec rayproc reads packs more than this many pixels into one byte of the file (deflate's
// limit of 1032:1 on 1-bit PNG pixels is 8256). A header claiming more is corrupt or hostile.
constexpr double kMaxPixelsPerFileByte = 8400.0;
// Throws "cannot read image ...: the header claims WxH pixels, more than a file of N bytes can
// hold" before the allocation such a header would ask for.
void checkClaimedSize(const std::string& path, std::int64_t width, std::int64_t height,
                      std::uint64_t fileBytes);
std::uint64_t fileSize(const std::string& path);

// No image rayproc reads needs a file this large (a 2^28-pixel float RGBA EXR, the texture
// limit, is 4 GiB uncompressed); the EXR header check reads the whole file.
constexpr std::uint64_t kMaxImageFileBytes = std::uint64_t(4) << 30;
// Refuses, naming the file, what no reader may be handed: a character or block device, a FIFO
// or a socket (/dev/zero made OpenImageIO's fallback reader seek forever; opening a FIFO
// blocks until a writer comes) and files larger than kMaxImageFileBytes. Opens nothing.
// Returns false when the path cannot be examined (missing, no permission): the reader then
// reports why it cannot open it.
bool checkInputFile(const std::string& path);

// Walks an OpenEXR file's header(s) before OpenEXR reads them: OpenEXR allocates whatever an
// attribute's size field says (1.2 GB from a 160-byte file, found by tests/fuzz/image_fuzzer).
// Throws a read error when an attribute claims more bytes than the file has left or has a size
// the C++ library would not read it by, when the header runs past the end of the file, or when
// a part's chunk offset table or decoding buffer would be larger than the file accounts for.
// Returns normally for files without the EXR magic number, having read only their first bytes.
void checkExrHeader(const std::string& path);

// Whether the file starts with the EXR magic number (its first 4 bytes); throws a read error
// when it cannot be opened.
bool startsAsExr(const std::string& path);

// For readers other than readExr (the texture loader's OpenImageIO): an EXR file that carries
// rayproc's pixel checksum is decoded once here and refused when its pixels do not match it
// (exr_checksum.h). Other files, and EXRs without the checksum, pass. Call after
// checkExrHeader.
void checkExrChecksum(const std::string& path);

// A PNG file's integrity, before a decoder sees it: every chunk's length fits in the file, every
// chunk's CRC-32 matches, the IDAT chunks' zlib stream inflates to its end (its Adler-32
// matches) and an IEND chunk closes the file. Throws a read error naming the chunk; returns
// normally for files without the PNG signature.
void checkPngFile(const std::string& path);

// Writes a file under a temporary name in the destination's directory and renames it onto the
// destination only once every byte is flushed and fsynced. Until commit() succeeds the
// destination is untouched; the destructor removes the temporary file if commit() was not
// reached, so a failure anywhere (including an exception in the encoder) leaves nothing behind.
//
// write() and seek() never throw: they record the first failure, so that they can be called
// from C callbacks (stb) that cannot unwind. commit() reports the recorded failure.
class AtomicFileWriter {
public:
    // Throws ImageIoError if the temporary file cannot be made. `what` names the kind of file in
    // messages: "cannot write <what>"<path>": ..." ("image " or "" for any file).
    explicit AtomicFileWriter(std::string path, std::string what = "image ");
    ~AtomicFileWriter();
    AtomicFileWriter(const AtomicFileWriter&) = delete;
    AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

    bool write(const void* data, std::size_t size);
    bool seek(std::uint64_t offset);
    std::uint64_t tell();
    bool failed() const { return !m_error.empty(); }
    const std::string& error() const { return m_error; }
    const std::string& path() const { return m_path; }
    const std::string& tempPath() const { return m_tempPath; }

    // Records an encoder failure; commit() will then throw with this reason.
    void fail(const std::string& reason);
    // Flush, fsync, close, rename onto the destination; throws ImageIoError on any failure.
    void commit();

private:
    void recordErrno(const char* what);
    void discard();

    [[noreturn]] void throwError(const std::string& reason) const;

    std::string m_path;
    std::string m_what;
    std::string m_tempPath;
    std::FILE* m_file = nullptr;
    std::string m_error; // first failure, empty while all is well
};

// A file opened for binary reading; opening failures throw ImageIoError with the errno text.
class FileReader {
public:
    explicit FileReader(std::string path);
    ~FileReader();
    FileReader(const FileReader&) = delete;
    FileReader& operator=(const FileReader&) = delete;

    std::FILE* get() const { return m_file; }
    const std::string& path() const { return m_path; }
    // Bytes from the current position to the end of the file.
    std::uint64_t remainingBytes();

private:
    std::string m_path;
    std::FILE* m_file = nullptr;
};

// The per-format codecs. Writers receive a validated image and throw ImageIoError.
void writePng(const std::string& path, const Image& img, const ToneMapSettings& tm);
Image readPng(const std::string& path);
void writeHdr(const std::string& path, const Image& img);
Image readHdr(const std::string& path);
// R, G, B and each layer as the channel "<name>.Y".
void writeExr(const std::string& path, const Image& img, const std::vector<ImageLayer>& layers = {});
Image readExr(const std::string& path);
void writePfm(const std::string& path, const Image& img);
Image readPfm(const std::string& path);

} // namespace rayproc::image_detail
