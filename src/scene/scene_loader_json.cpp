// JsonRef: checked reads of scene-file values, each error naming the file and JSON pointer.
// Also the transform syntax, which every kind of node shares.
#include "core/error.h"
#include "scene/scene_loader_detail.h"

#include <nlohmann/json.hpp>

#include <cfloat>
#include <cmath>
#include <cstdio>

namespace rayproc::scene_json {

namespace {

std::string inQuotes(std::string_view s) {
    std::string out(1, '"');
    out.append(s);
    out.push_back('"');
    return out;
}

std::string formatNumber(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

} // namespace

// RFC 6901: "~" and "/" inside a key are escaped so that the pointer stays unambiguous.
std::string pointerToken(std::string_view key) {
    std::string out;
    for (char c : key) {
        if (c == '~')
            out += "~0";
        else if (c == '/')
            out += "~1";
        else
            out += c;
    }
    return out;
}

std::string joinNames(const std::vector<std::string>& names) {
    if (names.empty()) return "(none)";
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

std::string parseType(const JsonRef& v, std::string_view what,
                      const std::vector<std::string>& known) {
    if (!v.isObject()) v.fail("expected an object (a " + std::string(what) + ")");
    if (!v.has("type")) {
        v.fail("missing required key \"type\"; " + std::string(what) +
               " types: " + joinNames(known));
    }
    std::string type = v["type"].string();
    for (const std::string& k : known)
        if (k == type) return type;
    v["type"].fail("unknown " + std::string(what) + " type \"" + type +
                   "\"; known types: " + joinNames(known));
}

JsonRef::JsonRef(const Json& value, const std::string& file, std::string pointer)
    : m_value(&value), m_file(&file), m_pointer(std::move(pointer)) {}

void JsonRef::fail(const std::string& problem) const {
    throw InputError(*m_file, m_pointer.empty() ? "/" : m_pointer, problem);
}

bool JsonRef::isObject() const {
    return m_value->is_object();
}
bool JsonRef::isArray() const {
    return m_value->is_array();
}
bool JsonRef::isNumber() const {
    return m_value->is_number();
}
bool JsonRef::isString() const {
    return m_value->is_string();
}

void JsonRef::expectObject(std::initializer_list<std::string_view> allowed,
                           std::string_view what) const {
    expectObject(std::vector<std::string_view>(allowed), what);
}

void JsonRef::expectObject(const std::vector<std::string_view>& allowed,
                           std::string_view what) const {
    if (!m_value->is_object()) fail("expected an object (" + std::string(what) + ")");
    for (const auto& item : m_value->items()) {
        bool known = false;
        for (std::string_view a : allowed) known = known || a == item.key();
        if (known) continue;
        std::vector<std::string> names(allowed.begin(), allowed.end());
        child(item.key())
            .fail("unknown key " + inQuotes(item.key()) + " in " + std::string(what) +
                  "; allowed keys: " + joinNames(names));
    }
}

bool JsonRef::has(std::string_view key) const {
    return m_value->is_object() && m_value->find(std::string(key)) != m_value->end();
}

JsonRef JsonRef::child(std::string_view key) const {
    std::string p = m_pointer + "/" + pointerToken(key);
    if (has(key)) return JsonRef(m_value->find(std::string(key)).value(), *m_file, std::move(p));
    return JsonRef(*m_value, *m_file, std::move(p)); // only good for naming the missing key
}

JsonRef JsonRef::operator[](std::string_view key) const {
    if (!m_value->is_object()) fail("expected an object");
    if (!has(key)) fail("missing required key " + inQuotes(key));
    return child(key);
}

std::vector<std::string> JsonRef::keys() const {
    std::vector<std::string> out;
    if (m_value->is_object())
        for (const auto& item : m_value->items()) out.push_back(item.key());
    return out;
}

std::size_t JsonRef::arraySize() const {
    if (!m_value->is_array()) fail("expected an array");
    return m_value->size();
}

JsonRef JsonRef::operator[](std::size_t index) const {
    if (!m_value->is_array()) fail("expected an array");
    if (index >= m_value->size()) fail("missing array element " + std::to_string(index));
    return JsonRef((*m_value)[index], *m_file, m_pointer + "/" + std::to_string(index));
}

float JsonRef::number() const {
    if (!m_value->is_number()) fail("expected a number");
    double d = m_value->get<double>();
    // JSON cannot spell NaN or Inf, but a literal such as 1e999 parses to infinity, and 1e39
    // is finite as a double yet infinite as a float.
    if (!std::isfinite(d) || std::fabs(d) > double(FLT_MAX))
        fail("expected a finite number; this one overflows a 32-bit float");
    return float(d);
}

float JsonRef::numberIn(float lo, float hi) const {
    float x = number();
    if (x < lo || x > hi) {
        fail("number " + formatNumber(x) + " out of range: expected " + formatNumber(lo) + " to " +
             formatNumber(hi));
    }
    return x;
}

float JsonRef::positive() const {
    float x = number();
    if (x < 0) fail("must be positive, got a negative number " + formatNumber(x));
    if (x == 0) fail("must be positive, got zero");
    return x;
}

long long JsonRef::integer(long long lo, long long hi) const {
    const Json& j = *m_value;
    long long v = 0;
    bool inRange = true;
    if (j.is_number_unsigned()) {
        auto u = j.get<unsigned long long>();
        inRange = u <= static_cast<unsigned long long>(hi);
        v = inRange ? static_cast<long long>(u) : hi;
    } else if (j.is_number_integer()) {
        v = j.get<long long>();
    } else if (j.is_number_float()) {
        // Accept 16.0 but not 16.5; huge literals fall out of range below.
        double d = j.get<double>();
        if (!std::isfinite(d) || d != std::floor(d)) fail("expected an integer");
        // double(hi) may round up past hi (double(LLONG_MAX) is 2^63), and converting a double
        // beyond the range of long long is undefined: stay strictly below 2^63.
        inRange = d >= double(lo) && d <= double(hi) && d < 9223372036854775808.0;
        v = inRange ? static_cast<long long>(d) : lo;
    } else {
        fail("expected an integer");
    }
    if (!inRange || v < lo || v > hi) {
        fail("integer out of range: expected " + std::to_string(lo) + " to " + std::to_string(hi));
    }
    return v;
}

bool JsonRef::boolean() const {
    if (!m_value->is_boolean()) fail("expected true or false");
    return m_value->get<bool>();
}

std::string JsonRef::string() const {
    if (!m_value->is_string()) fail("expected a string");
    return m_value->get<std::string>();
}

std::string JsonRef::nonEmptyString() const {
    std::string s = string();
    if (s.empty()) fail("expected a non-empty string");
    return s;
}

Vec2 JsonRef::vec2() const {
    if (!m_value->is_array() || m_value->size() != 2) fail("expected an array of 2 numbers");
    return {(*this)[std::size_t(0)].number(), (*this)[1].number()};
}

Vec3 JsonRef::vec3() const {
    if (!m_value->is_array() || m_value->size() != 3) fail("expected an array of 3 numbers");
    return {(*this)[std::size_t(0)].number(), (*this)[1].number(), (*this)[2].number()};
}

Vec3 JsonRef::direction() const {
    Vec3 d = vec3();
    double len2 = double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z;
    if (len2 == 0) fail("direction must be non-zero");
    if (!std::isfinite(len2)) d = d * 1e-30f; // normalise huge vectors without overflow
    return normalize(d);
}

Vec3 JsonRef::color() const {
    Vec3 c = vec3();
    for (int i = 0; i < 3; ++i)
        if (c[i] < 0) (*this)[std::size_t(i)].fail("colour components must not be negative");
    return c;
}

Vec3 JsonRef::albedo() const {
    Vec3 c = vec3();
    for (int i = 0; i < 3; ++i) {
        if (c[i] < 0 || c[i] > 1)
            (*this)[std::size_t(i)].fail("reflectance components must lie in [0, 1]");
    }
    return c;
}

// ---------------------------------------------------------------------------------------------
// Transforms

namespace {

Affine parseMatrix(const JsonRef& v) {
    std::size_t n = v.arraySize();
    if (n != 12 && n != 16) {
        v.fail("expected an array of 12 or 16 numbers (a row-major matrix), got " +
               std::to_string(n) + " elements");
    }
    Affine a;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) a.m[r][c] = v[std::size_t(r * 4 + c)].number();
    if (n == 16) {
        const float lastRow[4] = {0, 0, 0, 1};
        for (int c = 0; c < 4; ++c) {
            if (v[std::size_t(12 + c)].number() != lastRow[c])
                v.fail("the last row of a 4x4 transform must be 0 0 0 1 (affine only)");
        }
    }
    return a;
}

Affine parseRotation(const JsonRef& v) {
    v.expectObject({"angle", "axis"}, "a rotation");
    return Affine::rotate(v["angle"].number(), v["axis"].direction());
}

} // namespace

Affine parseTransform(const JsonRef& v) {
    Affine a;
    if (v.isArray()) {
        a = parseMatrix(v);
    } else {
        if (!v.isObject())
            v.fail("expected a transform: an array of 12 or 16 numbers, or an object");
        v.expectObject({"translate", "rotate", "scale"}, "a transform");
        Affine t, r, s;
        if (v.has("translate")) t = Affine::translate(v["translate"].vec3());
        if (v.has("rotate")) {
            // A list of rotations acts in the order written: the first one turns the object
            // first, so it stands rightmost in the product.
            JsonRef rot = v["rotate"];
            if (rot.isArray()) {
                for (std::size_t i = 0; i < rot.arraySize(); ++i) r = parseRotation(rot[i]) * r;
            } else {
                r = parseRotation(rot);
            }
        }
        if (v.has("scale")) {
            JsonRef sc = v["scale"];
            if (!sc.isNumber() && !sc.isArray())
                sc.fail("expected a number or an array of 3 numbers");
            Vec3 f = sc.isNumber() ? Vec3(sc.number()) : sc.vec3();
            if (f.x == 0 || f.y == 0 || f.z == 0) sc.fail("scale factors must be non-zero");
            s = Affine::scale(f);
        }
        a = t * r * s;
    }
    float det = a.determinant();
    if (det == 0 || !std::isfinite(det))
        v.fail("transform is singular (determinant 0) or not finite");
    return a;
}

} // namespace rayproc::scene_json
