// rayproc serve against a careless or hostile client (docs/serve.md, "Limits"; issue 36): bytes
// that are not UTF-8, cameras outside Embree's range, many open pages, idle connections. Each
// drives the real server over a socket (serve_client.h). Before the fixes the first two ended
// the process (status 134) and the last two left requests unanswered for as long as the
// sockets stayed open, or 30 s.
#include "serve/serve_client.h"

#include "accel/embree_scene.h"
#include "scene/scene_loader.h"

#include <memory>

using namespace rayproc;
using namespace rayproc::test;

namespace {

std::string hostOf(const Served& s) {
    return "Host: 127.0.0.1:" + std::to_string(s.server.port());
}

// A WebSocket to the server that has read its first state.
std::unique_ptr<RawClient> openPage(const Served& s) {
    auto c = std::make_unique<RawClient>(s.server.port());
    REQUIRE(statusLine(c->handshake({hostOf(s)})) == "HTTP/1.1 101 Switching Protocols");
    REQUIRE(c->readText("state")["type"] == "state");
    return c;
}

std::string errorAfter(RawClient& c, const std::string& message) {
    c.sendFrame(1, message);
    Json error = c.readText("error");
    REQUIRE(error.is_object());
    return error["message"].get<std::string>();
}

} // namespace

TEST_CASE("serve: a text frame that is not UTF-8 gets an error reply - the server goes on",
          "[serve]") {
    Served s;
    auto c = openPage(s);
    // A lone 0xff (what ended the server: the error quoting it could not be written as JSON),
    // invalid bytes inside a string and in a key, a truncated two-byte sequence.
    for (const std::string& bad :
         {std::string("\xff"), std::string("{\"type\": \"st\xfe\xff\"}"),
          std::string("{\"type\": \"camera\", \"\xc3\": 1}"), std::string("\xc3")}) {
        INFO(bad);
        CHECK_THAT(errorAfter(*c, bad), Catch::Contains("malformed message"));
    }
    c->sendFrame(1, "{\"type\": \"state\"}");
    CHECK(c->readText("state")["type"] == "state");
}

TEST_CASE("serve: cameras outside Embree's range are refused naming the position - what serve "
          "saves, render loads",
          "[serve]") {
    Served s;
    auto c = openPage(s);
    auto camera = [](double z) {
        return Json({{"type", "camera"}, {"position", {0, 1, z}}, {"look_at", {0, 1, 0}}}).dump();
    };
    // 1e19 aborted the preview inside Embree; 1e17 was accepted and saved, and render refused
    // the file; 1e30 was refused as "up must not be parallel".
    for (auto [z, printed] : {std::pair{1e19, "1e+19"}, {1e17, "1e+17"}, {1e30, "1e+30"}}) {
        INFO(printed);
        std::string message = errorAfter(*c, camera(z));
        CHECK_THAT(message,
                   Catch::Contains("camera.position") &&
                       Catch::Contains("the camera is at a coordinate of " + std::string(printed)));
        CHECK_THAT(message, !Catch::Contains("parallel"));
    }
    // Far, but in range: accepted, saved, and the saved scene loads and builds for rendering.
    c->sendFrame(1, camera(1e15));
    REQUIRE(c->readText("camera")["type"] == "camera");
    TempDir dir;
    c->sendFrame(1, Json({{"type", "save"}, {"path", dir.file("far.json")}}).dump());
    REQUIRE(c->readText("saved")["type"] == "saved");
    std::unique_ptr<Scene> saved = loadScene(dir.file("far.json"));
    CHECK(saved->camera.position.z == 1e15f);
    CHECK_NOTHROW(EmbreeScene(*saved));
    c->sendFrame(1, "{\"type\": \"pick\", \"x\": 0.5, \"y\": 0.5}");
    CHECK(c->readText("picked")["type"] == "picked");
}

TEST_CASE("serve: pages still load with many WebSockets open - beyond the cap one is refused "
          "with 503",
          "[serve]") {
    Served s;
    std::vector<std::unique_ptr<RawClient>> pages;
    for (std::size_t i = 0; i < Server::kMaxWebSockets; ++i) pages.push_back(openPage(s));
    {
        RawClient extra(s.server.port());
        std::string head = extra.handshake({hostOf(s)});
        CHECK(statusLine(head) == "HTTP/1.1 503 Service Unavailable");
        CHECK(extra.closedByServer());
    }
    // 15 open sockets used to leave every page load unanswered.
    for (const char* path : {"/", "/image.png"}) {
        RawClient get(s.server.port());
        CHECK(statusLine(get.request(path, {hostOf(s)})) == "HTTP/1.1 200 OK");
    }
    // A page closes: once the server has seen it, another may open.
    pages.pop_back();
    REQUIRE(clientsOnceSettled(s.server, Server::kMaxWebSockets - 1) == Server::kMaxWebSockets - 1);
    pages.push_back(openPage(s));
}

TEST_CASE("serve: idle connections neither block requests nor stay open", "[serve]") {
    Served s;
    // More than civetweb's threads were (16): each idle connection held one for 30 s.
    std::vector<std::unique_ptr<RawClient>> idle;
    for (int i = 0; i < 24; ++i) idle.push_back(std::make_unique<RawClient>(s.server.port()));
    RawClient get(s.server.port());
    CHECK(statusLine(get.request("/", {hostOf(s)})) == "HTTP/1.1 200 OK");
    // Dropped by the server well within the client's 20 s receive timeout (request_timeout_ms).
    CHECK(idle.front()->closedByServer());
    CHECK(idle.back()->closedByServer());
    // A connection that sent half a request is dropped too.
    RawClient half(s.server.port());
    half.sendRaw("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n");
    CHECK(half.closedByServer());
}
