// rayproc serve's web server (docs/serve.md): HTTP and WebSocket on 127.0.0.1 with civetweb.
//   GET /            the page (embedded in the binary: src/serve/page.cpp)
//   GET /image.png   the last render in raytrace, gi or path (partial after a cancel), else
//                    the live preview, PNG
//   GET /image.exr   the same, linear EXR
//   WS  /ws          JSON messages from the page (Session::handle), replies and events as
//                    JSON text, frames as binary messages (encodeFrame)
// Every request must name this server in Host, and a WebSocket may come only from this
// server's own page (Origin) or from a client that is not a browser (no Origin); anything else
// is refused with 403 (docs/serve.md, "Who may connect").
#pragma once

#include "serve/session.h"

#include <map>
#include <mutex>
#include <set>
#include <string>

struct mg_context;
struct mg_connection;

namespace rayproc::serve {

extern const char* const kPage; // the page's HTML, CSS and JavaScript

class Server {
public:
    // civetweb's worker threads, and how many of them WebSockets (open pages) may hold: the
    // rest answer page loads and downloads. A WebSocket beyond the cap is refused with 503.
    static constexpr int kThreads = 64;
    static constexpr std::size_t kMaxWebSockets = 32;

    // Listens on 127.0.0.1:port (0: the first free port from 8080 up); throws InputError when
    // the port is taken.
    Server(Session& session, int port);
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;
    int port() const { return m_port; }
    std::size_t clients() const;

    // civetweb's callbacks (public for the C trampolines in server.cpp).
    int onConnect(const mg_connection* conn); // 0: go on with the WebSocket handshake
    int onRequest(mg_connection* conn, const std::string& uri);
    void onReady(mg_connection* conn);
    int onData(mg_connection* conn, int flags, const char* data, std::size_t length);
    void onClose(const mg_connection* conn);

private:
    // Why a request is refused, empty when it is not: its Host must name this server
    // (127.0.0.1, localhost or [::1] at its port), and a WebSocket's Origin, when there is one,
    // must be this server's own page.
    std::string refusal(const mg_connection* conn, bool websocket) const;
    int handleData(mg_connection* conn, int flags, const char* data, std::size_t length);
    void broadcast(int opcode, const void* data, std::size_t length);
    void sendTo(mg_connection* conn, int opcode, const std::string& text);

    Session& m_session;
    mg_context* m_context = nullptr;
    int m_port = 0;
    mutable std::mutex m_mutex;
    std::map<const mg_connection*, int> m_clients; // connection -> client id
    // Handshakes accepted whose ready callback has not come yet (they count against the cap).
    std::set<const mg_connection*> m_opening;
    int m_nextClient = 1;
};

} // namespace rayproc::serve
