#include "scene/pbrt/pbrt_values.h"

#include "scene/pbrt/pbrt_spectrum.h"

namespace rayproc::pbrt {

void ValueReader::defineTexture(const std::string& name, const std::string& type,
                                const std::string& className, const ParamList& params,
                                const SourceLoc& loc) {
    Texture t;
    t.isFloat = type == "float";
    t.className = className;
    t.constant = className == "constant";
    if (t.constant) {
        const Param* v = t.isFloat ? params.get("value", {"float"})
                                   : params.get("value", {"rgb", "spectrum", "blackbody"});
        if (v) {
            t.value = *v;
            t.hasValue = true;
        }
    } else {
        m_warnings.add(loc, "Texture class \"" + className +
                                "\" is not supported; parameters that use such a texture get "
                                "their default value");
        for (const Param& p : params.all()) p.used = true; // reported once, as the class
    }
    auto& table = t.isFloat ? m_floatTextures : m_spectrumTextures;
    if (table.count(name))
        m_warnings.add(loc, "texture \"" + name +
                                "\" redefined; the last "
                                "definition is used");
    table[name] = std::move(t);
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
    if (p.type == "spectrum" && p.numbers.size() == 1) {
        out = Vec3(float(p.numbers[0]));
        return true;
    }
    if (p.type == "float" && p.numbers.size() == 1) {
        out = Vec3(float(p.numbers[0]));
        return true;
    }
    return false;
}

Vec3 ValueReader::convert(const Param& p, SpectrumUse use, Vec3 def) const {
    if (p.size() != 1 && !(p.type == "spectrum" && !p.numbers.empty()))
        failAt(p.loc,
               "parameter " + p.decl() + " expects one value, got " + std::to_string(p.size()));
    Vec3 c = def;
    if (p.type == "rgb" || p.type == "float") {
        plainColor(p, c);
    } else if (p.type == "blackbody") {
        if (!(p.numbers[0] > 0))
            failAt(p.loc, "parameter " + p.decl() + " needs a positive temperature in kelvin");
        c = blackbodyRgb(p.numbers[0]);
    } else if (!p.numbers.empty()) { // spectrum: a constant, or (wavelength, value) pairs
        if (p.numbers.size() == 1) {
            c = Vec3(float(p.numbers[0]));
        } else if (p.numbers.size() % 2 != 0) {
            failAt(p.loc, "parameter " + p.decl() +
                              " expects one constant or (wavelength, value) pairs, got an odd "
                              "count");
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
        if (name == "stdillum-D65" && use == SpectrumUse::Illuminant) {
            c = Vec3(1.0f); // sRGB's white point
        } else if (name == "stdillum-A" && use == SpectrumUse::Illuminant) {
            c = blackbodyRgb(2856.0); // CIE illuminant A is a 2856 K blackbody
        } else if (namedGlassIor(name, ior) && use == SpectrumUse::Unbounded) {
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
    return t->hasValue ? convert(t->value, use, def) : Vec3(1.0f);
}

float ValueReader::scalar(const ParamList& params, std::string_view name, float def) const {
    const Param* p = params.get(name, {"float", "texture"});
    if (!p) return def;
    if (p->size() != 1)
        failAt(p->loc,
               "parameter " + p->decl() + " expects one value, got " + std::to_string(p->size()));
    if (p->type == "float") return float(p->numbers[0]);
    const Texture* t = texture(*p, true);
    if (!t->constant) return def;
    return t->hasValue ? float(t->value.numbers[0]) : 1.0f;
}

} // namespace rayproc::pbrt
