// A client of the tev HDR viewer's display server (its documented TCP protocol, as pbrt-v4's
// --display-server uses): `rayproc render --display-server HOST:PORT` shows the image while it
// renders. Packets are a little-endian u32 total size, a type byte and the fields: CreateImage
// (4) names the image and its channels R, G, B; UpdateImageV3 (6) sends a crop of interleaved
// float RGB (offsets 0, 1, 2, stride 3).
#pragma once

#include "image/image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rayproc {

class DisplayClient {
public:
    // Connects to HOST:PORT; failure leaves the client closed with error() saying why.
    DisplayClient(const std::string& hostPort, const std::string& imageName);
    ~DisplayClient();
    DisplayClient(const DisplayClient&) = delete;
    DisplayClient& operator=(const DisplayClient&) = delete;

    bool connected() const { return m_socket >= 0; }
    const std::string& error() const { return m_error; }
    // Creates the image in the viewer (once) and sends all its pixels, in strips of rows. A
    // failed send closes the client (error() says why); rendering is not affected.
    void show(const Image& image);

    // The packets, for tests and for the fake viewers that check them.
    static std::vector<std::uint8_t> createImagePacket(const std::string& name, int width, int height);
    static std::vector<std::uint8_t> updateImagePacket(const std::string& name, const Image& image,
                                                       int y0, int rows);

private:
    bool sendAll(const std::vector<std::uint8_t>& bytes);

    int m_socket = -1;
    std::string m_name;
    std::string m_error;
    int m_createdWidth = 0, m_createdHeight = 0;
};

// "HOST:PORT" checked: a non-empty host and a port in 1..65535; throws InputError otherwise.
void checkDisplayServer(const std::string& hostPort);

} // namespace rayproc
