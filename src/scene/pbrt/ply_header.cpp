#include "scene/pbrt/ply_header.h"

#include "core/error.h"

#include <sstream>

namespace rayproc::pbrt::ply {

std::size_t typeSize(Type t) {
    switch (t) {
    case Type::Int8:
    case Type::Uint8:
        return 1;
    case Type::Int16:
    case Type::Uint16:
        return 2;
    case Type::Int32:
    case Type::Uint32:
    case Type::Float32:
        return 4;
    case Type::Float64:
        return 8;
    }
    return 1;
}

static bool parseType(const std::string& s, Type& t) {
    static const std::pair<const char*, Type> kNames[] = {
        {"char", Type::Int8},      {"int8", Type::Int8},       {"uchar", Type::Uint8},
        {"uint8", Type::Uint8},    {"short", Type::Int16},     {"int16", Type::Int16},
        {"ushort", Type::Uint16},  {"uint16", Type::Uint16},   {"int", Type::Int32},
        {"int32", Type::Int32},    {"uint", Type::Uint32},     {"uint32", Type::Uint32},
        {"float", Type::Float32},  {"float32", Type::Float32}, {"double", Type::Float64},
        {"float64", Type::Float64}};
    for (const auto& [n, v] : kNames) {
        if (s == n) {
            t = v;
            return true;
        }
    }
    return false;
}

void fail(const std::string& path, const std::string& problem) {
    throw InputError(path + ": " + problem);
}

// Reads the header; returns the offset of the first data byte.
std::size_t parseHeader(std::string_view bytes, const std::string& path, Format& format,
                        std::vector<Element>& elements) {
    if (bytes.substr(0, 3) != "ply" || (bytes.size() > 3 && bytes[3] != '\n' && bytes[3] != '\r'))
        fail(path, "not a PLY file (it does not start with \"ply\")");
    std::size_t pos = 0;
    bool haveFormat = false;
    for (int lineNo = 1;; ++lineNo) {
        std::size_t eol = bytes.find('\n', pos);
        if (eol == std::string_view::npos) fail(path, "the header has no end_header line");
        std::string line(bytes.substr(pos, eol - pos));
        pos = eol + 1;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream in(line);
        std::string word;
        in >> word;
        auto bad = [&](const std::string& what) {
            fail(path,
                 "header line " + std::to_string(lineNo) + ": " + what + ": \"" + line + "\"");
        };
        if (word == "ply" && lineNo == 1) continue;
        if (word.empty() || word == "comment" || word == "obj_info") continue;
        if (word == "end_header") break;
        if (word == "format") {
            std::string f, version;
            in >> f >> version;
            if (f == "ascii")
                format = Format::Ascii;
            else if (f == "binary_little_endian")
                format = Format::BinaryLittle;
            else if (f == "binary_big_endian")
                format = Format::BinaryBig;
            else
                bad("unknown format");
            haveFormat = true;
        } else if (word == "element") {
            Element e;
            long long count = -1;
            in >> e.name >> count;
            if (e.name.empty() || count < 0 || in.fail()) bad("malformed element");
            e.count = std::size_t(count);
            elements.push_back(std::move(e));
        } else if (word == "property") {
            if (elements.empty()) bad("property before any element");
            Property p;
            std::string t;
            in >> t;
            if (t == "list") {
                std::string ct, it;
                in >> ct >> it >> p.name;
                p.isList = true;
                if (!parseType(ct, p.countType) || !parseType(it, p.type)) bad("unknown type");
            } else {
                in >> p.name;
                if (!parseType(t, p.type)) bad("unknown type");
            }
            if (p.name.empty()) bad("property without a name");
            elements.back().props.push_back(p);
        } else {
            bad("unknown header keyword \"" + word + "\"");
        }
    }
    if (!haveFormat) fail(path, "the header has no format line");
    return pos;
}

} // namespace rayproc::pbrt::ply
