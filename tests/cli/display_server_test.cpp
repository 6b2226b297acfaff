// render --display-server: the tev viewer's TCP protocol, checked against a fake viewer that
// parses every packet (docs/serve.md, "--display-server").
#include "test_util.h"

#include "image/display_client.h"
#include "image/image.h"

#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <thread>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A listening socket on 127.0.0.1 at a free port.
struct Listener {
    int fd = -1;
    int port = 0;
    Listener() {
        fd = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = 0;
        if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(fd, 1) != 0) return;
        socklen_t len = sizeof a;
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
        port = ntohs(a.sin_port);
    }
    ~Listener() {
        if (fd >= 0) ::close(fd);
    }
    // Everything one client sends until it closes.
    std::vector<std::uint8_t> receiveAll() const {
        int c = ::accept(fd, nullptr, nullptr);
        std::vector<std::uint8_t> all;
        std::uint8_t buf[65536];
        for (ssize_t n; c >= 0 && (n = ::read(c, buf, sizeof buf)) > 0;) all.insert(all.end(), buf, buf + n);
        if (c >= 0) ::close(c);
        return all;
    }
};

// The fake viewer: applies CreateImage and UpdateImageV3 packets as tev does.
struct FakeViewer {
    std::string name;
    int width = 0, height = 0, created = 0, updates = 0;
    std::vector<std::string> channels;
    std::vector<float> pixels; // interleaved RGB
    std::string problem;

    void apply(const std::vector<std::uint8_t>& bytes) {
        std::size_t at = 0;
        while (at + 5 <= bytes.size() && problem.empty()) {
            std::uint32_t size;
            std::memcpy(&size, &bytes[at], 4);
            if (size < 5 || at + size > bytes.size()) {
                problem = "packet size " + std::to_string(size) + " runs past the data";
                return;
            }
            packet(std::vector<std::uint8_t>(bytes.begin() + long(at) + 4, bytes.begin() + long(at + size)));
            at += size;
        }
        if (at != bytes.size() && problem.empty()) problem = "trailing bytes";
    }

private:
    template <typename T>
    static T get(const std::vector<std::uint8_t>& p, std::size_t& at) {
        T v;
        std::memcpy(&v, &p[at], sizeof(T));
        at += sizeof(T);
        return v;
    }
    static std::string text(const std::vector<std::uint8_t>& p, std::size_t& at) {
        std::string s;
        while (at < p.size() && p[at] != 0) s += char(p[at++]);
        ++at;
        return s;
    }
    void packet(const std::vector<std::uint8_t>& p) {
        std::size_t at = 0;
        auto type = get<std::uint8_t>(p, at);
        get<std::uint8_t>(p, at); // grab focus
        std::string image = text(p, at);
        if (type == 4) {
            name = image;
            width = get<std::int32_t>(p, at);
            height = get<std::int32_t>(p, at);
            int n = get<std::int32_t>(p, at);
            channels.clear();
            for (int c = 0; c < n; ++c) channels.push_back(text(p, at));
            pixels.assign(std::size_t(width) * std::size_t(height) * 3, -1.0f);
            ++created;
            return;
        }
        if (type != 6) {
            problem = "unexpected packet type " + std::to_string(type);
            return;
        }
        if (image != name) problem = "update of an image never created: " + image;
        int n = get<std::int32_t>(p, at);
        std::vector<std::string> names;
        for (int c = 0; c < n; ++c) names.push_back(text(p, at));
        int x = get<std::int32_t>(p, at), y = get<std::int32_t>(p, at);
        int w = get<std::int32_t>(p, at), h = get<std::int32_t>(p, at);
        std::vector<std::int64_t> offsets(static_cast<std::size_t>(n));
        std::vector<std::int64_t> strides(static_cast<std::size_t>(n));
        for (auto& o : offsets) o = get<std::int64_t>(p, at);
        for (auto& s : strides) s = get<std::int64_t>(p, at);
        const float* data = reinterpret_cast<const float*>(&p[at]);
        std::size_t floats = (p.size() - at) / sizeof(float);
        for (int c = 0; c < n && c < 3; ++c)
            for (int py = 0; py < h; ++py)
                for (int px = 0; px < w; ++px) {
                    std::size_t i = std::size_t(offsets[std::size_t(c)]) +
                                    (std::size_t(py) * std::size_t(w) + std::size_t(px)) * std::size_t(strides[std::size_t(c)]);
                    if (i >= floats || x + px >= width || y + py >= height) {
                        problem = "update outside the image or its data";
                        return;
                    }
                    float v;
                    std::memcpy(&v, data + i, sizeof v);
                    pixels[(std::size_t(y + py) * std::size_t(width) + std::size_t(x + px)) * 3 + std::size_t(c)] = v;
                }
        ++updates;
    }
};

} // namespace

