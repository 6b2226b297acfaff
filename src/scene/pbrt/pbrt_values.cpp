#include "scene/pbrt/pbrt_values.h"

#include "scene/ior_spectrum.h"
#include "scene/pbrt/pbrt_spectrum.h"
#include "image/image.h"
#include "texture/texture_image.h"

#include <cstdlib>
#include <sstream>

namespace rayproc::pbrt {

namespace {

TextureWrap parseWrap(const std::string& w, const SourceLoc& loc) {
    if (w == "repeat") return TextureWrap::Repeat;
    if (w == "black") return TextureWrap::Black;
    if (w == "clamp") return TextureWrap::Clamp;
    if (w == "octahedralsphere") return TextureWrap::Octahedral;
    failAt(loc, "unknown texture wrap mode \"" + w +
                    "\" (expected repeat, black, clamp or octahedralsphere)");
}

TextureFilter parseFilter(const std::string& f, const SourceLoc& loc) {
    if (f == "point") return TextureFilter::Point;
    if (f == "bilinear") return TextureFilter::Bilinear;
    if (f == "trilinear") return TextureFilter::Trilinear;
    if (f == "ewa" || f == "EWA") return TextureFilter::Ewa;
    failAt(loc, "unknown texture filter \"" + f + "\" (expected point, bilinear, trilinear or ewa)");
}

TextureEncoding parseEncoding(const std::string& e, const SourceLoc& loc) {
    if (e == "sRGB" || e == "srgb") return {TextureEncoding::Kind::Srgb};
    if (e == "linear") return {TextureEncoding::Kind::Linear};
    if (e.rfind("gamma ", 0) == 0) {
        char* end = nullptr;
        float g = std::strtof(e.c_str() + 6, &end);
        if (end != e.c_str() + 6 && g > 0) return {TextureEncoding::Kind::Gamma, g};
    }
    failAt(loc, "unknown encoding \"" + e + "\" (expected sRGB, linear or \"gamma <value>\")");
}

} // namespace

// pbrt-v4's noise textures of the point (ValueReader::noiseTexture).
static bool isNoise(const std::string& className) {
    return className == "fbm" || className == "wrinkled" || className == "windy" ||
           className == "marble";
}

// pbrt-v4's 2D mapping ("mapping" and its own parameters, as pbrt-v4's TextureMapping2D reads
// them), shared by image maps, 2D checkerboards, bilerp and dots. An unknown name warns and is
// uv.
static void readMapping(const ParamList& params, rayproc::Texture& t, Warnings& warnings,
                        const SourceLoc& loc) {
    std::string mapping = params.getString("mapping", "uv");
    if (mapping == "spherical") {
        t.mapping = TextureMapping::Spherical;
    } else if (mapping == "cylindrical") {
        t.mapping = TextureMapping::Cylindrical;
    } else if (mapping == "planar") {
        t.mapping = TextureMapping::Planar;
        t.planarS = params.getVector3("v1", Vec3(1.0f, 0.0f, 0.0f));
        t.planarT = params.getVector3("v2", Vec3(0.0f, 1.0f, 0.0f));
        t.du = float(params.getFloat("udelta", 0.0));
        t.dv = float(params.getFloat("vdelta", 0.0));
    } else {
        if (mapping != "uv")
            warnings.add(loc, "texture mapping \"" + mapping +
                                  "\" is not one of pbrt-v4's (uv, spherical, cylindrical, "
                                  "planar); using \"uv\"");
        t.su = float(params.getFloat("uscale", 1.0));
        t.sv = float(params.getFloat("vscale", 1.0));
        t.du = float(params.getFloat("udelta", 0.0));
        t.dv = float(params.getFloat("vdelta", 0.0));
    }
}

rayproc::Texture ValueReader::imageTexture(const std::string& name, const ParamList& params,
                                           bool isFloat, const SourceLoc& loc,
                                           bool& missing) const {
    rayproc::Texture t;
    t.type = TextureType::Image;
    readMapping(params, t, m_warnings, loc);
    t.filter = parseFilter(params.getString("filter", "bilinear"), loc);
    t.wrap = parseWrap(params.getString("wrap", "repeat"), loc);
    t.scale = float(params.getFloat("scale", 1.0));
    t.invert = params.getBool("invert", false);
    params.ignore({"maxanisotropy"});
    TextureEncoding encoding = parseEncoding(params.getString("encoding", "sRGB"), loc);
    std::string file = params.getString("filename", "");
    if (file.empty()) failAt(loc, "Texture \"" + name + "\" (imagemap) needs \"string filename\"");
    std::filesystem::path path(file);
    if (path.is_relative()) path = m_dir / path;
    t.filename = path.string();
    missing = false;
    try {
        t.image = loadTextureImage(t.filename, encoding);
    } catch (const ImageIoError& e) {
        // A missing or unreadable file warns and leaves the parameters that use the texture at
        // their defaults (the shared scenes lack two texture files).
        m_warnings.add(loc, std::string(e.what()) + "; parameters that use texture \"" + name +
                                "\" keep their default values");
        missing = true;
    }
    return t;
}

int ValueReader::normalMapTexture(const std::string& file, const SourceLoc& loc) const {
    if (!m_table) return -1;
    rayproc::Texture t;
    t.type = TextureType::Image;
    t.name = "normalmap " + file;
    t.filter = TextureFilter::Bilinear;
    t.wrap = TextureWrap::Repeat;
    std::filesystem::path path(file);
    if (path.is_relative()) path = m_dir / path;
    t.filename = path.string();
    try {
        t.image = loadTextureImage(t.filename, parseEncoding("linear", loc));
    } catch (const ImageIoError& e) {
        m_warnings.add(loc, std::string(e.what()) + "; the material keeps its own normals");
        return -1;
    }
    m_table->push_back(std::move(t));
    return int(m_table->size()) - 1;
}

void ValueReader::operand(const ParamList& params, std::string_view name, bool isFloat, Vec3 def,
                          int& index, Vec3& value, OperandSpectrum* spectrum) const {
    index = -1;
    value = def;
    const Param* p = params.find(name);
    if (!p) return;
    if (p->type == "texture") {
        p->used = true;
        const Texture* t = texture(*p, isFloat);
        if (t->constant) {
            value = convertConstant(*t, SpectrumUse::Unbounded, def);
            if (spectrum && t->hasValue) *spectrum = operandSpectrum(t->value, *t->colorSpace);
        } else if (!t->missing) {
            index = t->index;
        }
        return;
    }
    if (isFloat) {
        value = Vec3(scalar(params, name, def.x));
        return;
    }
    value = color(params, name, SpectrumUse::Unbounded, def);
    if (spectrum) *spectrum = operandSpectrum(*p, *m_colorSpace);
}

// Called after convert() accepted the parameter: its values are valid.
OperandSpectrum ValueReader::operandSpectrum(const Param& p,
                                             const spectral::ColorSpace& cs) const {
    OperandSpectrum s;
    s.unbounded = ownSpectrum(p, SpectrumUse::Unbounded, cs);
    if (!s.unbounded) return s;
    s.albedoColour = convert(p, SpectrumUse::Albedo, Vec3(0.0f), cs);
    // Pairs are read unclamped by either use; an rgb is the albedo or the unbounded spectrum.
    s.albedo = p.type == "rgb" ? ownSpectrum(p, SpectrumUse::Albedo, cs) : s.unbounded;
    if (!s.albedo) s.albedo = s.unbounded;
    return s;
}

int ValueReader::reflectanceTexture(int index) const {
    if (index < 0 || !(*m_table)[std::size_t(index)].spectral) return index;
    if (auto it = m_reflectanceCopies.find(index); it != m_reflectanceCopies.end())
        return it->second;
    rayproc::Texture copy = (*m_table)[std::size_t(index)]; // the table grows below
    auto asReflectance = [](Vec3& value, const OperandSpectrum& s) {
        if (s) value = s.albedoColour;
    };
    asReflectance(copy.aValue, copy.aSpectrum);
    asReflectance(copy.bValue, copy.bSpectrum);
    for (std::size_t k = 0; k < copy.corners.size(); ++k)
        asReflectance(copy.corners[k], copy.cornerSpectra[k]);
    copy.a = reflectanceTexture(copy.a);
    if (copy.type != TextureType::Scale) copy.b = reflectanceTexture(copy.b); // "scale": a float
    copy.name += " (as a reflectance)";
    m_table->push_back(std::move(copy));
    const int made = int(m_table->size()) - 1;
    m_reflectanceCopies[index] = made;
    return made;
}

bool ValueReader::hasSpectra(const rayproc::Texture& t) const {
    auto spectralTexture = [this](int index) {
        return index >= 0 && (*m_table)[std::size_t(index)].spectral;
    };
    bool any = bool(t.aSpectrum) || bool(t.bSpectrum) || spectralTexture(t.a);
    // Scale's second operand is a float ("scale"), never spectral.
    if (t.type != TextureType::Scale) any = any || spectralTexture(t.b);
    for (const OperandSpectrum& c : t.cornerSpectra) any = any || bool(c);
    return any;
}

// A texture that combines others or values ("scale", "mix", "directionmix", "checkerboard",
// "bilerp"), as pbrt-v4 defines each (operands' defaults included).
rayproc::Texture ValueReader::combination(const std::string& className, const ParamList& params,
                                          bool isFloat, const SourceLoc& loc,
                                          const Mat4& worldFromTexture) const {
    rayproc::Texture rt;
    const Vec3 one(1.0f), zero(0.0f);
    auto spectra = [isFloat](OperandSpectrum& s) { return isFloat ? nullptr : &s; };
    if (className == "scale") {
        rt.type = TextureType::Scale;
        operand(params, "tex", isFloat, one, rt.a, rt.aValue, spectra(rt.aSpectrum));
        operand(params, "scale", true, one, rt.b, rt.bValue);
    } else if (className == "mix" || className == "directionmix") {
        rt.type = className == "mix" ? TextureType::Mix : TextureType::DirectionMix;
        operand(params, "tex1", isFloat, zero, rt.a, rt.aValue, spectra(rt.aSpectrum));
        operand(params, "tex2", isFloat, one, rt.b, rt.bValue, spectra(rt.bSpectrum));
        if (rt.type == TextureType::Mix) {
            Vec3 amount;
            operand(params, "amount", true, Vec3(0.5f), rt.amountTexture, amount);
            rt.amount = amount.x;
        } else {
            const Vec3 dir = params.getVector3("dir", Vec3(0.0f, 1.0f, 0.0f));
            rt.direction = normalize(worldFromTexture.toAffine().vector(dir));
            if (!(lengthSquared(rt.direction) > 0) || !isFinite(rt.direction))
                failAt(loc, "directionmix's \"dir\" must be a non-zero direction");
        }
    } else if (className == "dots") {
        readMapping(params, rt, m_warnings, loc);
        rt.type = TextureType::Dots;
        operand(params, "inside", isFloat, one, rt.a, rt.aValue, spectra(rt.aSpectrum));
        operand(params, "outside", isFloat, zero, rt.b, rt.bValue, spectra(rt.bSpectrum));
    } else if (className == "bilerp") {
        readMapping(params, rt, m_warnings, loc);
        rt.type = TextureType::Bilerp;
        const char* names[4] = {"v00", "v10", "v01", "v11"};
        const float defaults[4] = {0, 0, 1, 1};
        for (std::size_t k = 0; k < 4; ++k) {
            if (isFloat) {
                rt.corners[k] = Vec3(scalar(params, names[k], defaults[k]));
                continue;
            }
            rt.corners[k] = color(params, names[k], SpectrumUse::Unbounded, Vec3(defaults[k]));
            if (const Param* p = params.find(names[k]))
                rt.cornerSpectra[k] = operandSpectrum(*p, *m_colorSpace);
        }
    } else {
        rt.type = TextureType::Checkerboard;
        const long long dimension = params.getInt("dimension", 2);
        if (dimension == 3) rt.mapping = TextureMapping::Point;
        else if (dimension == 2) readMapping(params, rt, m_warnings, loc);
        else failAt(loc, "checkerboard's \"dimension\" must be 2 or 3");
        operand(params, "tex1", isFloat, one, rt.a, rt.aValue, spectra(rt.aSpectrum));
        operand(params, "tex2", isFloat, zero, rt.b, rt.bValue, spectra(rt.bSpectrum));
    }
    rt.spectral = hasSpectra(rt);
    return rt;
}

// pbrt-v4's noise textures of the point ("fbm", "wrinkled", "windy", "marble"), with its
// parameters and defaults (texture/noise.h).
rayproc::Texture ValueReader::noiseTexture(const std::string& className, const ParamList& params,
                                           const SourceLoc& loc) const {
    rayproc::Texture rt;
    rt.mapping = TextureMapping::Point;
    rt.type = className == "fbm"        ? TextureType::Fbm
              : className == "wrinkled" ? TextureType::Wrinkled
              : className == "windy"    ? TextureType::Windy
                                        : TextureType::Marble;
    if (rt.type == TextureType::Windy) return rt; // pbrt-v4's has no parameters
    const long long octaves = params.getInt("octaves", 8);
    if (octaves < 0 || octaves > 64)
        failAt(loc, className + "'s \"octaves\" must be from 0 to 64, got " +
                        std::to_string(octaves));
    rt.octaves = int(octaves);
    rt.omega = float(params.getFloat("roughness", 0.5));
    if (rt.type == TextureType::Marble) {
        rt.noiseScale = float(params.getFloat("scale", 1.0));
        rt.variation = float(params.getFloat("variation", 0.2));
    }
    return rt;
}

void ValueReader::defineTexture(const std::string& name, const std::string& type,
                                const std::string& className, const ParamList& params,
                                const SourceLoc& loc, const Mat4& worldFromTexture) {
    Texture t;
    t.isFloat = type == "float";
    t.className = className;
    t.constant = className == "constant";
    t.colorSpace = m_colorSpace;
    if (t.constant) {
        const Param* v = t.isFloat ? params.get("value", {"float"})
                                   : params.get("value", {"rgb", "spectrum", "blackbody"});
        if (v) {
            t.value = *v;
            t.hasValue = true;
        }
    } else if (m_table && (className == "imagemap" || className == "scale" ||
                           className == "mix" || className == "directionmix" ||
                           className == "checkerboard" || className == "bilerp" ||
                           className == "dots" || isNoise(className))) {
        rayproc::Texture rt = className == "imagemap"
                                  ? imageTexture(name, params, t.isFloat, loc, t.missing)
                              : isNoise(className)
                                  ? noiseTexture(className, params, loc)
                                  : combination(className, params, t.isFloat, loc,
                                                worldFromTexture);
        rt.name = name;
        rt.isFloat = t.isFloat;
        if (rt.mapping != TextureMapping::Uv) {
            Mat4 inverse;
            if (!worldFromTexture.inverse(inverse))
                failAt(loc, "Texture \"" + name + "\": the transform has no inverse, which its "
                            "mapping needs");
            rt.textureFromWorld = inverse.toAffine();
        }
        if (!t.missing) {
            m_table->push_back(std::move(rt));
            t.index = int(m_table->size()) - 1;
        }
    } else {
        m_warnings.add(loc, "Texture class \"" + className +
                                "\" is not supported; parameters that use such a texture get "
                                "their default value");
        for (const Param& p : params.all()) p.used = true; // reported once, as the class
        t.missing = true;
    }
    auto& table = t.isFloat ? m_floatTextures : m_spectrumTextures;
    if (table.count(name))
        m_warnings.add(loc, "texture \"" + name +
                                "\" redefined; the last "
                                "definition is used");
    table[name] = std::move(t);
}

ColorParam ValueReader::colorParam(const ParamList& params, std::string_view name,
                                   SpectrumUse use, Vec3 def) const {
    ColorParam c;
    c.value = def;
    const Param* p = params.get(name, {"rgb", "spectrum", "blackbody", "texture"});
    if (!p) return c;
    if (p->type != "texture") {
        c.value = convert(*p, use, def);
        return c;
    }
    const Texture* t = texture(*p, false);
    if (t->constant)
        c.value = convertConstant(*t, use, def);
    else if (!t->missing)
        c.texture = use == SpectrumUse::Albedo ? reflectanceTexture(t->index) : t->index;
    return c;
}

FloatParam ValueReader::floatParam(const ParamList& params, std::string_view name,
                                   float def) const {
    FloatParam f;
    f.value = def;
    const Param* p = params.get(name, {"float", "texture"});
    if (!p) return f;
    if (p->type != "texture") {
        f.value = scalar(params, name, def);
        return f;
    }
    const Texture* t = texture(*p, true);
    if (t->constant)
        f.value = t->hasValue ? float(t->value.numbers[0]) : 1.0f;
    else if (!t->missing)
        f.texture = t->index;
    return f;
}

const ValueReader::Texture* ValueReader::texture(const Param& ref, bool wantFloat) const {
    if (ref.strings.size() != 1)
        failAt(ref.loc, "parameter " + ref.decl() + " expects one texture name");
    const auto& table = wantFloat ? m_floatTextures : m_spectrumTextures;
    auto it = table.find(ref.strings[0]);
    if (it == table.end())
        failAt(ref.loc, std::string("no ") + (wantFloat ? "float" : "spectrum") +
                            " texture named \"" + ref.strings[0] + "\"");
    return &it->second;
}

bool ValueReader::plainColor(const Param& p, Vec3& out) {
    if (p.type == "rgb" && p.numbers.size() == 3) {
        out = {float(p.numbers[0]), float(p.numbers[1]), float(p.numbers[2])};
        return true;
    }
    if (p.type == "float" && p.numbers.size() == 1) {
        out = Vec3(float(p.numbers[0]));
        return true;
    }
    return false;
}

Vec3 ValueReader::convert(const Param& p, SpectrumUse use, Vec3 def,
                          const spectral::ColorSpace& cs) const {
    if (p.size() != 1 && !(p.type == "spectrum" && !p.numbers.empty()))
        failAt(p.loc,
               "parameter " + p.decl() + " expects one value, got " + std::to_string(p.size()));
    Vec3 c = def;
    if (p.type == "rgb") {
        plainColor(p, c);
        // Checked as written, before a colour space's conversion can move it.
        if (!isFinite(c) || c.x < 0 || c.y < 0 || c.z < 0)
            failAt(p.loc, "parameter " + p.decl() + " must not be negative");
        if (use == SpectrumUse::Albedo && maxComponent(c) > 1)
            failAt(p.loc, "parameter " + p.decl() + " is a reflectance and must not exceed 1");
        c = use == SpectrumUse::Albedo     ? rgbAlbedoToSrgb(c, cs)
            : use == SpectrumUse::Unbounded ? rgbUnboundedToSrgb(c, cs)
                                            : rgbIlluminantToSrgb(c, cs);
    } else if (p.type == "float") {
        plainColor(p, c);
    } else if (p.type == "blackbody") {
        if (!(p.numbers[0] > 0))
            failAt(p.loc, "parameter " + p.decl() + " needs a positive temperature in kelvin");
        c = blackbodyRgb(p.numbers[0]);
    } else if (!p.numbers.empty()) { // spectrum: (wavelength, value) pairs
        // As pbrt-v4 (ParameterDictionary): no constant spectrum, one number is an odd count.
        if (p.numbers.size() % 2 != 0) {
            failAt(p.loc, "parameter " + p.decl() + " expects (wavelength, value) pairs, got " +
                              std::to_string(p.numbers.size()) +
                              (p.numbers.size() == 1 ? " value (pbrt-v4 has no constant "
                                                       "spectrum: write \"float\" or \"rgb\")"
                                                     : " values, an odd count"));
        } else if (use == SpectrumUse::Illuminant) {
            c = sampledEmissionRgb(p.numbers);
        } else if (use == SpectrumUse::Albedo) {
            c = sampledReflectanceRgb(p.numbers);
        } else {
            c = Vec3(float(sampledValueAt(p.numbers, 587.6)));
        }
    } else { // a named spectrum
        const std::string& name = p.strings[0];
        double ior = 0;
        if (use == SpectrumUse::Illuminant && namedIlluminantRgb(name, c)) {
            // the tabulated CIE illuminant's colour, luminance 1
        } else if (namedGlassIndex(name, ior) && use == SpectrumUse::Unbounded) {
            c = Vec3(float(ior));
        } else {
            m_warnings.add(p.loc, "named spectrum \"" + name +
                                      "\" is not supported here; using the default value");
        }
    }
    if (!isFinite(c) || c.x < 0 || c.y < 0 || c.z < 0)
        failAt(p.loc, "parameter " + p.decl() + " must not be negative");
    if (use == SpectrumUse::Albedo && maxComponent(c) > 1)
        failAt(p.loc, "parameter " + p.decl() + " is a reflectance and must not exceed 1");
    return c;
}

Vec3 ValueReader::color(const ParamList& params, std::string_view name, SpectrumUse use,
                        Vec3 def) const {
    const Param* p = params.get(name, {"rgb", "spectrum", "blackbody", "texture"});
    if (!p) return def;
    if (p->type != "texture") return convert(*p, use, def);
    const Texture* t = texture(*p, false);
    if (!t->constant) return def;
    return convertConstant(*t, use, def);
}

Vec3 ValueReader::emission(const ParamList& params, std::string_view name, Vec3 def,
                           EmissionSpectrumRef& spectrum) const {
    spectrum = nullptr;
    Vec3 c = color(params, name, SpectrumUse::Illuminant, def);
    const Param* p = params.get(name, {"rgb", "spectrum", "blackbody", "texture"});
    if (!p) return c;
    if (p->type != "texture") {
        spectrum = emissionSpectrum(*p, *m_colorSpace);
    } else {
        const Texture* t = texture(*p, false);
        if (t->constant && t->hasValue) spectrum = emissionSpectrum(t->value, *t->colorSpace);
    }
    return c;
}

// Called after convert() accepted the parameter: its values are valid.
EmissionSpectrumRef ValueReader::emissionSpectrum(const Param& p, const spectral::ColorSpace& cs) {
    if (p.type == "blackbody") return blackbodyEmission(p.numbers[0]);
    if (p.type == "rgb") {
        Vec3 rgb;
        return plainColor(p, rgb) ? rgbIlluminantEmission(rgb, cs) : nullptr;
    }
    if (p.type != "spectrum") return nullptr;
    if (p.numbers.size() >= 2) return sampledEmission(p.numbers);
    if (p.numbers.empty() && p.strings.size() == 1) return namedIlluminantEmission(p.strings[0]);
    return nullptr;
}

ColorParam ValueReader::reflectance(const ParamList& params, std::string_view name, Vec3 def,
                                    ReflectanceSpectrumRef& spectrum) const {
    return keptSpectrum(params, name, SpectrumUse::Albedo, def, spectrum);
}

ColorParam ValueReader::unbounded(const ParamList& params, std::string_view name, Vec3 def,
                                  ReflectanceSpectrumRef& spectrum) const {
    return keptSpectrum(params, name, SpectrumUse::Unbounded, def, spectrum);
}

ColorParam ValueReader::keptSpectrum(const ParamList& params, std::string_view name,
                                     SpectrumUse use, Vec3 def,
                                     ReflectanceSpectrumRef& spectrum) const {
    spectrum = nullptr;
    ColorParam c = colorParam(params, name, use, def);
    const Param* p = params.get(name, {"rgb", "spectrum", "blackbody", "texture"});
    if (!p || c.textured()) return c;
    if (p->type != "texture") {
        spectrum = ownSpectrum(*p, use, *m_colorSpace);
    } else {
        const Texture* t = texture(*p, false);
        if (t->constant && t->hasValue) spectrum = ownSpectrum(t->value, use, *t->colorSpace);
    }
    return c;
}

// Called after convert() accepted the parameter: its values are valid.
ReflectanceSpectrumRef ValueReader::ownSpectrum(const Param& p, SpectrumUse use,
                                                const spectral::ColorSpace& cs) {
    const bool albedo = use == SpectrumUse::Albedo;
    Vec3 rgb;
    if (p.type == "rgb") {
        if (!plainColor(p, rgb)) return nullptr;
        return albedo ? rgbAlbedoReflectance(rgb, cs) : rgbUnboundedValues(rgb, cs);
    }
    if (p.type == "spectrum" && p.numbers.size() >= 2)
        return albedo ? sampledReflectance(p.numbers) : sampledUnbounded(p.numbers);
    return nullptr; // a blackbody or a named spectrum: its colour (convert's) is all there is
}

float ValueReader::scalar(const ParamList& params, std::string_view name, float def) const {
    const Param* p = params.get(name, {"float", "texture"});
    if (!p) return def;
    if (p->size() != 1)
        failAt(p->loc,
               "parameter " + p->decl() + " expects one value, got " + std::to_string(p->size()));
    if (p->type == "float") return float(p->numbers[0]);
    const Texture* t = texture(*p, true);
    if (!t->constant) {
        // Where pbrt-v4 takes no texture (a dielectric's eta, a layer's g, ...), a varying one
        // cannot be honoured; a missing file has warned already.
        if (!t->missing) {
            std::ostringstream text;
            text << "parameter " << p->decl() << ": a texture that varies over the surface is "
                 << "not supported here; using the default " << def;
            m_warnings.add(p->loc, text.str());
        }
        return def;
    }
    return t->hasValue ? float(t->value.numbers[0]) : 1.0f;
}

} // namespace rayproc::pbrt
