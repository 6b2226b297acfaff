// Colour and scalar parameters as rayproc values: "rgb", "spectrum" (a constant, wavelength /
// value pairs, or a named spectrum), "blackbody", and "texture" references to named textures:
// "constant" ones stand for their value; "imagemap", "scale", "mix" and "checkerboard" become
// entries of Scene::textures that a ColorParam / FloatParam refers to. How a spectrum becomes a colour depends on its use, as in pbrt-v4:
// reflectances must lie in [0, 1]; emission spectra other than RGB are normalised to
// luminance 1 (pbrt's "1 nit" convention; the light's "scale" sets the brightness).
#pragma once

#include "core/math.h"
#include "scene/emission_spectrum.h"
#include "scene/material.h"
#include "scene/texture.h"
#include "scene/pbrt/pbrt_params.h"
#include "scene/pbrt/pbrt_transform.h"
#include "scene/pbrt/pbrt_warnings.h"
#include "spectral/color_space.h"

#include <filesystem>
#include <string>
#include <unordered_map>
#include <vector>

namespace rayproc::pbrt {

enum class SpectrumUse { Albedo, Unbounded, Illuminant };

class ValueReader {
public:
    explicit ValueReader(Warnings& warnings) : m_warnings(warnings) {}
    // Where textures go (Scene::textures) and the folder image file names are relative to.
    void bindTextures(std::vector<rayproc::Texture>* table, std::filesystem::path dir) {
        m_table = table;
        m_dir = std::move(dir);
    }

    // The Texture directive. `type` is "float" or "spectrum" (pbrt-v3's "color" too);
    // `worldFromTexture` the transform at the directive (the mappings other than uv and a
    // direction mix's "dir" are in its space).
    void defineTexture(const std::string& name, const std::string& type,
                       const std::string& className, const ParamList& params, const SourceLoc& loc,
                       const Mat4& worldFromTexture);

    // A colour parameter, or `def` if absent. A texture of a class other than "constant"
    // gives `def` with a warning.
    Vec3 color(const ParamList& params, std::string_view name, SpectrumUse use, Vec3 def) const;
    // An emission colour parameter (SpectrumUse::Illuminant), as color(), and the spectrum the
    // file gave it (a blackbody, pairs, a named illuminant, an "rgb" under another colour space
    // than sRGB) kept whole for the spectral mode; nullptr where the colour is all there is.
    Vec3 emission(const ParamList& params, std::string_view name, Vec3 def,
                  EmissionSpectrumRef& spectrum) const;
    // A reflectance-like parameter (SpectrumUse::Albedo), as colorParam(), and the spectrum
    // the file gave its constant (pairs, an "rgb" under another colour space than sRGB) kept
    // whole for the spectral mode (scene/reflectance_spectrum.h); nullptr where the colour is
    // all there is (sRGB rgb, a texture of another class than "constant").
    ColorParam reflectance(const ParamList& params, std::string_view name, Vec3 def,
                           ReflectanceSpectrumRef& spectrum) const;
    // The same for an unbounded value (SpectrumUse::Unbounded: a conductor's eta and k), its
    // spectrum clamped to >= 0 only.
    ColorParam unbounded(const ParamList& params, std::string_view name, Vec3 def,
                         ReflectanceSpectrumRef& spectrum) const;
    // A float parameter or float texture, or `def`.
    float scalar(const ParamList& params, std::string_view name, float def) const;
    // The same as parameters that may refer to a texture of any class. A texture whose image
    // file was missing gives `def` (the loader warned where the texture was defined).
    ColorParam colorParam(const ParamList& params, std::string_view name, SpectrumUse use,
                          Vec3 def) const;
    FloatParam floatParam(const ParamList& params, std::string_view name, float def) const;

    // A material's "normalmap" image (pbrt-v4 reads it linear, bilinear, repeating) as a new
    // Scene::textures entry: its index, or -1 when the file is missing or unreadable (warned at
    // `loc`; the material then shades with its own normals).
    int normalMapTexture(const std::string& file, const SourceLoc& loc) const;

