// rayproc serve's web server: who may connect, and what a WebSocket client is told
// (docs/serve.md). A raw socket speaks HTTP and RFC 6455 frames, so every header is the
// test's choice (a browser would not let a script set Origin or Host).
#include "test_util.h"

#include "serve/server.h"
#include "serve/session.h"

#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

using namespace rayproc;
using namespace rayproc::test;
using rayproc::serve::Json;
using rayproc::serve::Server;
using rayproc::serve::Session;

namespace {

// A session on the Cornell box and its server on the first free port from 8080 up.
struct Served {
    Session session{scenePath("cornell-box"), Session::Options{2, 64}};
    Server server{session, 0};
    // The worker ends before the server goes (as rayproc serve does): it broadcasts through it.
    ~Served() { session.stop(); }
};

// One TCP connection to 127.0.0.1: a request with chosen headers, then WebSocket frames.
// The server learns that a client closed its socket on civetweb's thread, some time after the
// close: the number of clients once it is down to `expected`, or after 10 s, what it is then.
std::size_t clientsOnceSettled(const Server& server, std::size_t expected) {
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (server.clients() != expected && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return server.clients();
}

class RawClient {
public:
    explicit RawClient(int port) {
        m_fd = ::socket(AF_INET, SOCK_STREAM, 0);
        REQUIRE(m_fd >= 0);
        timeval timeout{20, 0}; // a reply that never comes fails the test, it does not hang it
        ::setsockopt(m_fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_port = htons(std::uint16_t(port));
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::connect(m_fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
    }
    ~RawClient() { ::close(m_fd); }
    RawClient(const RawClient&) = delete;
    RawClient& operator=(const RawClient&) = delete;

    // GET `path` with these header lines; returns the response's head (status line and
    // headers).
    std::string request(const std::string& path, const std::vector<std::string>& headers) {
        std::string r = "GET " + path + " HTTP/1.1\r\n";
        for (const std::string& h : headers) r += h + "\r\n";
        sendAll(r + "\r\n");
        std::size_t end;
        while ((end = m_in.find("\r\n\r\n")) == std::string::npos)
            if (!receive()) return m_in;
        std::string head = m_in.substr(0, end + 4);
        m_in.erase(0, end + 4);
        return head;
    }
    // The WebSocket handshake on /ws with extra header lines; returns the response's head.
    std::string handshake(const std::vector<std::string>& extra) {
        std::vector<std::string> headers = {
            "Upgrade: websocket", "Connection: Upgrade",
            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==", "Sec-WebSocket-Version: 13"};
        headers.insert(headers.end(), extra.begin(), extra.end());
        return request("/ws", headers);
    }
    // A client frame (masked, as RFC 6455 requires), FIN set unless `final` is false.
    void sendFrame(int opcode, const std::string& payload, bool final = true) {
        std::string f;
        f += char((final ? 0x80 : 0) | opcode);
        if (payload.size() < 126) {
            f += char(0x80 | payload.size());
        } else {
            REQUIRE(payload.size() < 65536);
            f += char(0x80 | 126);
            f += char(payload.size() >> 8);
            f += char(payload.size() & 0xff);
        }
        const char mask[4] = {0x12, 0x34, 0x56, 0x78};
        f.append(mask, 4);
        for (std::size_t i = 0; i < payload.size(); ++i) f += char(payload[i] ^ mask[i % 4]);
        sendAll(f);
    }
    // The next server frame; false when the connection closed or nothing came in time.
    bool readFrame(int& opcode, std::string& payload) {
        if (!have(2)) return false;
        opcode = std::uint8_t(m_in[0]) & 0xf;
        std::uint64_t length = std::uint8_t(m_in[1]) & 0x7f;
        std::size_t head = 2;
        if (length == 126) {
            if (!have(4)) return false;
            length = (std::uint64_t(std::uint8_t(m_in[2])) << 8) | std::uint8_t(m_in[3]);
            head = 4;
        } else if (length == 127) {
            if (!have(10)) return false;
            length = 0;
            for (int b = 0; b < 8; ++b) length = (length << 8) | std::uint8_t(m_in[2 + b]);
            head = 10;
        }
        if (!have(head + length)) return false;
        payload = m_in.substr(head, length);
        m_in.erase(0, head + length);
        return true;
    }
    // The next JSON text message whose type is `type`, null when none came; frames are
    // skipped, and the types of other text messages go to `skipped`.
    Json readText(const std::string& type, std::vector<std::string>* skipped = nullptr) {
        int opcode;
        std::string payload;
        while (readFrame(opcode, payload)) {
            if (opcode != 1) continue;
            Json m = Json::parse(payload);
            if (m["type"] == type) return m;
            if (skipped) skipped->push_back(m["type"].get<std::string>());
        }
        return nullptr;
    }
    // True when the server closed the connection (nothing more to read).
    bool closedByServer() {
        while (receive()) {
        }
        return m_closed;
    }

private:
    void sendAll(const std::string& bytes) {
        std::size_t sent = 0;
        while (sent < bytes.size()) {
            ssize_t n = ::send(m_fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
            REQUIRE(n > 0);
            sent += std::size_t(n);
        }
    }
    bool receive() {
        char buf[65536];
        ssize_t n = ::recv(m_fd, buf, sizeof buf, 0);
        if (n == 0) m_closed = true;
        if (n <= 0) return false;
        m_in.append(buf, std::size_t(n));
        return true;
    }
    bool have(std::size_t n) {
        while (m_in.size() < n)
            if (!receive()) return false;
        return true;
    }

    int m_fd = -1;
    std::string m_in;
    bool m_closed = false;
};

std::string statusLine(const std::string& head) {
    return head.substr(0, head.find("\r\n"));
}

} // namespace

TEST_CASE("serve: only the server's own page may open a WebSocket - other origins are refused",
          "[serve]") {
    Served s;
    const std::string port = std::to_string(s.server.port());
    const std::string host = "Host: 127.0.0.1:" + port;

    // The page's own origin, under each name of the loopback address, and a client that is no
    // browser (no Origin): accepted, and the state arrives.
    for (const std::string& origin :
         {"Origin: http://127.0.0.1:" + port, "Origin: http://localhost:" + port,
          "Origin: http://[::1]:" + port, std::string()}) {
        INFO(origin);
        RawClient c(s.server.port());
        std::vector<std::string> headers = {host};
        if (!origin.empty()) headers.push_back(origin);
        CHECK(statusLine(c.handshake(headers)) == "HTTP/1.1 101 Switching Protocols");
        CHECK(c.readText("state")["type"] == "state");
    }
    {
        RawClient c(s.server.port());
        CHECK(statusLine(
                  c.handshake({"Host: localhost:" + port, "Origin: http://localhost:" + port})) ==
              "HTTP/1.1 101 Switching Protocols");
    }

    // Another site's page (what the audit found: it could send "save"), the right name at
    // another port, a sandboxed page ("null"), https: refused with 403, and closed.
    for (const std::string& origin :
         {std::string("http://evil.example"),
          "http://127.0.0.1:" + std::to_string(s.server.port() + 1), std::string("null"),
          "https://127.0.0.1:" + port, "http://127.0.0.1:" + port + ".evil.example"}) {
        INFO(origin);
        RawClient c(s.server.port());
        std::string head = c.handshake({host, "Origin: " + origin});
        CHECK(statusLine(head) == "HTTP/1.1 403 Forbidden");
        CHECK(c.closedByServer());
    }
    // DNS rebinding: the browser thinks evil.example is the server's own origin, and says so
    // in Host.
    {
        RawClient c(s.server.port());
        std::string head =
            c.handshake({"Host: evil.example:" + port, "Origin: http://evil.example:" + port});
        CHECK(statusLine(head) == "HTTP/1.1 403 Forbidden");
    }
    // Every accepted client has closed and no refused one was ever counted (under ASan on a
    // busy machine the last close was once still being handled when this was read at once).
    CHECK(clientsOnceSettled(s.server, 0) == 0);
}

TEST_CASE("serve: HTTP requests must name the server in Host (DNS rebinding)", "[serve]") {
    Served s;
    const std::string port = std::to_string(s.server.port());
    for (const char* name : {"127.0.0.1", "localhost", "LOCALHOST", "[::1]"}) {
        RawClient c(s.server.port());
        std::string host = std::string("Host: ") + name + ":" + port;
        CHECK(statusLine(c.request("/", {host})) == "HTTP/1.1 200 OK");
    }
    for (const std::string& hostLine :
         {"Host: evil.example:" + port, std::string("Host: evil.example"),
          std::string("Host: 127.0.0.1"), "Host: 127.0.0.1:" + port + "0"}) {
        INFO(hostLine);
        RawClient c(s.server.port());
        CHECK(statusLine(c.request("/image.png", {hostLine})) == "HTTP/1.1 403 Forbidden");
    }
}

TEST_CASE("serve: a binary WebSocket message is refused with a message - the socket still works",
          "[serve]") {
    Served s;
    RawClient c(s.server.port());
    REQUIRE(statusLine(c.handshake({"Host: 127.0.0.1:" + std::to_string(s.server.port())})) ==
            "HTTP/1.1 101 Switching Protocols");
    REQUIRE(c.readText("state")["type"] == "state");
    c.sendFrame(2, std::string("{\"type\": \"state\"}"));
    Json error = c.readText("error");
    REQUIRE(error.is_object());
    CHECK_THAT(error["message"].get<std::string>(), Catch::Contains("binary"));
    // A text message split into fragments: refused once, its continuation dropped.
    c.sendFrame(1, "{\"type\": ", false);
    c.sendFrame(0, "\"state\"}");
    error = c.readText("error");
    REQUIRE(error.is_object());
    CHECK_THAT(error["message"].get<std::string>(), Catch::Contains("fragmented"));
    c.sendFrame(1, "{\"type\": \"state\"}");
    std::vector<std::string> before;
    CHECK(c.readText("state", &before)["type"] == "state");
    CHECK(before.empty()); // no reply to the continuation
}
