// A floor lit only through a rough silver ceiling that reflects a lamp facing up: every path
// to the floor's light is L G D (none in the caustic map or the floor's light samples), so a
// gi render must read the global map's glossy radiance estimate to match path mode. Used by
// the RGB and the spectral gi tests.
#pragma once

#include "test_util.h"

namespace rayproc::test {

inline std::unique_ptr<Scene> glossyCeilingScene() {
    return sceneFromJson(R"({
      "camera": {"position": [0, 1.2, 6], "look_at": [0, 0, 0], "fov": 50, "resolution": [32, 32]},
      "materials": {
        "floor": {"type": "diffuse", "color": [0.7, 0.7, 0.7]},
        "metal": {"type": "conductor", "metal": "Ag", "roughness": 0.1, "remap_roughness": false}},
      "lights": [],
      "nodes": [
        {"type": "quad", "material": "floor", "corners": [[-4, 0, -4], [-4, 0, 4], [4, 0, 4], [4, 0, -4]]},
        {"type": "quad", "material": "metal", "corners": [[-4, 3, -4], [4, 3, -4], [4, 3, 4], [-4, 3, 4]]},
        {"type": "quad", "emission": [20, 20, 20],
         "corners": [[-0.5, 1, -0.5], [-0.5, 1, 0.5], [0.5, 1, 0.5], [0.5, 1, -0.5]]}]})");
}

} // namespace rayproc::test
