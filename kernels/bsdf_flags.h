// Which lobes a BSDF has, as pbrt-v4's BxDFFlags and Mitsuba 3's BSDFFlags name them: the
// stages route a hit by these (engine/surface_stage.cpp), not by the material's name.
// Reflection / Transmission: the sides light leaves on; Diffuse, Glossy, Specular: how wide
// the lobes are (Specular: delta, found only by sampling). kLobeStraight is rayproc's own: a
// transmission that does not bend (pbrt-v4's thin dielectric slab), which the refraction stage's
// model of one refracting interface does not describe.
#pragma once

#include <cstdint>

namespace rayproc::kernels {

using LobeFlags = std::uint8_t;

enum LobeFlag : LobeFlags {
    kLobeReflection = 1,
    kLobeTransmission = 2,
    kLobeDiffuse = 4,
    kLobeGlossy = 8,
    kLobeSpecular = 16,
    kLobeStraight = 32,
};

constexpr bool hasLobe(LobeFlags flags, LobeFlags lobe) { return (flags & lobe) != 0; }

// Only delta lobes: light sampling cannot help, every direction has density zero.
constexpr bool onlySpecular(LobeFlags flags) {
    return !hasLobe(flags, LobeFlags(kLobeDiffuse | kLobeGlossy));
}

} // namespace rayproc::kernels
