#include "scene/pbrt/pbrt_lights.h"

#include <algorithm>
#include <cmath>

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

} // namespace

void convertLight(const std::string& type, const ParamList& params, const Mat4& toWorld,
                  const ValueReader& values, Warnings& warnings, const SourceLoc& loc,
                  Scene& scene) {
    Light l;
    if (type == "point") {
        l.type = LightType::Point;
        Vec3 I = values.color(params, "I", SpectrumUse::Illuminant, Vec3(1.0f));
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
        Vec3 I = values.color(params, "I", SpectrumUse::Illuminant, Vec3(1.0f));
        l.intensity = I * float(intensityScale(params, kE));
        l.position = toWorld.point(Vec3d(from)).toFloat();
        l.direction = direction(toWorld, from, to, loc).toFloat();
        l.coneAngle = float(std::max(cone - delta, 1e-3));
        l.falloffAngle = float(cone - l.coneAngle);
    } else if (type == "distant") {
        l.type = LightType::Directional;
        Vec3 from = params.getPoint3("from", {0, 0, 0}), to = params.getPoint3("to", {0, 0, 1});
        Vec3 L = values.color(params, "L", SpectrumUse::Illuminant, Vec3(1.0f));
        l.intensity = L * float(params.getFloat("scale", 1.0));
        l.direction = direction(toWorld, from, to, loc).toFloat(); // where the light travels
    } else if (type == "infinite") {
        l.type = LightType::Environment;
        Vec3 L = values.color(params, "L", SpectrumUse::Illuminant, Vec3(1.0f));
        if (params.get("filename", {"string"})) {
            warnings.add(loc, "image-based infinite lights are not supported; using a uniform "
                              "grey sky of radiance 1 (times scale)");
            L = Vec3(1.0f);
        }
        double scale = params.getFloat("scale", 1.0);
        double illuminance = params.getFloat("illuminance", -1.0);
        if (illuminance > 0) scale *= illuminance / kPiD; // a uniform sky gives E = pi L
        l.intensity = L * float(scale);
        for (Light& other : scene.lights) {
            if (other.type == LightType::Environment) { // rayproc has one sky: add them up
                other.intensity += l.intensity;
                return;
            }
        }
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
    Vec3 L = values.color(params, "L", SpectrumUse::Illuminant, Vec3(1.0f));
    if (params.get("filename", {"string"}))
        warnings.add(loc, "image-textured area lights are not supported; \"L\" is used");
    e.radiance = L * float(params.getFloat("scale", 1.0));
    e.twoSided = params.getBool("twosided", false);
    if (!isFinite(e.radiance) || e.radiance.x < 0 || e.radiance.y < 0 || e.radiance.z < 0)
        failAt(loc, "area light radiance must be finite and not negative (check \"scale\")");
    return e;
}

} // namespace rayproc::pbrt
