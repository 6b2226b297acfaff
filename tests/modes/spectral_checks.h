// What the spectral mode's tests share (spectral_mode_test.cpp, spectral_gi_test.cpp): a
// grey Cornell box, whose spectral render must have its RGB render's mean, and that check.
#pragma once

#include "../analytic/analytic.h"

#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace rayproc::test {

// The Cornell box with every colour (materials and emission) replaced by its channel mean.
inline std::string greyCornellBox() {
    std::ifstream in(scenePath("cornell-box"));
    std::stringstream text;
    text << in.rdbuf();
    std::string json = text.str(), out;
    std::regex triple(R"re("(color|emission)": \[([0-9.]+), ([0-9.]+), ([0-9.]+)\])re");
    auto it = std::sregex_iterator(json.begin(), json.end(), triple);
    std::size_t last = 0;
    int replaced = 0;
    for (; it != std::sregex_iterator(); ++it) {
        const std::smatch& m = *it;
        double mean = (std::stod(m[2]) + std::stod(m[3]) + std::stod(m[4])) / 3;
        out += json.substr(last, std::size_t(m.position()) - last);
        out += "\"" + m[1].str() + "\": " + jsonVec(Vec3(float(mean)));
        last = std::size_t(m.position() + m.length());
        ++replaced;
    }
    REQUIRE(replaced >= 8); // every material and the light
    return out + json.substr(last);
}

// Checks per channel that two renders of one scene (different random numbers) have the same
// mean over the pixels that see no emitter (RGB below 1 in `a`): their per-pixel difference's
// mean within 4 of its standard errors (the renders' noise, not the image's content) plus
// `slack` of the mean, and that the check can see a 1% difference.
inline void checkSameMean(const Image& a, const Image& b, const std::string& label,
                          double slack = 2e-3) {
    REQUIRE(a.pixels.size() == b.pixels.size());
    for (int c = 0; c < 3; ++c) {
        double sum = 0, sumSq = 0, meanA = 0;
        std::size_t n = 0;
        for (std::size_t p = 0; p < a.pixels.size() / 3; ++p) {
            if (a.pixels[3 * p] > 1 || a.pixels[3 * p + 1] > 1 || a.pixels[3 * p + 2] > 1)
                continue;
            ++n;
            double d = double(b.pixels[3 * p + c]) - a.pixels[3 * p + c];
            sum += d;
            sumSq += d * d;
            meanA += a.pixels[3 * p + c];
        }
        double mean = sum / double(n), var = sumSq / double(n) - mean * mean;
        double stdError = std::sqrt(std::max(var, 0.0) / double(n - 1));
        meanA /= double(n);
        INFO(label << " channel " << c << ": mean " << meanA << ", difference " << mean
                   << " +- " << stdError);
        CHECK(std::abs(mean) <= 4 * stdError + slack * meanA);
        CHECK(n > a.pixels.size() / 3 / 2);
        CHECK(stdError < 0.0025 * meanA);
    }
}

} // namespace rayproc::test
