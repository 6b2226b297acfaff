#include "serve/server.h"

#include "core/error.h"
#include "image/image.h"

#include <civetweb.h>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>
#include <vector>

namespace rayproc::serve {

namespace {

Server* serverOf(const mg_connection* conn) {
    return static_cast<Server*>(mg_get_user_data(mg_get_context(conn)));
}

int onRequestTrampoline(mg_connection* conn, void*) {
    const mg_request_info* info = mg_get_request_info(conn);
    return serverOf(conn)->onRequest(conn, info->local_uri ? info->local_uri : "");
}
int onConnectTrampoline(const mg_connection* conn, void*) {
    return serverOf(conn)->onConnect(conn);
}
void onReadyTrampoline(mg_connection* conn, void*) { serverOf(conn)->onReady(conn); }
int onDataTrampoline(mg_connection* conn, int flags, char* data, size_t length, void*) {
    return serverOf(conn)->onData(conn, flags, data, length);
}
void onCloseTrampoline(const mg_connection* conn, void*) { serverOf(conn)->onClose(conn); }

// The image as a file's bytes, through the writers `rayproc render` uses (a PNG with the page's
// exposure and tone map; an EXR stays linear).
std::string imageBytes(const Image& img, const std::string& extension, const ToneMapSettings& tm) {
    std::string dir = std::filesystem::temp_directory_path().string();
    std::string path = dir + "/rayproc-serve-" + std::to_string(::getpid()) + "-" +
                       std::to_string(reinterpret_cast<std::uintptr_t>(&img)) + extension;
    writeImage(path, img, tm);
    std::ifstream in(path, std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    std::filesystem::remove(path);
    return bytes.str();
}

// "name:port" (or "name" for port 80) with name 127.0.0.1, localhost or [::1], any case.
bool namesLoopback(std::string authority, int port) {
    for (char& c : authority) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const char* name : {"127.0.0.1", "localhost", "[::1]"}) {
        if (authority == std::string(name) + ":" + std::to_string(port)) return true;
        if (port == 80 && authority == name) return true;
    }
    return false;
}

} // namespace

Server::Server(Session& session, int port) : m_session(session) {
    mg_init_library(0);
    mg_callbacks callbacks;
    std::memset(&callbacks, 0, sizeof callbacks);
    int first = port > 0 ? port : 8080, last = port > 0 ? port : 8180;
    for (int p = first; p <= last && !m_context; ++p) {
        std::string listen = "127.0.0.1:" + std::to_string(p);
        const std::string threads = std::to_string(kThreads);
        // civetweb gives each connection a thread for as long as it is open: a WebSocket for
        // its life, an HTTP connection until its request arrives (request_timeout_ms) or, kept
        // alive, until the next one does (keep_alive_timeout_ms). WebSockets may hold at most
        // kMaxWebSockets of the threads; idle connections let go of theirs within seconds.
        // WebSockets themselves do not time out (civetweb waits for their frames without one).
        const char* options[] = {"listening_ports",       listen.c_str(),  //
                                 "num_threads",           threads.c_str(), //
                                 "enable_keep_alive",     "yes",           //
                                 "keep_alive_timeout_ms", "1000",          //
                                 "request_timeout_ms",    "5000",          nullptr};
        m_context = mg_start(&callbacks, this, options);
        if (m_context) m_port = p;
    }
    if (!m_context)
        throw InputError(port > 0 ? "cannot listen on 127.0.0.1:" + std::to_string(port) +
                                        " (in use?); choose another --port"
                                  : std::string("no free port in 127.0.0.1:8080-8180"));
    mg_set_request_handler(m_context, "/", onRequestTrampoline, nullptr);
    mg_set_websocket_handler(m_context, "/ws", onConnectTrampoline, onReadyTrampoline,
                             onDataTrampoline, onCloseTrampoline, nullptr);
    session.start({[this](const std::string& text) {
                       broadcast(MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
                   },
                   [this](const std::vector<std::uint8_t>& frame) {
                       broadcast(MG_WEBSOCKET_OPCODE_BINARY, frame.data(), frame.size());
                   }});
}

Server::~Server() {
    // Pages are told the server is going: civetweb's stop waits for open WebSockets, which a
    // browser would otherwise hold for minutes.
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        static const char bye[] = "\x03\xe9server stopping"; // status 1001 "going away"
        for (auto& [conn, id] : m_clients) {
            auto* c = const_cast<mg_connection*>(conn);
            mg_lock_connection(c);
            mg_websocket_write(c, MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE, bye, sizeof bye - 1);
            mg_unlock_connection(c);
        }
    }
    if (m_context) mg_stop(m_context);
    mg_exit_library();
}

std::size_t Server::clients() const {
    std::lock_guard<std::mutex> lk(m_mutex);
    return m_clients.size();
}

std::string Server::refusal(const mg_connection* conn, bool websocket) const {
    // DNS rebinding: a page of another site whose name now resolves to 127.0.0.1 is
    // same-origin with this server as far as the browser knows, but it names its own host.
    // No Host (an HTTP/1.0 client) is no browser.
    const char* host = mg_get_header(conn, "Host");
    if (host && !namesLoopback(host, m_port))
        return std::string("Host \"") + host + "\" is not this server (127.0.0.1:" +
               std::to_string(m_port) + ")";
    // A WebSocket is not bound by the same-origin policy: any page the browser shows could
    // open one to 127.0.0.1 and send "save". Browsers always name the page's origin; other
    // clients (scripts, tests) send none.
    const char* origin = mg_get_header(conn, "Origin");
    if (websocket && origin) {
        std::string o = origin;
        const std::string scheme = "http://";
        bool own = o.size() > scheme.size() && o.compare(0, scheme.size(), scheme) == 0 &&
                   namesLoopback(o.substr(scheme.size()), m_port);
        if (!own)
            return "a WebSocket from the page of " + o +
                   " is refused: only this server's own page (http://127.0.0.1:" +
                   std::to_string(m_port) + "/) may connect";
    }
    return {};
}

int Server::onConnect(const mg_connection* conn) {
    std::string why = refusal(conn, true);
    const char* status = "403 Forbidden";
    if (why.empty()) {
        std::lock_guard<std::mutex> lk(m_mutex);
        if (m_clients.size() + m_opening.size() < kMaxWebSockets) {
            m_opening.insert(conn);
            return 0; // civetweb goes on with the handshake
        }
        status = "503 Service Unavailable";
        why = "too many open pages: rayproc serve takes " + std::to_string(kMaxWebSockets) +
              " WebSockets at once; close a tab and reload";
    }
    // civetweb sends nothing when the handshake is refused: the client is told why.
    why += "\n";
    auto* c = const_cast<mg_connection*>(conn);
    mg_printf(c,
              "HTTP/1.1 %s\r\nContent-Type: text/plain\r\nContent-Length: %zu\r\n"
              "Connection: close\r\n\r\n",
              status, why.size());
    mg_write(c, why.data(), why.size());
    return 1;
}

int Server::onRequest(mg_connection* conn, const std::string& uri) {
    auto send = [&](int status, const char* type, const std::string& body,
                    const char* extra = "") {
        mg_printf(conn,
                  "HTTP/1.1 %d %s\r\nContent-Type: %s\r\nContent-Length: %zu\r\n"
                  "Cache-Control: no-store\r\n%sConnection: close\r\n\r\n",
                  status,
                  status == 200   ? "OK"
                  : status == 403 ? "Forbidden"
                  : status == 404 ? "Not Found"
                                  : "Error",
                  type, body.size(), extra);
        mg_write(conn, body.data(), body.size());
        return status;
    };
    {
        // civetweb reuses a thread's connection: a handshake it left unfinished there (no
        // ready or close callback) is over and no longer counts against the cap.
        std::lock_guard<std::mutex> lk(m_mutex);
        m_opening.erase(conn);
    }
    std::string why = refusal(conn, false);
    if (!why.empty()) return send(403, "text/plain", why + "\n");
    if (uri == "/" || uri == "/index.html") return send(200, "text/html; charset=utf-8", kPage);
    if (uri == "/image.png" || uri == "/image.exr") {
        // The last render (partial after a cancel), else the live preview.
        Image img;
        if (!m_session.lastRender(img) && !m_session.lastFrame(img))
            return send(404, "text/plain", "no image yet\n");
        bool png = uri == "/image.png";
        try {
            return send(200, png ? "image/png" : "image/x-exr",
                        imageBytes(img, png ? ".png" : ".exr", m_session.display()),
                        png ? "Content-Disposition: attachment; filename=\"render.png\"\r\n"
                            : "Content-Disposition: attachment; filename=\"render.exr\"\r\n");
        } catch (const std::exception& e) {
            return send(500, "text/plain", std::string(e.what()) + "\n");
        }
    }
    return send(404, "text/plain", "not found: " + uri + "\n");
}

void Server::onReady(mg_connection* conn) {
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        m_opening.erase(conn);
        m_clients[conn] = m_nextClient++;
    }
    Json s = m_session.state();
    s["type"] = "state";
    sendTo(conn, MG_WEBSOCKET_OPCODE_TEXT, toText(s));
    // The image so far, so a new tab does not start blank.
    Image img;
    std::uint64_t version = 0;
    if (m_session.lastFrame(img, &version)) {
        std::vector<std::uint8_t> frame = encodeFrame(img, 0, version);
        mg_lock_connection(conn);
        mg_websocket_write(conn, MG_WEBSOCKET_OPCODE_BINARY, reinterpret_cast<const char*>(frame.data()), frame.size());
        mg_unlock_connection(conn);
    }
}

