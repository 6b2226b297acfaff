// The global map's rounds (PhotonPassSpec::maxRounds, GiSettings::photonRounds): rounds of
// `count` photons repeat until enough photons of the gather's map have landed in view, each
// round from its own random stream, and the powers are divided by the rounds traced, so the
// map carries the lights' power once whatever the count.
#include "../analytic/analytic.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A diffuse box open at the top under a directional light: the first landings are the sun's.
std::unique_ptr<Scene> openBox() {
    return sceneFromJson(R"({
        "camera": {"position": [0, 1, 3], "look_at": [0, 0.5, 0], "resolution": [16, 16]},
        "materials": {"m": {"type": "diffuse", "color": [0.6, 0.6, 0.6]}},
        "lights": [{"type": "directional", "direction": [0.2, -1, 0.1],
                    "irradiance": [3, 3, 3]}],
        "nodes": [
          {"type": "quad", "material": "m", "corners": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
          {"type": "quad", "material": "m", "corners": [[-1,0,-1],[-1,1,-1],[1,1,-1],[1,0,-1]]},
          {"type": "quad", "material": "m", "corners": [[-1,0,-1],[-1,0,1],[-1,1,1],[-1,1,-1]]},
          {"type": "quad", "material": "m", "corners": [[1,0,-1],[1,1,-1],[1,1,1],[1,0,1]]}]})");
}

struct Built {
    int rounds = 0;
    std::size_t photons = 0, scattered = 0;
    Vec3 power{0, 0, 0};
};

Built build(const Scene& scene, const EmbreeScene& accel, int maxRounds, std::size_t target) {
    PhotonMap all, scattered;
    Built b;
    PhotonPassSpec pass{false, 20000, 1, "photons", maxRounds, target};
    b.rounds = traceGlobalMap(scene, accel, pass, all, &scattered).rounds;
    b.photons = all.size();
    b.scattered = scattered.size();
    double sum[3] = {0, 0, 0};
    for (std::uint32_t i = 0; i < all.size(); ++i)
        for (int c = 0; c < 3; ++c) sum[c] += all.photon(i).power[c];
    b.power = Vec3(float(sum[0]), float(sum[1]), float(sum[2]));
    return b;
}

} // namespace

TEST_CASE("Photon rounds: more rounds until enough photons land, the same power in all",
          "[gi][photon-rounds]") {
    auto scene = openBox();
    EmbreeScene accel(*scene);
    Built one = build(*scene, accel, 1, 1000000000);
    Built enough = build(*scene, accel, 8, 1); // the first round already has one photon
    Built four = build(*scene, accel, 4, 1000000000);
    Built upTo = build(*scene, accel, 8, one.scattered * 5 / 2);
    CHECK(one.rounds == 1);
    CHECK(enough.rounds == 1);
    CHECK(enough.photons == one.photons); // the first round is the single pass, photon for photon
    CHECK(four.rounds == 4);
    // Rounds land about the same number (within a few percent): the third passes 2.5 times
    // the first's.
    CHECK(upTo.rounds == 3);
    INFO("one round: " << one.photons << " photons, power " << one.power[0] << "; four: "
                       << four.photons << ", power " << four.power[0]);
    CHECK(double(four.photons) == Approx(4.0 * double(one.photons)).epsilon(0.05));
    for (int c = 0; c < 3; ++c) CHECK(four.power[c] == Approx(one.power[c]).epsilon(0.02));
}
