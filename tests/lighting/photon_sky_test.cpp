// Photons from an image sky: a diffuse sphere of radius R under the sky intercepts, from every
// direction, the radiance times its cross-section pi R^2, so the power stored at the photons'
// first hits is 4 pi <L> pi R^2 (<L> the sky's mean radiance), whatever the map looks like.
// A map whose power is mostly one bright pixel checks that photons are emitted by the sky's
// density with flux L / pdf (a uniform emission would leave that estimate very noisy).
#include "engine/intersect.h"
#include "engine/pipeline.h"
#include "gi/photon_emitter.h"
#include "gi/gi_pipeline.h"
#include "gi/photon_stage.h"
#include "image/image.h"

#include "../analytic/analytic.h"

#include <filesystem>
#include <unistd.h>

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("Image sky photons: a sphere stores 4 pi <L> pi R^2 at first hits", "[lights]") {
    const int res = 16;
    Image sky(res, res);
    for (float& v : sky.pixels) v = 0.05f;
    float* sun = sky.at(5, 9);
    sun[0] = 400.0f, sun[1] = 300.0f, sun[2] = 200.0f;
    auto dir = std::filesystem::temp_directory_path() /
               ("rayproc-lights-photons-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::string path = (dir / "sky.pfm").string();
    writeImage(path, sky);
    struct Cleanup {
        std::filesystem::path dir;
        ~Cleanup() {
            std::error_code ec;
            std::filesystem::remove_all(dir, ec);
        }
    } cleanup{dir};
    const float R = 1.5f;
    auto scene = sceneFromJson(
        R"({"camera": {"position": [0, 0, 8], "look_at": [0, 0, 0], "resolution": [8, 8]},
            "materials": {"m": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
            "lights": [{"type": "environment", "image": ")" + path + R"("}],
            "nodes": [{"type": "sphere", "material": "m", "radius": 1.5}]})");
    EmbreeScene accel(*scene);
    LightSet lights = LightSet::build(*scene, accel);
    Film film(1, 1);
    ShadingPolicy policy;
    RenderContext rc{*scene, accel, lights, policy, film, 7};
    Stats stats;
    PhotonStage stage(rc, /*causticPass=*/false, /*maxPhotonDepth=*/1);
    Pipeline pipeline("photons", "photon", accel.root(), 16, stats, 2);
    pipeline.stage("photon", {kPhotonQueue}, stage);
    PhotonEmitter emitter(lights, scene->worldBounds(), 200000, 7, 1);
    pipeline.run(emitter, [] { return false; });
    double stored[3] = {0, 0, 0};
    for (const PhotonRecord& p : stage.takePhotons())
        for (int c = 0; c < 3; ++c) stored[c] += p.power[c];
    Vec3 avg = lights.environment.average();
    for (int c = 0; c < 3; ++c) {
        double expected = 4 * kPi * avg[c] * kPi * R * R;
        INFO("channel " << c << " stored " << stored[c] << " expected " << expected);
        CHECK(stored[c] == Approx(expected).epsilon(0.02));
    }
}
