// Checks of command-line values shared by every command and by the modes' own options
// (modes/mode_options.h), so a mode can declare its options without including cli/.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <limits>
#include <string>

namespace rayproc {

// Refuses NaN and infinities in a floating-point option: CLI11 reads "nan" and "inf" as
// numbers, and its Range and PositiveNumber checks let NaN through (every comparison with NaN
// is false). Attached to every float option of every command. With `floatRange`, also
// magnitudes beyond float's range (3.4e38), finite as text and in double but infinite once
// stored in a float.
inline CLI::Validator finiteNumber(bool floatRange = false) {
    return CLI::Validator(
        [floatRange](std::string& text) -> std::string {
            try {
                std::size_t used = 0;
                double v = std::stod(text, &used);
                if (!std::isfinite(v)) return "must be a finite number, got " + text;
                if (floatRange && std::abs(v) > double(std::numeric_limits<float>::max()))
                    return "must be at most 3.4e38 in magnitude (a float), got " + text;
            } catch (const std::exception&) {
                return {}; // not a number at all: the option's own conversion says so
            }
            return {};
        },
        "");
}

// finiteNumber for an option stored as a float.
inline CLI::Validator finiteFloat() { return finiteNumber(true); }

} // namespace rayproc
