// What session.cpp (the model, the worker) and session_messages.cpp (one function per page
// message) share: the checks that refuse a malformed message with the field it names, and the
// JSON forms of vectors and of the display settings. Internal to src/serve.
#pragma once

#include "core/error.h"
#include "serve/session.h"

#include <cmath>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace rayproc::serve::session_detail {

inline const std::vector<std::string> kMessageTypes = {
    "state", "camera", "pick", "transform", "material", "emission", "light",
    "undo", "redo", "save", "render", "cancel", "display", "view"};
[[noreturn]] inline void refuse(const std::string& what) { throw InputError(what); }

inline const Json& field(const Json& m, const char* key, const char* type) {
    if (!m.contains(key)) refuse(std::string(type) + ": missing \"" + key + "\"");
    return m[key];
}

inline double finite(const Json& v, const std::string& where) {
    if (!v.is_number()) refuse(where + ": expected a number");
    double d = v.get<double>();
    if (!std::isfinite(d) || std::abs(d) > 3.0e38) refuse(where + ": expected a finite number");
    return d;
}

inline Vec3 vec3(const Json& v, const std::string& where) {
    if (!v.is_array() || v.size() != 3) refuse(where + ": expected an array of 3 numbers");
    return {float(finite(v[0], where)), float(finite(v[1], where)), float(finite(v[2], where))};
}

inline Json vec3Json(const Vec3& v) { return Json::array({double(v.x), double(v.y), double(v.z)}); }

// Keys a message may carry, besides "type".
inline void expectKeys(const Json& m, std::initializer_list<const char*> allowed) {
    for (auto it = m.begin(); it != m.end(); ++it) {
        if (it.key() == "type") continue;
        bool ok = false;
        for (const char* a : allowed) ok |= it.key() == a;
        if (!ok) refuse(m["type"].get<std::string>() + ": unknown key \"" + it.key() + "\"");
    }
}

inline const std::vector<std::pair<std::string, ToneMap>> kToneMaps = {
    {"clamp", ToneMap::Clamp}, {"reinhard", ToneMap::Reinhard}, {"aces", ToneMap::Aces}};

inline Json displayJson(const ToneMapSettings& tm) {
    std::string op;
    for (const auto& [name, value] : kToneMaps)
        if (value == tm.op) op = name;
    return {{"exposure", double(tm.exposure)}, {"tone_map", op}};
}

} // namespace rayproc::serve::session_detail