    // A colour parameter's value as written (rgb, or a float as grey); false for any other
    // type (spectra, blackbody, textures).
    static bool plainColor(const Param& p, Vec3& out);

    // The ColorSpace directive's colour space in the graphics state: "rgb" values read from now
    // on (and constant textures defined from now on) are in it (pbrt_spectrum.h's conversions).
    void setColorSpace(const spectral::ColorSpace& cs) { m_colorSpace = &cs; }

private:
    struct Texture {
        bool isFloat = false;
        bool constant = false;
        std::string className;
        Param value; // "value" of a constant texture (type float, rgb, spectrum or blackbody)
        bool hasValue = false;
        int index = -1;       // Scene::textures entry of the other classes
        bool missing = false; // an image map whose file could not be read
        const spectral::ColorSpace* colorSpace = nullptr; // where it was defined
    };
    // A texture operand ("tex", "tex1", "amount", ...): a texture index or a value; with
    // `spectrum`, a colour value's own spectrum where it has one (operandSpectrum).
    void operand(const ParamList& params, std::string_view name, bool isFloat, Vec3 def,
                 int& index, Vec3& value, OperandSpectrum* spectrum = nullptr) const;
    // A constant colour operand's spectra (none for an sRGB `rgb`, a blackbody, a named one).
    OperandSpectrum operandSpectrum(const Param& p, const spectral::ColorSpace& cs) const;
    // The table's texture `index` as a reflectance reads it: itself, or for a texture with
    // operand spectra (Texture::spectral) a copy whose such operands (and operand textures)
    // are their colours as reflectances, made once (pbrt-v4 instantiates a spectrum texture
    // per use, reading an operand's spectrum as an albedo or an unbounded spectrum).
    int reflectanceTexture(int index) const;
    // Whether a combination's operands have spectra (Texture::spectral).
    bool hasSpectra(const rayproc::Texture& t) const;
    rayproc::Texture imageTexture(const std::string& name, const ParamList& params,
                                  bool isFloat, const SourceLoc& loc, bool& missing) const;
    rayproc::Texture noiseTexture(const std::string& className, const ParamList& params,
                                  const SourceLoc& loc) const;
    rayproc::Texture combination(const std::string& className, const ParamList& params,
                                 bool isFloat, const SourceLoc& loc,
                                 const Mat4& worldFromTexture) const;
    Vec3 convert(const Param& p, SpectrumUse use, Vec3 def) const {
        return convert(p, use, def, *m_colorSpace);
    }
    Vec3 convert(const Param& p, SpectrumUse use, Vec3 def, const spectral::ColorSpace& cs) const;
    Vec3 convertConstant(const Texture& t, SpectrumUse use, Vec3 def) const {
        return t.hasValue ? convert(t.value, use, def, *t.colorSpace) : Vec3(1.0f);
    }
    const Texture* texture(const Param& ref, bool wantFloat) const;
    static EmissionSpectrumRef emissionSpectrum(const Param& p, const spectral::ColorSpace& cs);
    // reflectance() and unbounded(): the colour and the constant's own spectrum.
    ColorParam keptSpectrum(const ParamList& params, std::string_view name, SpectrumUse use,
                            Vec3 def, ReflectanceSpectrumRef& spectrum) const;
    static ReflectanceSpectrumRef ownSpectrum(const Param& p, SpectrumUse use,
                                              const spectral::ColorSpace& cs);

    Warnings& m_warnings;
    std::unordered_map<std::string, Texture> m_floatTextures;
    std::unordered_map<std::string, Texture> m_spectrumTextures;
    std::vector<rayproc::Texture>* m_table = nullptr;
    mutable std::unordered_map<int, int> m_reflectanceCopies; // reflectanceTexture's
    std::filesystem::path m_dir;
    const spectral::ColorSpace* m_colorSpace = &spectral::colorSpace(spectral::ColorSpaceId::Srgb);
};

} // namespace rayproc::pbrt
