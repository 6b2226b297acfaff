#include "image/display_client.h"

#include "core/error.h"

#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace rayproc {

namespace {

constexpr std::uint8_t kCreateImage = 4;
constexpr std::uint8_t kUpdateImageV3 = 6;
// Rows per update packet: about 4 MB of floats for a 1920-wide image.
constexpr int kStripPixels = 1 << 19;

struct Writer {
    std::vector<std::uint8_t> bytes = std::vector<std::uint8_t>(4, 0); // the size, filled last
    template <typename T>
    void value(T v) {
        const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
        bytes.insert(bytes.end(), p, p + sizeof(T));
    }
    void text(const std::string& s) {
        bytes.insert(bytes.end(), s.begin(), s.end());
        bytes.push_back(0);
    }
    std::vector<std::uint8_t> finish() {
        auto size = std::uint32_t(bytes.size());
        std::memcpy(bytes.data(), &size, 4);
        return std::move(bytes);
    }
};

bool splitHostPort(const std::string& hostPort, std::string& host, std::string& port) {
    std::size_t colon = hostPort.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 >= hostPort.size()) return false;
    host = hostPort.substr(0, colon);
    port = hostPort.substr(colon + 1);
    if (port.find_first_not_of("0123456789") != std::string::npos || port.size() > 5) return false;
    long p = std::stol(port);
    return p >= 1 && p <= 65535;
}

} // namespace

void checkDisplayServer(const std::string& hostPort) {
    std::string host, port;
    if (!splitHostPort(hostPort, host, port))
        throw InputError("--display-server: expected HOST:PORT (e.g. 127.0.0.1:14158, tev's "
                         "default), got \"" + hostPort + "\"");
}

std::vector<std::uint8_t> DisplayClient::createImagePacket(const std::string& name, int width,
                                                           int height) {
    Writer w;
    w.value(kCreateImage);
    w.value(std::uint8_t(1)); // grab focus
    w.text(name);
    w.value(std::int32_t(width));
    w.value(std::int32_t(height));
    w.value(std::int32_t(3));
    for (const char* c : {"R", "G", "B"}) w.text(c);
    return w.finish();
}

std::vector<std::uint8_t> DisplayClient::updateImagePacket(const std::string& name,
                                                           const Image& image, int y0, int rows) {
    Writer w;
    w.value(kUpdateImageV3);
    w.value(std::uint8_t(0));
    w.text(name);
    w.value(std::int32_t(3));
    for (const char* c : {"R", "G", "B"}) w.text(c);
    w.value(std::int32_t(0));
    w.value(std::int32_t(y0));
    w.value(std::int32_t(image.width));
    w.value(std::int32_t(rows));
    for (std::int64_t offset : {0, 1, 2}) w.value(offset);
    for (int c = 0; c < 3; ++c) w.value(std::int64_t(3));
    const float* first = image.pixels.data() + std::size_t(y0) * std::size_t(image.width) * 3;
    const auto* p = reinterpret_cast<const std::uint8_t*>(first);
    w.bytes.insert(w.bytes.end(), p, p + std::size_t(rows) * std::size_t(image.width) * 3 * sizeof(float));
    return w.finish();
}

DisplayClient::DisplayClient(const std::string& hostPort, const std::string& imageName)
    : m_name(imageName) {
    std::string host, port;
    if (!splitHostPort(hostPort, host, port)) {
        m_error = "not HOST:PORT: " + hostPort;
        return;
    }
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (int rc = getaddrinfo(host.c_str(), port.c_str(), &hints, &found); rc != 0) {
        m_error = std::string("cannot resolve ") + host + ": " + gai_strerror(rc);
        return;
    }
    for (addrinfo* a = found; a && m_socket < 0; a = a->ai_next) {
        int s = ::socket(a->ai_family, a->ai_socktype, a->ai_protocol);
        if (s < 0) continue;
        if (::connect(s, a->ai_addr, a->ai_addrlen) == 0) {
            m_socket = s;
        } else {
            m_error = std::string("cannot connect to ") + hostPort + ": " + std::strerror(errno);
            ::close(s);
        }
    }
    freeaddrinfo(found);
    if (m_socket >= 0) m_error.clear();
}

DisplayClient::~DisplayClient() {
    if (m_socket >= 0) ::close(m_socket);
}

bool DisplayClient::sendAll(const std::vector<std::uint8_t>& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        // MSG_NOSIGNAL: a viewer that went away is an error here, not a SIGPIPE.
        ssize_t n = ::send(m_socket, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            m_error = std::string("the display server stopped listening: ") + std::strerror(errno);
            ::close(m_socket);
            m_socket = -1;
            return false;
        }
        done += std::size_t(n);
    }
    return true;
}

void DisplayClient::show(const Image& image) {
    if (m_socket < 0 || image.width <= 0 || image.height <= 0) return;
    if (image.width != m_createdWidth || image.height != m_createdHeight) {
        if (!sendAll(createImagePacket(m_name, image.width, image.height))) return;
        m_createdWidth = image.width;
        m_createdHeight = image.height;
    }
    int rowsPerStrip = std::max(1, kStripPixels / image.width);
    for (int y = 0; y < image.height; y += rowsPerStrip)
        if (!sendAll(updateImagePacket(m_name, image, y, std::min(rowsPerStrip, image.height - y))))
            return;
}

} // namespace rayproc
