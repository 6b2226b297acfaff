// The PLY header, private to ply_reader.cpp: the format, the elements and their properties.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace rayproc::pbrt::ply {

enum class Format { Ascii, BinaryLittle, BinaryBig };
enum class Type { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

struct Property {
    std::string name;
    Type type = Type::Float32; // of the value, or of a list's items
    bool isList = false;
    Type countType = Type::Uint8;
    int slot = -1;          // where the reader stores the value; -1: skipped
    std::size_t offset = 0; // in a fixed-size binary row
};

struct Element {
    std::string name;
    std::size_t count = 0;
    std::vector<Property> props;
    bool fixedSize() const {
        for (const Property& p : props)
            if (p.isList) return false;
        return true;
    }
};

std::size_t typeSize(Type t);

// Throws InputError "<path>: <problem>".
[[noreturn]] void fail(const std::string& path, const std::string& problem);

// Reads the header; returns the offset of the first data byte.
std::size_t parseHeader(std::string_view bytes, const std::string& path, Format& format,
                        std::vector<Element>& elements);

} // namespace rayproc::pbrt::ply