int Server::onData(mg_connection* conn, int flags, const char* data, std::size_t length) {
    // An exception must not unwind into civetweb's C code (it would end the process): a
    // client's message can fail, the server cannot.
    try {
        return handleData(conn, flags, data, length);
    } catch (const std::exception& e) {
        Json error = {{"type", "error"},
                      {"message", std::string("the message failed: ") + e.what()}};
        sendTo(conn, MG_WEBSOCKET_OPCODE_TEXT, toText(error));
    } catch (...) {
        sendTo(conn, MG_WEBSOCKET_OPCODE_TEXT,
               R"({"type": "error", "message": "the message failed"})");
    }
    return 1;
}

int Server::handleData(mg_connection* conn, int flags, const char* data, std::size_t length) {
    int opcode = flags & 0xf;
    bool final = (flags & 0x80) != 0; // FIN: the message's last (here: only) frame
    if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
    int client;
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        auto it = m_clients.find(conn);
        if (it == m_clients.end()) return 0;
        client = it->second;
    }
    // Every message is JSON text in one frame. Anything else is refused like any malformed
    // message, so the client learns why nothing happened; the rest of a refused fragmented
    // message (continuation frames) is dropped without a second reply.
    std::string refused;
    if (opcode == MG_WEBSOCKET_OPCODE_BINARY)
        refused = "a binary WebSocket message is refused: every message is a JSON object sent "
                  "as text (docs/serve.md)";
    else if (opcode == MG_WEBSOCKET_OPCODE_TEXT && !final)
        refused = "a fragmented WebSocket message is refused: send each JSON message as one "
                  "text frame";
    else if (opcode != MG_WEBSOCKET_OPCODE_TEXT)
        return 1; // continuation frames, pings, pongs
    if (!refused.empty()) {
        Json error = {{"type", "error"}, {"message", refused}};
        sendTo(conn, MG_WEBSOCKET_OPCODE_TEXT, toText(error));
        return 1;
    }
    std::string reply = m_session.handle(std::string(data, length), client);
    sendTo(conn, MG_WEBSOCKET_OPCODE_TEXT, reply);
    // Every page shows the same scene: a change reaches them all.
    Json r = Json::parse(reply);
    if (r["type"] == "edited" || r["type"] == "camera" || r["type"] == "display") {
        Json s = m_session.state();
        s["type"] = "state";
        std::string text = toText(s);
        broadcast(MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
    }
    return 1;
}

void Server::onClose(const mg_connection* conn) {
    int client = -1;
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        m_opening.erase(conn);
        auto it = m_clients.find(conn);
        if (it != m_clients.end()) {
            client = it->second;
            m_clients.erase(it);
        }
    }
    if (client >= 0) m_session.clientClosed(client);
}

void Server::sendTo(mg_connection* conn, int opcode, const std::string& text) {
    mg_lock_connection(conn);
    mg_websocket_write(conn, opcode, text.data(), text.size());
    mg_unlock_connection(conn);
}

void Server::broadcast(int opcode, const void* data, std::size_t length) {
    std::lock_guard<std::mutex> lk(m_mutex);
    for (auto& [conn, id] : m_clients) {
        auto* c = const_cast<mg_connection*>(conn);
        mg_lock_connection(c);
        mg_websocket_write(c, opcode, static_cast<const char*>(data), length);
        mg_unlock_connection(c);
    }
}

} // namespace rayproc::serve
