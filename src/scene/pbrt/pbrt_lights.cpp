#include "scene/pbrt/pbrt_lights.h"

#include "image/image.h"
#include "lighting/environment.h"
#include "lighting/sphere_mapping.h"
#include "scene/pbrt/pbrt_shapes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace rayproc::pbrt {

namespace {

constexpr double kPiD = 3.14159265358979323846;

double radians(double degrees) {
    return degrees * kPiD / 180.0;
}

// "scale", and "power" divided by the light's k_e (its power per unit intensity).
double intensityScale(const ParamList& params, double kE) {
    double scale = params.getFloat("scale", 1.0);
    double power = params.getFloat("power", -1.0);
    if (power > 0) scale *= power / kE;
    return scale;
}

Vec3d direction(const Mat4& toWorld, const Vec3& from, const Vec3& to, const SourceLoc& loc) {
    Vec3d d = toWorld.vector(Vec3d(to - from));
    if (!(length(d) > 0)) failAt(loc, "\"from\" and \"to\" must differ");
    return normalize(d);
}

// The image a light's "string filename" names, relative to the directory of the file that
// names it (pbrt-v4 resolves against the scene's directory; the two agree unless an Include'd
// file in another directory names an image). Read failures are input errors at `loc`. Sets
// l.image and l.imageFile; leaves them empty without "filename".
void readLightImage(const ParamList& params, const SourceLoc& loc, Light& l) {
    std::string name = params.getString("filename", "");
    if (name.empty()) return;
    std::filesystem::path dir =
        loc.file ? std::filesystem::path(*loc.file).parent_path() : std::filesystem::path();
    const std::string path = resolvePath(name, dir, dir).string();
    try {
        auto img = std::make_shared<Image>(readImage(path));
        if (img->width <= 0 || img->height <= 0) failAt(loc, quote(name) + ": the image is empty");
        l.image = std::move(img);
        l.imageFile = path;
    } catch (const ImageIoError& e) {
        failAt(loc, e.what());
    }
}

// Mean over the pixels of the channel mean (pbrt-v4 reduces a goniometric image to one
// channel this way).
double imageChannelMean(const Image& img) {
    double sum = 0;
    for (float v : img.pixels) sum += std::max(0.0f, v);
    return sum / double(img.pixels.size());
}

// The true upper-hemisphere (+z) illuminance of a lat-long image of radiance: each pixel
// covers 2 pi^2 sin(theta) / N steradians.
double latLongIlluminance(const Image& img) {
    double sum = 0;
    for (int y = 0; y < img.height; ++y) {
        double theta = kPiD * (y + 0.5) / img.height;
        if (std::cos(theta) <= 0) continue;
        for (int x = 0; x < img.width; ++x) {
            const float* p = img.at(x, y);
            sum += luminance({p[0], p[1], p[2]}) * std::cos(theta) * std::sin(theta);
        }
    }
    return sum * 2 * kPiD * kPiD / (double(img.width) * img.height);
}

void convertInfinite(const ParamList& params, const Mat4& toWorld, const ValueReader& values,
                     Warnings& warnings, const SourceLoc& loc, Light& l) {
    l.type = LightType::Environment;
    l.toWorld = toWorld.toAffine();
    if (params.has("portal")) {
        warnings.add(loc, "infinite light \"portal\" is not supported; ignored (the sky is "
                          "sampled without it)");
        params.ignore({"portal"});
    }
    bool hasL = params.has("L");
    EmissionSpectrumRef spectrum;
    Vec3 L = values.emission(params, "L", Vec3(1.0f), spectrum);
    double scale = params.getFloat("scale", 1.0);
    double illuminance = params.getFloat("illuminance", -1.0);
    readLightImage(params, loc, l);
    if (!l.image) {
        if (illuminance > 0) scale *= illuminance / kPiD; // a uniform sky gives E = pi L
        l.intensity = L * float(scale);
        l.spectrum = spectrum;
        return;
    }
    if (hasL) failAt(loc, "an infinite light takes \"L\" or \"filename\", not both");
    const Image& img = *l.image;
    if (img.width == img.height) {
        l.mapping = EnvironmentMapping::EqualArea;
        if (illuminance > 0) scale *= equalAreaIlluminanceScale(img, 1.0f) * illuminance;
    } else {
        // pbrt-v4 rejects non-square maps; pbrt-v3 scenes use lat-long ones, so we read them so.
        warnings.add(loc, "\"" + params.getString("filename", "") + "\" is not square (" +
                              std::to_string(img.width) + " x " + std::to_string(img.height) +
                              "), so not an equal-area map: read as lat-long (+z up)");
        l.mapping = EnvironmentMapping::LatLong;
        double e = latLongIlluminance(img);
        if (illuminance > 0 && e > 0) scale *= illuminance / e;
    }
    l.intensity = Vec3(float(scale));
}

// pbrt-v4's goniometric light: a point light at the light-space origin whose intensity is I
// times the (single-channel) image at the equal-area point of the emitted direction, where
// the image's +z is the light's +y (pbrt-v4 swaps y and z to make it so).
void convertGoniometric(const ParamList& params, const Mat4& toWorld, const ValueReader& values,
                        Warnings& warnings, const SourceLoc& loc, Light& l) {
    l.type = LightType::Goniometric;
    Vec3 I = values.emission(params, "I", Vec3(1.0f), l.spectrum);
    readLightImage(params, loc, l);
    double scale = params.getFloat("scale", 1.0), power = params.getFloat("power", -1.0);
    double mean = 1;
    if (!l.image) {
        warnings.add(loc, "goniometric light without \"filename\": emits as a point light");
    } else {
        if (l.image->width != l.image->height)
            failAt(loc, "the goniometric image is " + std::to_string(l.image->width) + " x " +
                            std::to_string(l.image->height) +
                            ": it must be square (an equal-area map)");
        mean = imageChannelMean(*l.image);
    }
    if (power > 0) {
        if (!(mean > 0)) failAt(loc, "\"power\" given for a goniometric light whose image is black");
        scale *= power / (4 * kPiD * mean);
    }
    l.intensity = I * float(scale);
    Mat4 swapYZ;
    swapYZ.m[1][1] = swapYZ.m[2][2] = 0;
    swapYZ.m[1][2] = swapYZ.m[2][1] = 1;
    Mat4 frame = toWorld * swapYZ;
    l.position = frame.point({0, 0, 0}).toFloat();
    frame.m[0][3] = frame.m[1][3] = frame.m[2][3] = 0; // directions only
    l.toWorld = frame.toAffine();
}

} // namespace

