// Scene loading: the flat sections of a scene file (camera, render settings, materials,
// lights). Each key is optional unless noted; the defaults are those of scene.h.
#include "core/error.h"
#include "image/image.h"
#include "scene/camera_check.h"
#include "scene/ior_spectrum.h"
#include "scene/metals.h"
#include "scene/pbrt/pbrt_spectrum.h"
#include "scene/scene_loader_detail.h"
#include "texture/texture_image.h"

#include <nlohmann/json.hpp>

#include <climits>
#include <filesystem>

namespace rayproc::scene_json {

namespace {

float nonNegative(const JsonRef& v) {
    float x = v.number();
    if (x < 0) v.fail("must not be negative");
    return x;
}

// "filter": {"type": "box" | "triangle" | "gaussian" | "mitchell" | "lanczos", "radius": r or
// [rx, ry], "sigma", "b", "c", "tau"}; absent keys take scene.h's defaults (box of radius 0.5).
PixelFilter parseFilter(const JsonRef& v) {
    v.expectObject({"type", "radius", "sigma", "b", "c", "tau"}, "the camera's filter");
    PixelFilter f;
    if (v.has("type")) {
        std::string t = v["type"].string();
        struct Named {
            const char* name;
            PixelFilter::Type type;
        };
        using T = PixelFilter::Type;
        static const Named kTypes[] = {{"box", T::Box},
                                       {"triangle", T::Triangle},
                                       {"gaussian", T::Gaussian},
                                       {"mitchell", T::Mitchell},
                                       {"lanczos", T::Lanczos}};
        const Named* found = nullptr;
        for (const Named& k : kTypes)
            if (t == k.name) found = &k;
        if (!found)
            v["type"].fail("unknown filter \"" + t +
                           "\" (box, triangle, gaussian, mitchell, lanczos)");
        f.type = found->type;
    }
    if (v.has("radius")) {
        JsonRef r = v["radius"];
        if (r.isArray()) {
            if (r.arraySize() != 2) r.fail("expected a number or an array of 2 numbers [rx, ry]");
            f.radius = {r[std::size_t(0)].numberIn(1e-3f, 16.0f), r[1].numberIn(1e-3f, 16.0f)};
        } else {
            float x = r.numberIn(1e-3f, 16.0f);
            f.radius = {x, x};
        }
    }
    if (v.has("sigma")) f.sigma = v["sigma"].positive();
    if (v.has("b")) f.b = v["b"].number();
    if (v.has("c")) f.c = v["c"].number();
    if (v.has("tau")) f.tau = v["tau"].positive();
    return f;
}

} // namespace

Camera parseCamera(const JsonRef& v) {
    v.expectObject(
        {"position", "look_at", "up", "fov", "resolution", "aperture", "focus_distance", "filter"},
        "the camera");
    Camera c;
    if (v.has("position")) c.position = v["position"].vec3();
    if (v.has("look_at")) c.lookAt = v["look_at"].vec3();
    if (v.has("up")) c.up = v["up"].direction();
    if (v.has("fov")) {
        c.fovY = v["fov"].number();
        if (c.fovY <= 0 || c.fovY >= 180)
            v["fov"].fail("field of view must lie strictly between 0 and 180 degrees");
    }
    if (v.has("resolution")) {
        JsonRef r = v["resolution"];
        if (!r.isArray() || r.arraySize() != 2)
            r.fail("expected an array of 2 integers [width, height]");
        long long w = r[std::size_t(0)].integer(1, kMaxImageSide);
        long long h = r[1].integer(1, kMaxImageSide);
        if (w * h > kMaxImagePixels) {
            r.fail("image too large: " + std::to_string(w) + " x " + std::to_string(h) +
                   " pixels exceeds the limit of " + std::to_string(kMaxImagePixels) +
                   " (2^26) pixels");
        }
        c.width = int(w);
        c.height = int(h);
    }
    if (v.has("aperture")) c.apertureRadius = nonNegative(v["aperture"]);
    if (v.has("focus_distance")) c.focusDistance = nonNegative(v["focus_distance"]);
    if (v.has("filter")) c.filter = parseFilter(v["filter"]);

    // What serve's camera message and EmbreeScene check too: a view, an up not parallel to
    // it, a position and lens within Embree's range.
    if (auto problem = cameraProblem(c)) {
        if (problem->field == "up" && !v.has("up"))
            v.child("up").fail("the default up [0, 1, 0] is parallel to the view direction; "
                               "give \"up\"");
        v.child(problem->field).fail(problem->message);
    }
    return c;
}

SceneRenderSettings parseRenderSettings(const JsonRef& v) {
    v.expectObject({"mode", "spp", "max_depth", "light_samples", "seed", "spectral"},
                   "the render settings");
    SceneRenderSettings s;
    if (v.has("mode")) s.mode = v["mode"].nonEmptyString(); // the CLI checks the name
    if (v.has("spp")) s.spp = int(v["spp"].integer(1, 1000000));
    if (v.has("max_depth")) s.maxDepth = int(v["max_depth"].integer(1, 10000));
    if (v.has("light_samples")) s.lightSamples = int(v["light_samples"].integer(1, 65536));
    if (v.has("seed")) s.seed = v["seed"].integer(0, LLONG_MAX);
    if (v.has("spectral")) s.spectral = v["spectral"].boolean();
    return s;
}

namespace {

// The index of the texture named by the string `v`, or a JSON-path error.
int textureNamed(const JsonRef& v, const Scene& scene) {
    std::string name = v.nonEmptyString();
    for (std::size_t i = 0; i < scene.textures.size(); ++i)
        if (scene.textures[i].name == name) return int(i);
    v.fail("unknown texture \"" + name + "\"");
}

// A colour that may be a texture's name; `albedo`: components in [0, 1].
ColorParam colorParam(const JsonRef& v, const Scene& scene, bool albedo) {
    ColorParam c;
    if (v.isString()) c.texture = textureNamed(v, scene);
    else c.value = albedo ? v.albedo() : v.color();
    return c;
}

// A texture operand: a colour, a number (grey) or a texture's name.
void textureOperand(const JsonRef& v, const Scene& scene, int& index, Vec3& value) {
    if (v.isString()) index = textureNamed(v, scene);
    else if (v.isNumber()) value = Vec3(v.number());
    else value = v.color();
}

// The texture coordinates' scale (uscale, vscale) and offset (udelta, vdelta).
void parseUvMapping(const JsonRef& t, Texture& tex) {
    if (t.has("uscale")) tex.su = t["uscale"].number();
    if (t.has("vscale")) tex.sv = t["vscale"].number();
    if (t.has("udelta")) tex.du = t["udelta"].number();
    if (t.has("vdelta")) tex.dv = t["vdelta"].number();
}

// An image texture: its file relative to the scene file, its filter, wrap and encoding.
void parseImageTexture(const JsonRef& t, Texture& tex) {
    t.expectObject({"type", "file", "uscale", "vscale", "udelta", "vdelta", "filter", "wrap",
                    "encoding", "scale", "invert"},
                   "an image texture");
    tex.type = TextureType::Image;
    parseUvMapping(t, tex);
    if (t.has("scale")) tex.scale = t["scale"].number();
    if (t.has("invert")) tex.invert = t["invert"].boolean();
    if (t.has("filter")) {
        std::string f = t["filter"].string();
        if (f == "point") tex.filter = TextureFilter::Point;
        else if (f == "bilinear") tex.filter = TextureFilter::Bilinear;
        else if (f == "trilinear") tex.filter = TextureFilter::Trilinear;
        else t["filter"].fail("expected \"point\", \"bilinear\" or \"trilinear\"");
    }
    if (t.has("wrap")) {
        std::string w = t["wrap"].string();
        if (w == "repeat") tex.wrap = TextureWrap::Repeat;
        else if (w == "clamp") tex.wrap = TextureWrap::Clamp;
        else if (w == "black") tex.wrap = TextureWrap::Black;
        else t["wrap"].fail("expected \"repeat\", \"clamp\" or \"black\"");
    }
    TextureEncoding encoding;
    if (t.has("encoding")) {
        std::string e = t["encoding"].string();
        if (e == "linear") encoding.kind = TextureEncoding::Kind::Linear;
        else if (e != "srgb") t["encoding"].fail("expected \"srgb\" or \"linear\"");
    }
    JsonRef file = t["file"];
    std::filesystem::path p(file.nonEmptyString());
    if (p.is_relative()) p = std::filesystem::path(t.file()).parent_path() / p;
    tex.filename = p.string();
    try {
        tex.image = loadTextureImage(tex.filename, encoding);
    } catch (const ImageIoError& e) {
        file.fail(e.what());
    }
}

} // namespace

// "textures": named textures, each defined before the ones that use it (so no cycles).
void parseTextures(const JsonRef& v, Scene& scene) {
    if (!v.isObject()) v.fail("expected an object mapping texture names to textures");
    static const std::vector<std::string> kTypes = {"image", "constant", "scale", "mix",
                                                    "checkerboard"};
    for (const std::string& name : v.keys()) {
        JsonRef t = v[name];
        if (name.empty()) t.fail("texture name must not be empty");
        std::string type = parseType(t, "texture", kTypes);
        Texture tex;
        tex.name = name;
        if (type == "image") {
            parseImageTexture(t, tex);
        } else if (type == "constant") {
            t.expectObject({"type", "value"}, "a constant texture");
            tex.value = t["value"].color();
        } else if (type == "scale") {
            t.expectObject({"type", "tex", "scale"}, "a scale texture");
            tex.type = TextureType::Scale;
            if (t.has("tex")) textureOperand(t["tex"], scene, tex.a, tex.aValue);
            if (t.has("scale")) textureOperand(t["scale"], scene, tex.b, tex.bValue);
        } else if (type == "mix") {
            t.expectObject({"type", "tex1", "tex2", "amount"}, "a mix texture");
            tex.type = TextureType::Mix;
            tex.aValue = Vec3(0.0f);
            tex.bValue = Vec3(1.0f);
            if (t.has("tex1")) textureOperand(t["tex1"], scene, tex.a, tex.aValue);
            if (t.has("tex2")) textureOperand(t["tex2"], scene, tex.b, tex.bValue);
            if (t.has("amount")) {
                if (t["amount"].isString()) tex.amountTexture = textureNamed(t["amount"], scene);
                else tex.amount = t["amount"].numberIn(0, 1);
            }
        } else {
            t.expectObject({"type", "tex1", "tex2", "uscale", "vscale", "udelta", "vdelta"},
                           "a checkerboard texture");
            tex.type = TextureType::Checkerboard;
            tex.bValue = Vec3(0.0f);
            parseUvMapping(t, tex);
            if (t.has("tex1")) textureOperand(t["tex1"], scene, tex.a, tex.aValue);
            if (t.has("tex2")) textureOperand(t["tex2"], scene, tex.b, tex.bValue);
        }
        scene.textures.push_back(std::move(tex));
    }
}

namespace {

// "roughness" (both axes) or "u_roughness" / "v_roughness", and "remap_roughness" (pbrt-v4's
// remapping alpha = sqrt(r), on by default as in pbrt-v4).
void parseRoughness(const JsonRef& m, Material& mat) {
    if (m.has("roughness")) {
        mat.uRoughness.value = mat.vRoughness.value = m["roughness"].numberIn(0, 1e6f);
    }
    if (m.has("u_roughness")) mat.uRoughness.value = m["u_roughness"].numberIn(0, 1e6f);
    if (m.has("v_roughness")) mat.vRoughness.value = m["v_roughness"].numberIn(0, 1e6f);
    if (m.has("remap_roughness")) mat.remapRoughness = m["remap_roughness"].boolean();
}

// A conductor's complex index: "eta" and "k" as colours, or "metal": a name of pbrt-v4's
// measured metals ("Ag", "Al", "Au", "Cu", "CuZn", "MgO", "TiO2"), or "reflectance".
void parseConductorIndex(const JsonRef& m, Material& mat) {
    if (m.has("metal")) {
        if (m.has("eta") || m.has("k") || m.has("reflectance"))
            m.fail("give \"metal\", or \"eta\" and \"k\", or \"reflectance\", not several");
        std::string metal = m["metal"].nonEmptyString();
        Vec3 eta, k;
        if (!namedMetal(metal, eta, k))
            m["metal"].fail("unknown metal \"" + metal +
                            "\" (expected one of Ag, Al, Au, Cu, CuZn, MgO, TiO2)");
        mat.eta.value = eta;
        mat.k.value = k;
    } else if (m.has("reflectance")) {
        if (m.has("eta") || m.has("k")) m.fail("give \"eta\" and \"k\", or \"reflectance\", not both");
        mat.color = m["reflectance"].albedo();
        mat.useReflectance = true;
    } else {
        if (m.has("eta")) mat.eta.value = m["eta"].color();
        if (m.has("k")) mat.k.value = m["k"].color();
    }
}

// A dielectric's, thindielectric's or coated material's (its coat's) "ior": a number; a named
// glass ("glass-BK7", ...: its catalogue n_d, and its Sellmeier dispersion for the spectral
// mode, scene/ior_spectrum.h); or [wavelength, index, ...] pairs (their value at 587.6 nm, and
// the pairs for the spectral mode where the index varies).
void parseDielectricIor(const JsonRef& m, Material& mat) {
    if (!m.has("ior")) return;
    const JsonRef v = m["ior"];
    if (v.isString()) {
        const std::string name = v.string();
        double nd = 0;
        if (!namedGlassIndex(name, nd))
            v.fail("unknown glass \"" + name + "\" (glass-BK7, glass-BAF10, glass-FK51A, "
                   "glass-LASF9, glass-F5, glass-F10, glass-F11)");
        mat.ior = float(nd);
        mat.iorSpectrum = namedGlassDispersion(name);
    } else if (v.isArray()) {
        const std::size_t n = v.arraySize();
        if (n < 2 || n % 2 != 0) v.fail("expected (wavelength, index) pairs");
        std::vector<double> pairs;
        for (std::size_t i = 0; i < n; ++i) {
            pairs.push_back(v[i].positive());
            if (i % 2 == 0 && i > 0 && !(pairs[i] > pairs[i - 2]))
                v[i].fail("wavelengths must ascend");
        }
        mat.iorSpectrum = sampledIor(pairs);
        mat.ior = mat.iorSpectrum ? mat.iorSpectrum->at(587.6f) : float(pairs[1]);
    } else {
        mat.ior = v.positive();
    }
}

// The slab between a coat and its base: "thickness", "albedo", "g", "max_depth", "samples".
void parseLayer(const JsonRef& m, Material& mat) {
    if (m.has("thickness")) mat.thickness.value = m["thickness"].positive();
    if (m.has("albedo")) mat.albedo.value = m["albedo"].albedo();
    if (m.has("g")) mat.g = m["g"].numberIn(-0.999f, 0.999f);
    if (m.has("max_depth")) mat.maxDepth = int(m["max_depth"].integer(1, 1000));
    if (m.has("samples")) mat.nSamples = int(m["samples"].integer(1, 1000));
}

void parseCoatedDiffuse(const JsonRef& m, Material& mat) {
    m.expectObject({"type", "color", "ior", "roughness", "u_roughness", "v_roughness",
                    "remap_roughness", "thickness", "albedo", "g", "max_depth", "samples", "model",
                    "displacement", "normal_map"},
                   "a coateddiffuse material");
    mat.type = MaterialType::CoatedDiffuse;
    mat.color = Vec3(0.5f);
    parseDielectricIor(m, mat);
    parseRoughness(m, mat);
    parseLayer(m, mat);
    if (m.has("model") && !coatModelNamed(m["model"].nonEmptyString(), mat.coatModel))
        m["model"].fail("expected \"auto\", \"analytic\" or \"random-walk\"");
}

// pbrt-v4's coatedconductor: the coat's "ior" and roughness keys (as coateddiffuse's), the
// conductor's index keys (as conductor's) and its "conductor_roughness" /
// "conductor_u_roughness" / "conductor_v_roughness", and the slab's keys.
void parseCoatedConductor(const JsonRef& m, Material& mat) {
    m.expectObject({"type", "ior", "roughness", "u_roughness", "v_roughness", "remap_roughness",
                    "metal", "eta", "k", "reflectance", "conductor_roughness",
                    "conductor_u_roughness", "conductor_v_roughness", "thickness", "albedo", "g",
                    "max_depth", "samples", "displacement", "normal_map"},
                   "a coatedconductor material");
    mat.type = MaterialType::CoatedConductor;
    parseDielectricIor(m, mat);
    parseRoughness(m, mat);
    parseConductorIndex(m, mat);
    if (m.has("conductor_roughness"))
        mat.conductorURoughness.value = mat.conductorVRoughness.value =
            m["conductor_roughness"].numberIn(0, 1e6f);
    if (m.has("conductor_u_roughness"))
        mat.conductorURoughness.value = m["conductor_u_roughness"].numberIn(0, 1e6f);
    if (m.has("conductor_v_roughness"))
        mat.conductorVRoughness.value = m["conductor_v_roughness"].numberIn(0, 1e6f);
    parseLayer(m, mat);
}

// One material of the given type, its keys checked against the type's. A mix's two materials
// are resolved once the whole block is read (resolveMixes).
Material parseMaterial(const JsonRef& m, const std::string& name, const std::string& type,
                       Scene& scene) {
    Material mat;
    mat.name = name;
    mat.color = Vec3(1.0f);
    if (type == "diffuse") {
        m.expectObject({"type", "color", "displacement", "normal_map"}, "a diffuse material");
        mat.type = MaterialType::Diffuse;
        mat.color = Vec3(0.5f);
    } else if (type == "mirror") {
        m.expectObject({"type", "color", "displacement", "normal_map"}, "a mirror material");
        mat.type = MaterialType::Mirror;
    } else if (type == "dielectric") {
        m.expectObject({"type", "color", "ior", "roughness", "u_roughness", "v_roughness",
                        "remap_roughness", "displacement", "normal_map"},
                       "a dielectric material");
        mat.type = MaterialType::Dielectric;
        parseDielectricIor(m, mat);
        parseRoughness(m, mat);
    } else if (type == "glossy") {
        m.expectObject({"type", "color", "roughness", "displacement", "normal_map"},
                       "a glossy material");
        mat.type = MaterialType::Glossy;
        if (m.has("roughness")) mat.roughness = m["roughness"].numberIn(0, 1);
    } else if (type == "conductor") {
        m.expectObject({"type", "metal", "eta", "k", "reflectance", "roughness", "u_roughness",
                        "v_roughness", "remap_roughness", "displacement", "normal_map"},
                       "a conductor material");
        mat.type = MaterialType::Conductor;
        parseConductorIndex(m, mat);
        parseRoughness(m, mat);
    } else if (type == "coateddiffuse") {
        parseCoatedDiffuse(m, mat);
    } else if (type == "coatedconductor") {
        parseCoatedConductor(m, mat);
    } else if (type == "thindielectric") {
        m.expectObject({"type", "ior", "displacement", "normal_map"}, "a thindielectric material");
        mat.type = MaterialType::ThinDielectric;
        parseDielectricIor(m, mat);
    } else if (type == "diffusetransmission") {
        m.expectObject({"type", "color", "transmittance", "scale", "displacement", "normal_map"},
                       "a diffusetransmission material");
        mat.type = MaterialType::DiffuseTransmission;
        mat.color = Vec3(0.25f);
        if (m.has("transmittance")) mat.transmittance = colorParam(m["transmittance"], scene, true);
        if (m.has("scale")) mat.scale = m["scale"].numberIn(0, 1e6f);
    } else {
        m.expectObject({"type", "materials", "amount"}, "a mix material");
        mat.type = MaterialType::Mix;
        if (m.has("amount")) mat.amount.value = m["amount"].numberIn(0, 1);
    }
    if (m.has("color")) {
        ColorParam c = colorParam(m["color"], scene, true);
        mat.color = c.textured() ? Vec3(0.5f) : c.value;
        mat.colorTexture = c.texture;
    }
    // Bump and normal mapping (engine/material_bsdf.h, resolveShading): texture names.
    if (m.has("displacement")) mat.displacement = textureNamed(m["displacement"], scene);
    if (m.has("normal_map")) mat.normalMap = textureNamed(m["normal_map"], scene);
    return mat;
}

// A mix names two materials of this block (from index `first` on), in any order; it must not
// contain itself. `mixes`: each mix's index and JSON.
void resolveMixes(const std::vector<std::pair<std::size_t, JsonRef>>& mixes, std::size_t first,
                  Scene& scene) {
    for (auto& [index, m] : mixes) {
        JsonRef names = m["materials"];
        if (!names.isArray() || names.arraySize() != 2)
            names.fail("expected an array of two material names");
        for (std::size_t k = 0; k < 2; ++k) {
            std::string ref = names[k].nonEmptyString();
            int found = scene.findMaterial(ref);
            if (found < int(first)) names[k].fail("unknown material \"" + ref + "\"");
            scene.materials[index].mix[k] = found;
        }
    }
    for (auto& [index, m] : mixes)
        if (mixContainsItself(scene.materials, int(index)))
            m["materials"].fail("the mix contains itself");
}

} // namespace

void parseMaterials(const JsonRef& v, Scene& scene) {
    if (!v.isObject()) v.fail("expected an object mapping material names to materials");
    static const std::vector<std::string> kTypes = {
        "diffuse", "mirror", "dielectric", "glossy", "conductor", "coateddiffuse",
        "coatedconductor", "thindielectric", "diffusetransmission", "mix"};
    const std::size_t first = scene.materials.size();
    std::vector<std::pair<std::size_t, JsonRef>> mixes;
    for (const std::string& name : v.keys()) {
        JsonRef m = v[name];
        if (name.empty()) m.fail("material name must not be empty");
        if (name.rfind("__", 0) == 0)
            m.fail("material names starting with \"__\" are reserved for the loader");
        std::string type = parseType(m, "material", kTypes);
        Material mat = parseMaterial(m, name, type, scene);
        if (mat.type == MaterialType::Mix) mixes.push_back({scene.materials.size(), m});
        scene.materials.push_back(mat);
    }
    resolveMixes(mixes, first, scene);
}

// "image": a file relative to the scene file, read as linear RGB; "mapping" says how it covers
// the sphere ("equal-area" needs a square image). Errors name the JSON path.
void parseLightImage(const JsonRef& l, Light& light, bool allowLatLong) {
    JsonRef file = l["image"];
    std::filesystem::path p(file.nonEmptyString());
    if (p.is_relative()) p = std::filesystem::path(l.file()).parent_path() / p;
    try {
        light.image = std::make_shared<const Image>(readImage(p.string()));
        light.imageFile = p.string();
    } catch (const ImageIoError& e) {
        file.fail(e.what());
    }
    light.mapping = EnvironmentMapping::EqualArea;
    if (allowLatLong && l.has("mapping")) {
        std::string m = l["mapping"].string();
        if (m == "lat-long") light.mapping = EnvironmentMapping::LatLong;
        else if (m != "equal-area") l["mapping"].fail("expected \"equal-area\" or \"lat-long\"");
    }
    if (light.image->width <= 0 || light.image->height <= 0) file.fail("the image is empty");
    if (light.mapping == EnvironmentMapping::EqualArea && light.image->width != light.image->height)
        file.fail("an equal-area image must be square, this one is " +
                  std::to_string(light.image->width) + " x " + std::to_string(light.image->height) +
                  (allowLatLong ? " (\"mapping\": \"lat-long\" reads latitude-longitude maps)" : ""));
}

// "transform": the light's frame (light space -> world; its translation is ignored).
Affine parseLightFrame(const JsonRef& l) {
    if (!l.has("transform")) return Affine::identity();
    Affine a = parseTransform(l["transform"]);
    a.m[0][3] = a.m[1][3] = a.m[2][3] = 0;
    return a;
}

// A light's colour: [r, g, b] (>= 0), or {"blackbody": kelvin, "scale": s}: Planck's law at
// luminance 1 as pbrt-v4 normalises a blackbody light, times s (default 1). The blackbody keeps
// its spectrum for the spectral mode (`spectrum`, scene/emission_spectrum.h); RGB mode takes its
// colour, the importer's blackbodyRgb.
namespace {
Vec3 lightColor(const JsonRef& v, EmissionSpectrumRef& spectrum) {
    spectrum = nullptr;
    if (!v.isObject()) return v.color();
    v.expectObject({"blackbody", "scale"}, "a blackbody colour");
    const float kelvin = v["blackbody"].positive();
    const float scale = v.has("scale") ? nonNegative(v["scale"]) : 1.0f;
    spectrum = pbrt::blackbodyEmission(kelvin);
    if (!spectrum) v["blackbody"].fail("a blackbody this cold has no visible light");
    return spectrum->rgb * scale;
}
} // namespace

void parseLights(const JsonRef& v, Scene& scene) {
    if (!v.isArray()) v.fail("expected an array of lights");
    static const std::vector<std::string> kTypes = {"point", "spot", "directional",
                                                      "environment", "goniometric"};
    bool haveEnvironment = false;
    for (std::size_t i = 0; i < v.arraySize(); ++i) {
        JsonRef l = v[i];
        std::string type = parseType(l, "light", kTypes);
        Light light;
        if (type == "point") {
            l.expectObject({"type", "name", "position", "intensity"}, "a point light");
            light.type = LightType::Point;
            light.position = l["position"].vec3();
            light.intensity = lightColor(l["intensity"], light.spectrum);
        } else if (type == "spot") {
            l.expectObject({"type", "name", "position", "direction", "intensity", "cone_angle",
                            "falloff_angle"},
                           "a spot light");
            light.type = LightType::Spot;
            light.position = l["position"].vec3();
            light.direction = l["direction"].direction();
            light.intensity = lightColor(l["intensity"], light.spectrum);
            if (l.has("cone_angle")) light.coneAngle = l["cone_angle"].positive();
            if (l.has("falloff_angle")) light.falloffAngle = nonNegative(l["falloff_angle"]);
            if (light.coneAngle + light.falloffAngle > 180) {
                l.child(l.has("falloff_angle") ? "falloff_angle" : "cone_angle")
                    .fail("cone_angle + falloff_angle must not exceed 180 degrees");
            }
        } else if (type == "directional") {
            l.expectObject({"type", "name", "direction", "irradiance"}, "a directional light");
            light.type = LightType::Directional;
            light.direction = l["direction"].direction();
            light.intensity = lightColor(l["irradiance"], light.spectrum);
        } else if (type == "goniometric") {
            l.expectObject({"type", "name", "position", "intensity", "image", "transform"},
                           "a goniometric light");
            light.type = LightType::Goniometric;
            light.position = l["position"].vec3();
            light.intensity = lightColor(l["intensity"], light.spectrum);
            parseLightImage(l, light, false);
            light.toWorld = parseLightFrame(l);
        } else {
            l.expectObject({"type", "name", "radiance", "image", "mapping", "transform", "scale"},
                           "an environment light");
            if (haveEnvironment) l.fail("a scene may have only one environment light");
            haveEnvironment = true;
            light.type = LightType::Environment;
            if (!l.has("image") || l.has("radiance"))
                light.intensity = lightColor(l["radiance"], light.spectrum);
            if (l.has("image")) parseLightImage(l, light, true);
            else if (l.has("mapping")) l["mapping"].fail("\"mapping\" needs an \"image\"");
            if (l.has("scale")) light.intensity = light.intensity * nonNegative(l["scale"]);
            light.toWorld = parseLightFrame(l);
        }
        if (l.has("name")) light.name = l["name"].string();
        scene.lights.push_back(light);
    }
}

} // namespace rayproc::scene_json
