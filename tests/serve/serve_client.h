// A raw socket client of rayproc serve's web server: it speaks HTTP and RFC 6455 frames, so
// every header and every byte of a frame is the test's choice (a browser would not let a script
// set Origin or Host, nor send a frame that is not UTF-8). Shared by tests/serve/*_test.cpp.
#pragma once

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

namespace rayproc::test {

using rayproc::serve::Json;
using rayproc::serve::Server;
using rayproc::serve::Session;

// A session on a scene (the Cornell box unless named) and its server on the first free port
// from 8080 up.
struct Served {
    Session session;
    Server server{session, 0};
    explicit Served(const std::string& scene = scenePath("cornell-box"))
        : session(scene, Session::Options{2, 64}) {}
    // The worker ends before the server goes (as rayproc serve does): it broadcasts through it.
    ~Served() { session.stop(); }
};

// One TCP connection to 127.0.0.1: a request with chosen headers, then WebSocket frames.
// The server learns that a client closed its socket on civetweb's thread, some time after the
// close: the number of clients once it is down to `expected`, or after 10 s, what it is then.
inline std::size_t clientsOnceSettled(const Server& server, std::size_t expected) {
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
    // Bytes as they are (half a request, say).
    void sendRaw(const std::string& bytes) { sendAll(bytes); }
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

inline std::string statusLine(const std::string& head) {
    return head.substr(0, head.find("\r\n"));
}

} // namespace rayproc::test