TEST_CASE("A render with a display server streams to a tev viewer, the last update the final image",
          "[cli]") {
    TempDir dir;
    Listener viewer;
    REQUIRE(viewer.port > 0);
    std::vector<std::uint8_t> received;
    std::thread reader([&] { received = viewer.receiveAll(); });
    std::string out = dir.file("shown.pfm");
    RunResult r = runRayproc({"render", scenePath("cornell-box"), "--mode", "path", "--spp", "16",
                              "--width", "40", "--height", "24", "--threads", "2", "-q", "-o", out,
                              "--display-server", "127.0.0.1:" + std::to_string(viewer.port)},
                             dir);
    reader.join();
    INFO(r.err);
    REQUIRE(r.status == 0);
    FakeViewer tev;
    tev.apply(received);
    INFO(tev.problem);
    CHECK(tev.problem.empty());
    CHECK(tev.created == 1);
    CHECK(tev.name == "shown.pfm");
    CHECK(tev.width == 40);
    CHECK(tev.height == 24);
    CHECK(tev.channels == std::vector<std::string>{"R", "G", "B"});
    CHECK(tev.updates >= 2); // at least the end of the passes and the final image
    Image written = readImage(out);
    CHECK(tev.pixels == written.pixels);
}

TEST_CASE("An unreachable display server is a warning, a malformed one an error", "[cli]") {
    TempDir dir;
    int port;
    {
        Listener gone; // a port that was free a moment ago, with nobody listening now
        port = gone.port;
    }
    std::string out = dir.file("alone.pfm");
    RunResult r = runRayproc({"render", scenePath("cornell-box"), "--mode", "preview", "--width",
                              "16", "--height", "16", "-q", "-o", out, "--display-server",
                              "127.0.0.1:" + std::to_string(port)},
                             dir);
    CHECK(r.status == 0);
    CHECK(r.err.find("warning: --display-server") != std::string::npos);
    CHECK(std::filesystem::exists(out));
    for (const char* bad : {"localhost", ":14158", "localhost:0", "localhost:99999", "host:12ab"}) {
        INFO(bad);
        RunResult b = runRayproc({"render", scenePath("cornell-box"), "-q", "-o", dir.file("x.png"),
                                  "--display-server", bad},
                                 dir);
        CHECK(b.status == 1);
        CHECK(b.err.find("expected HOST:PORT") != std::string::npos);
    }
}

TEST_CASE("Display packets follow tev's layout", "[image]") {
    std::vector<std::uint8_t> create = DisplayClient::createImagePacket("a", 3, 2);
    // size, type 4, focus, "a\0", 3, 2, 3 channels, "R\0G\0B\0"
    CHECK(create.size() == 4 + 1 + 1 + 2 + 4 + 4 + 4 + 6);
    std::uint32_t size;
    std::memcpy(&size, create.data(), 4);
    CHECK(size == create.size());
    CHECK(create[4] == 4);
    Image img(3, 2);
    for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(i);
    std::vector<std::uint8_t> update = DisplayClient::updateImagePacket("a", img, 1, 1);
    CHECK(update[4] == 6);
    // The last 9 floats are row 1, interleaved RGB.
    float last;
    std::memcpy(&last, &update[update.size() - 4], 4);
    CHECK(last == 17.0f);
    CHECK(update.size() == 4 + 1 + 1 + 2 + 4 + 6 + 16 + 24 + 24 + 9 * 4);
}