void convertLight(const std::string& type, const ParamList& params, const Mat4& toWorld,
                  const ValueReader& values, Warnings& warnings, const SourceLoc& loc,
                  Scene& scene) {
    Light l;
    if (type == "point") {
        l.type = LightType::Point;
        Vec3 I = values.emission(params, "I", Vec3(1.0f), l.spectrum);
        l.intensity = I * float(intensityScale(params, 4 * kPiD));
        l.position = toWorld.point(Vec3d(params.getPoint3("from", {0, 0, 0}))).toFloat();
    } else if (type == "spot") {
        l.type = LightType::Spot;
        Vec3 from = params.getPoint3("from", {0, 0, 0}), to = params.getPoint3("to", {0, 0, 1});
        double cone = params.getFloat("coneangle", 30.0);
        double delta = params.getFloat("conedeltaangle", 5.0);
        if (!(cone > 0 && cone <= 180)) failAt(loc, "spot \"coneangle\" must be in (0, 180]");
        if (delta < 0) failAt(loc, "spot \"conedeltaangle\" must not be negative");
        delta = std::min(delta, cone);
        // pbrt: full intensity inside coneangle - conedeltaangle, smooth falloff to coneangle.
        double cosStart = std::cos(radians(cone - delta)), cosEnd = std::cos(radians(cone));
        double kE = 2 * kPiD * ((1 - cosStart) + (cosStart - cosEnd) / 2);
        Vec3 I = values.emission(params, "I", Vec3(1.0f), l.spectrum);
        l.intensity = I * float(intensityScale(params, kE));
        l.position = toWorld.point(Vec3d(from)).toFloat();
        l.direction = direction(toWorld, from, to, loc).toFloat();
        l.coneAngle = float(std::max(cone - delta, 1e-3));
        l.falloffAngle = float(cone - l.coneAngle);
    } else if (type == "distant") {
        l.type = LightType::Directional;
        Vec3 from = params.getPoint3("from", {0, 0, 0}), to = params.getPoint3("to", {0, 0, 1});
        Vec3 L = values.emission(params, "L", Vec3(1.0f), l.spectrum);
        double scale = params.getFloat("scale", 1.0);
        double illuminance = params.getFloat("illuminance", -1.0);
        if (illuminance > 0) scale *= illuminance; // the irradiance of a spectrum of 1 nit
        l.intensity = L * float(scale);
        l.direction = direction(toWorld, from, to, loc).toFloat(); // where the light travels
    } else if (type == "infinite") {
        convertInfinite(params, toWorld, values, warnings, loc, l);
        for (Light& other : scene.lights) {
            if (!l.image && other.type == LightType::Environment && !other.image) {
                // Constant skies add up into one, and so do their spectra.
                other.spectrum = sumOfEmissions(other.intensity, other.spectrum, l.intensity,
                                                l.spectrum);
                other.intensity += l.intensity;
                return;
            }
        }
    } else if (type == "goniometric") {
        convertGoniometric(params, toWorld, values, warnings, loc, l);
    } else {
        warnings.add(loc, "LightSource \"" + type + "\" is not supported; skipped");
        for (const Param& p : params.all()) p.used = true;
        return;
    }
    if (!isFinite(l.intensity) || l.intensity.x < 0 || l.intensity.y < 0 || l.intensity.z < 0)
        failAt(loc, "light intensity must be finite and not negative (check \"scale\")");
    scene.lights.push_back(l);
}

