#include "scene/pbrt/pbrt_camera.h"

#include "scene/camera_check.h"
#include "scene/scene_loader.h"

#include <algorithm>
#include <cmath>

namespace rayproc::pbrt {

namespace {

constexpr double kPiD = 3.14159265358979323846;
constexpr long long kMaxResolution = kMaxImageSide; // scene_loader.h: one limit for all
constexpr long long kMaxPixels = kMaxImagePixels;

// The "rgb" film's sensor (pbrt-v4's PixelSensor::Create): "iso", "whitebalance" and "sensor";
// only the CIE 1931 observer is available (no measured camera curves on the build machine), so
// another sensor warns and renders with it, white balanced at 6500 K unless told otherwise as
// pbrt-v4 defaults that sensor.
void readSensor(const FilmDirective& film, Warnings& warnings, FilmSensor& sensor) {
    const SourceLoc& loc = film.loc;
    sensor.iso = film.params.getFloat("iso", 100.0);
    sensor.whiteBalance = film.params.getFloat("whitebalance", 0.0);
    const std::string name = film.params.getString("sensor", "cie1931");
    if (!(sensor.iso > 0) || !std::isfinite(sensor.iso))
        failAt(loc, "film \"iso\" must be positive");
    if (!(sensor.whiteBalance >= 0) || !std::isfinite(sensor.whiteBalance))
        failAt(loc, "film \"whitebalance\" must be a temperature in kelvin, or 0 for none");
    if (name != "cie1931") {
        if (sensor.whiteBalance == 0) sensor.whiteBalance = 6500;
        warnings.add(loc, "film sensor " + quote(name) +
                              ": no measured sensor curves are available; rendered with the "
                              "\"cie1931\" sensor, white balanced at " +
                              std::to_string(int(std::lround(sensor.whiteBalance))) + " K");
    }
}

// The exposure time, the camera's shutterclose - shutteropen (pbrt-v4's film reads it there).
void readExposure(const CameraDirective& cam, const SourceLoc& loc, FilmSensor& sensor) {
    double open = cam.params.getFloat("shutteropen", 0.0);
    double close = cam.params.getFloat("shutterclose", 1.0);
    sensor.exposureTime = close - open;
    if (!(sensor.exposureTime > 0) || !std::isfinite(sensor.exposureTime))
        failAt(loc, "the camera's shutter does not open (\"shutterclose\" " + std::to_string(close) +
                        " is not after \"shutteropen\" " + std::to_string(open) + ")");
}

void readFilm(const FilmDirective& film, Scene& scene) {
    const SourceLoc& loc = film.loc;
    long long w = film.params.getInt("xresolution", 1280);
    long long h = film.params.getInt("yresolution", 720);
    if (w < 1 || w > kMaxResolution || h < 1 || h > kMaxResolution)
        failAt(loc, "film resolution " + std::to_string(w) + "x" + std::to_string(h) +
                        " is outside 1..16384");
    if (w * h > kMaxPixels)
        failAt(loc, "film of " + std::to_string(w * h) + " pixels exceeds the limit of 2^26");
    film.params.ignore({"filename", "savefp16", "diagonal"}); // output and realistic-camera only
    scene.camera.width = int(w);
    scene.camera.height = int(h);
}

// tan of half the vertical field of view, from pbrt's fov, frame aspect and screen window.
double tanHalfVertical(const CameraDirective& cam, const Scene& scene, Warnings& warnings,
                       const SourceLoc& loc) {
    const ParamList& p = cam.params;
    double fov = cam.type == "perspective" ? p.getFloat("fov", 90.0) : 90.0;
    if (!(fov > 0 && fov < 180)) failAt(loc, "camera \"fov\" must be strictly between 0 and 180");
    double aspect = double(scene.camera.width) / double(scene.camera.height);
    double frame = p.getFloat("frameaspectratio", aspect);
    if (!(frame > 0)) failAt(loc, "camera \"frameaspectratio\" must be positive");
    double x0 = -1, x1 = 1, y0 = -1, y1 = 1;
    if (frame > 1) {
        x0 = -frame;
        x1 = frame;
    } else {
        y0 = -1 / frame;
        y1 = 1 / frame;
    }
    if (const Param* sw = p.get("screenwindow", {"float"})) {
        if (sw->numbers.size() != 4)
            failAt(sw->loc, "\"screenwindow\" expects 4 numbers: xmin xmax ymin ymax");
        x0 = sw->numbers[0];
        x1 = sw->numbers[1];
        y0 = sw->numbers[2];
        y1 = sw->numbers[3];
        if (!(x1 > x0 && y1 > y0)) failAt(sw->loc, "\"screenwindow\" is empty");
    }
    if (std::fabs(x0 + x1) > 1e-6 * (x1 - x0) || std::fabs(y0 + y1) > 1e-6 * (y1 - y0))
        warnings.add(loc, "an off-centre screen window is not supported; it is centred");
    double windowAspect = (x1 - x0) / (y1 - y0);
    if (std::fabs(windowAspect / aspect - 1) > 1e-3)
        warnings.add(loc, "the screen window's aspect differs from the film's (non-square "
                          "pixels); the vertical field of view is kept");
    return std::tan(0.5 * fov * kPiD / 180.0) * 0.5 * (y1 - y0);
}

// The shared check's message under pbrt's names: lensradius, focaldistance, the transform.
std::string pbrtCameraProblem(const CameraProblem& p) {
    if (p.field == "aperture") return "camera \"lensradius\": " + p.message;
    if (p.field == "focus_distance") return "camera \"focaldistance\": " + p.message;
    if (p.field == "fov") return "camera \"fov\": " + p.message;
    return "the camera transform (LookAt, Transform, ...): " + p.message;
}

} // namespace

Mat4 convertCamera(const CameraDirective& cam, const FilmDirective& film, Scene& scene,
                   Warnings& warnings, const SourceLoc& worldBegin) {
    const SourceLoc& loc = cam.given ? cam.loc : worldBegin;
    scene.camera.width = 1280; // pbrt's default film
    scene.camera.height = 720;
    if (film.given) readFilm(film, scene);
    if (film.given) readSensor(film, warnings, scene.sensor);

    if (cam.type != "perspective")
        warnings.add(loc, "Camera " + quote(cam.type) +
                              " is not supported; using a perspective camera with a 90 degree "
                              "field of view");
    double tanHalfY = tanHalfVertical(cam, scene, warnings, loc);

    Mat4 worldFromCamera;
    if (!cam.cameraFromWorld.isAffine() || !cam.cameraFromWorld.inverse(worldFromCamera))
        failAt(loc, "the camera transform is singular or projective");
    Vec3d eye = worldFromCamera.point({0, 0, 0});
    Vec3d right = worldFromCamera.vector({1, 0, 0});
    Vec3d up = worldFromCamera.vector({0, 1, 0});
    Vec3d forward = worldFromCamera.vector({0, 0, 1});
    double lr = length(right), lu = length(up), lf = length(forward);
    double tol = 1e-4 * lf;
    if (std::fabs(lr - lf) > tol || std::fabs(lu - lf) > tol ||
        std::fabs(dot(right, up)) > tol * lf || std::fabs(dot(right, forward)) > tol * lf ||
        std::fabs(dot(up, forward)) > tol * lf)
        warnings.add(loc, "a camera transform with shear or non-uniform scale is not supported; "
                          "only its directions are used");

    Camera& c = scene.camera;
    c.position = eye.toFloat();
    // A look_at one unit ahead rounds onto the eye in float beyond ~1e7: it is set far enough
    // ahead that float keeps the direction.
    double ahead = std::max({1.0, std::fabs(eye.x), std::fabs(eye.y), std::fabs(eye.z)});
    c.lookAt = (eye + normalize(forward) * ahead).toFloat();
    c.up = normalize(up).toFloat();
    c.fovY = float(2.0 * std::atan(tanHalfY) * 180.0 / kPiD);
    double lens = cam.params.getFloat("lensradius", 0.0);
    double focus = cam.params.getFloat("focaldistance", 1e6);
    if (lens < 0) failAt(loc, "camera \"lensradius\" must not be negative");
    if (lens > 0 && !(focus > 0)) failAt(loc, "camera \"focaldistance\" must be positive");
    c.apertureRadius = float(lens);
    c.focusDistance = lens > 0 ? float(focus) : 0.0f;
    // The limits a JSON scene and serve's camera message meet (scene/camera_check.h).
    if (auto problem = cameraProblem(c)) failAt(loc, pbrtCameraProblem(*problem));
    readExposure(cam, loc, scene.sensor); // no motion blur: nothing moves
    if (cam.type != "perspective") // the camera itself was reported, not its parameters
        for (const Param& p : cam.params.all()) p.used = true;

    // pbrt shows x to the right; rayproc shows cross(forward, up). If they disagree, mirror the
    // world about the plane through the eye that holds forward and up.
    Vec3d rayprocRight = cross(forward, up);
    if (dot(rayprocRight, right) >= 0) return Mat4();
    return Mat4::mirror(eye, normalize(cross(up, forward)));
}

PixelFilter convertFilter(const FilterDirective& d, Warnings& warnings) {
    PixelFilter f;
    f.type = PixelFilter::Type::Gaussian;
    f.radius = {1.5f, 1.5f};
    f.sigma = 0.5f;
    if (!d.given) return f;
    const ParamList& p = d.params;
    // pbrt-v4's default radius of each filter.
    double r = 0.5;
    if (d.type == "box") {
        f.type = PixelFilter::Type::Box;
    } else if (d.type == "triangle") {
        f.type = PixelFilter::Type::Triangle;
        r = 2.0;
    } else if (d.type == "gaussian") {
        r = 1.5;
        f.sigma = float(p.getFloat("sigma", 0.5));
        if (!(f.sigma > 0)) failAt(d.loc, "PixelFilter \"gaussian\": \"sigma\" must be positive");
    } else if (d.type == "mitchell") {
        f.type = PixelFilter::Type::Mitchell;
        r = 2.0;
        f.b = float(p.getFloat("B", 1.0 / 3.0));
        f.c = float(p.getFloat("C", 1.0 / 3.0));
    } else if (d.type == "sinc") {
        f.type = PixelFilter::Type::Lanczos;
        f.tau = float(p.getFloat("tau", 3.0));
        if (!(f.tau > 0)) failAt(d.loc, "PixelFilter \"sinc\": \"tau\" must be positive");
    } else {
        warnings.add(d.loc, "PixelFilter \"" + d.type +
                                "\" is not supported; using pbrt-v4's default gaussian");
        for (const Param& q : p.all()) q.used = true;
        return f;
    }
    double rx = p.getFloat("xradius", r), ry = p.getFloat("yradius", r);
    if (!(rx > 0) || !(ry > 0) || rx > 16 || ry > 16)
        failAt(d.loc, "PixelFilter \"" + d.type + "\": radii " + std::to_string(rx) + ", " +
                          std::to_string(ry) + " must be in (0, 16] pixels");
    f.radius = {float(rx), float(ry)};
    if (f.type == PixelFilter::Type::Mitchell || f.type == PixelFilter::Type::Lanczos)
        warnings.add(d.loc, "PixelFilter \"" + d.type +
                                "\": negative lobes are not supported; its positive part is used");
    return f;
}

} // namespace rayproc::pbrt
