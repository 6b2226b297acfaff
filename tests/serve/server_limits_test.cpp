// rayproc serve against a careless or hostile client (docs/robustness.md, "rayproc serve's
// clients"; issue 36): bytes that are not UTF-8. Each test drives the real server over a socket
// (serve_client.h). Before the fix the first frame of them ended the process (status 134).
#include "serve/serve_client.h"

#include <memory>

using namespace rayproc;
using namespace rayproc::test;

namespace {

std::string hostOf(const Served& s) { return "Host: 127.0.0.1:" + std::to_string(s.server.port()); }

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