std::optional<AreaEmission> convertAreaLight(const std::string& type, const ParamList& params,
                                             const ValueReader& values, Warnings& warnings,
                                             const SourceLoc& loc) {
    if (type != "diffuse") {
        warnings.add(loc, "AreaLightSource " + quote(type) +
                              " is not supported; the shapes do not emit");
        for (const Param& p : params.all()) p.used = true;
        return std::nullopt;
    }
    AreaEmission e;
    Vec3 L = values.emission(params, "L", Vec3(1.0f), e.spectrum);
    if (params.get("filename", {"string"}))
        warnings.add(loc, "image-textured area lights are not supported; \"L\" is used");
    e.radiance = L * float(params.getFloat("scale", 1.0));
    e.twoSided = params.getBool("twosided", false);
    e.power = params.getFloat("power", -1.0);
    // The shapes' area is known only where they are placed: SceneBuilder::shape applies it.
    if (!isFinite(e.radiance) || e.radiance.x < 0 || e.radiance.y < 0 || e.radiance.z < 0)
        failAt(loc, "area light radiance must be finite and not negative (check \"scale\")");
    return e;
}

Vec3 areaRadianceForPower(const AreaEmission& e, double area) {
    if (!(e.power > 0)) return e.radiance;
    // A Lambertian emitter of radiance L and area A emits pi A L per side.
    double kE = kPiD * area * (e.twoSided ? 2 : 1);
    if (!(kE > 0) || !std::isfinite(kE)) return Vec3(0.0f);
    return e.radiance * float(e.power / kE);
}

double shapesArea(const std::vector<Shape>& shapes, const Affine& toWorld) {
    double area = 0;
    for (const Shape& s : shapes) {
        switch (s.type) {
        case ShapeType::Mesh: {
            const TriangleMesh& m = *s.mesh;
            for (std::size_t t = 0; t < m.triangleCount(); ++t) {
                Vec3 a = toWorld.point(m.positions[m.indices[3 * t]]);
                Vec3 b = toWorld.point(m.positions[m.indices[3 * t + 1]]);
                Vec3 c = toWorld.point(m.positions[m.indices[3 * t + 2]]);
                area += double(triangleArea(a, b, c));
            }
            break;
        }
        case ShapeType::Sphere:
        case ShapeType::Disk: {
            // Uniform scale assumed, as LightSet does: radius times the cube root of |det|.
            double k = std::cbrt(std::abs(double(toWorld.determinant())));
            double r = double(s.radius) * k;
            area += (s.type == ShapeType::Sphere ? 4 : 1) * kPiD * r * r;
            break;
        }
        }
    }
    return area;
}

} // namespace rayproc::pbrt
