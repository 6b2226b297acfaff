// A directive's parameter list: "type name" value pairs, where the value is one token or a
// bracketed list. Types are checked while parsing (a string where numbers belong, a fractional
// integer, a point3 list that is not a multiple of three are input errors) and again when the
// converter asks for a parameter (asking for "fov" as a float when the file declares a string is
// an input error). Every lookup marks the parameter used, so that whatever the converter never
// asked for can be reported as unsupported.
#pragma once

#include "core/math.h"
#include "scene/pbrt/pbrt_tokenizer.h"

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace rayproc::pbrt {

struct Param {
    std::string type; // normalised: integer float point2 vector2 point3 vector3 normal3 rgb
                      // spectrum blackbody bool string texture
    std::string name;
    SourceLoc loc;
    std::vector<double> numbers;      // numeric types, and spectra given as numbers
    std::vector<std::string> strings; // string, texture, and named spectra
    std::vector<char> bools;
    mutable bool used = false;

    std::string decl() const { return "\"" + type + " " + name + "\""; }
    std::size_t size() const;
};

class ParamList {
public:
    // Reads parameters from `tok` while the next token is a quoted declaration.
    void parse(Tokenizer& tok);

    const std::vector<Param>& all() const { return m_params; }
    bool has(std::string_view name) const { return find(name) != nullptr; }
    const Param* find(std::string_view name) const;

    // Single values; a missing parameter gives `def`. A parameter of another type, or with more
    // than one value, is an input error at its declaration.
    double getFloat(std::string_view name, double def) const;
    long long getInt(std::string_view name, long long def) const;
    bool getBool(std::string_view name, bool def) const;
    std::string getString(std::string_view name, const std::string& def) const;
    Vec3 getPoint3(std::string_view name, Vec3 def) const;
    Vec3 getVector3(std::string_view name, Vec3 def) const;

    // The parameter if present, checked against the accepted types; marks it used.
    const Param* get(std::string_view name, std::initializer_list<std::string_view> types) const;

    // Marks parameters as consumed without reading them (accepted and deliberately ignored).
    void ignore(std::initializer_list<std::string_view> names) const;
    std::vector<const Param*> unused() const;

private:
    const Param* single(std::string_view name, std::string_view type) const;
    std::vector<Param> m_params;
};

// "foo" as a parameter type name in messages, and pbrt's aliases (point -> point3,
// normal -> normal3, color -> rgb, ...); empty if `type` is not a pbrt parameter type.
std::string normaliseParamType(std::string_view type);

// Parses a number the way pbrt writes them ("1", "-0.5", "+2", ".5", "1e-3"); false if `text`
// is not a finite number.
bool parseNumber(std::string_view text, double& out);

} // namespace rayproc::pbrt
